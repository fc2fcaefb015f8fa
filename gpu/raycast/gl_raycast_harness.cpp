#include "gpu/raycast/gl_raycast_harness.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "gpu/gl/gl_harness_pass.h"
#include "gpu/raycast/gl_raycast.h"

namespace uvr::gpu {

namespace {

// The std430 layouts of shaders/raycast_harness.frag's structs: scalar arrays only, so that no vec3 rounds a member
// up to 16 bytes.
struct GlRayExact {
    double tex0[3], dtex[3], tex_exit[3], last_length, length, entry[3], dir[3];
    int32_t samples, pad;
};
static_assert(sizeof(GlRayExact) == 144, "GlRayExact must match HarnessRayExact in shaders/raycast_harness.frag");

struct GlRay {
    double length, entry[3], dir[3];
    float tex0[3], dtex[3], tex_exit[3], last_length;
    int32_t samples;
    float pad;
};
static_assert(sizeof(GlRay) == 104 && offsetof(GlRay, tex0) == 56,
              "GlRay must match HarnessRay in shaders/raycast_harness.frag");

struct GlMarchResult {
    float colour[4], samples, pad[3];
};
static_assert(sizeof(GlMarchResult) == 32, "GlMarchResult must match HarnessMarchResult in shaders/raycast_harness.frag");

struct GlLightCase {
    double entry[3], dir[3], t;
    float g[3], pad;
};
static_assert(sizeof(GlLightCase) == 72, "GlLightCase must match HarnessLightCase in shaders/raycast_harness.frag");

template <typename V>
void put(const V& v, auto* out)
{
    for (int i = 0; i < 3; ++i) out[i] = v[i];
}
glm::dvec3 get(const double* v) { return {v[0], v[1], v[2]}; }

constexpr std::size_t kChunk = std::size_t(kHarnessWidth) * kHarnessRows;

// Runs `program` over `count` cases in chunks: `fill(base, m, pass)` makes the chunk's input buffers and returns the
// output buffer, `read(base, m, pass, buffer)` reads it back.
template <typename Fill, typename Read>
void run_chunks(GlContext& ctx, const GlProgram& prog, GLuint vao, std::size_t count, const char* what, Fill fill,
                Read read)
{
    const GlFunctions& gl = ctx.gl();
    gl.Uniform1i(prog.uniform("harness_width"), kHarnessWidth);
    gl.BindVertexArray(vao);
    gl.Disable(GL_BLEND);
    for (std::size_t base = 0; base < count; base += kChunk) {
        const std::size_t m = std::min(kChunk, count - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        gl.Uniform1i(prog.uniform("harness_count"), GLint(m));
        HarnessPass pass(gl);
        const GLuint results = fill(base, m, pass);
        pass.targets(ctx, {GL_RGBA32F}, w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        read(base, m, pass, results);
        ctx.check_error(what);
    }
    gl.BindVertexArray(0);
}

}  // namespace

GlRaycastHarness::GlRaycastHarness(GlContext& ctx) : ctx_(ctx)
{
    ctx_.make_current();
    ctx_.gl().GenVertexArrays(1, &vao_);
}

GlRaycastHarness::~GlRaycastHarness()
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    for (GLuint& t : textures_)
        if (t) gl.DeleteTextures(1, &t);
    programs_.clear();
    if (vao_) gl.DeleteVertexArrays(1, &vao_);
}

const GlProgram& GlRaycastHarness::program(int which)
{
    auto& p = programs_[which];
    if (!p) {
        const char* const modes[] = {"HARNESS_RAY", "HARNESS_MARCH", "HARNESS_LIGHT", "HARNESS_RAY_PUBLISHED"};
        const char* mode = modes[which];
        p = std::make_unique<GlProgram>(
            ctx_, GlShaderSource{{"fullscreen.vert"}, {}, {}},
            GlShaderSource{{"classification_table.frag", "preintegration_table.frag", "raycast_fragment.frag",
                            "raycast_harness.frag"},
                           {{mode, "1"}, {"RAYCAST_SHADE", "1"}},  // shading decided by the uniform rc_shade
                           {}});
    }
    return *p;
}

std::vector<RaycastRayExact> GlRaycastHarness::run_ray(const RaycastFrameConstants& fc,
                                                       const std::vector<glm::ivec2>& pixels)
{
    ctx_.make_current();
    const GlProgram& prog = program(0);
    ctx_.gl().UseProgram(prog.id());
    set_raycast_frame_uniforms(ctx_, prog, fc);
    std::vector<RaycastRayExact> out(pixels.size());
    run_chunks(
        ctx_, prog, vao_, pixels.size(), "the ray caster's ray harness pass",
        [&](std::size_t base, std::size_t m, HarnessPass& pass) {
            pass.storage(0, pixels.data() + base, m * sizeof(glm::ivec2));
            return pass.storage(1, nullptr, m * sizeof(GlRayExact));
        },
        [&](std::size_t base, std::size_t m, HarnessPass& pass, GLuint results) {
            std::vector<GlRayExact> res(m);
            pass.read_storage(results, res.data(), m * sizeof(GlRayExact));
            for (std::size_t i = 0; i < m; ++i) {
                const GlRayExact& r = res[i];
                RaycastRayExact& o = out[base + i];
                o.samples = r.samples;
                o.tex0 = get(r.tex0);
                o.dtex = get(r.dtex);
                o.tex_exit = get(r.tex_exit);
                o.last_length = r.last_length;
                o.length = r.length;
                o.entry = get(r.entry);
                o.dir = get(r.dir);
            }
        });
    return out;
}

std::vector<RaycastResult> GlRaycastHarness::run_march(const RaycastVolume& rv, const RaycastFrameConstants& fc,
                                                       const std::vector<RaycastRay>& rays)
{
    ctx_.make_current();
    upload_raycast_textures(ctx_, rv, textures_);
    const GlProgram& prog = program(1);
    ctx_.gl().UseProgram(prog.id());
    set_raycast_frame_uniforms(ctx_, prog, fc);
    std::vector<RaycastResult> out(rays.size());
    run_chunks(
        ctx_, prog, vao_, rays.size(), "the ray caster's march harness pass",
        [&](std::size_t base, std::size_t m, HarnessPass& pass) {
            std::vector<GlRay> in(m);
            for (std::size_t i = 0; i < m; ++i) {
                const RaycastRay& r = rays[base + i];
                GlRay& g = in[i];
                g = GlRay{};
                g.length = r.length;
                put(r.entry, g.entry);
                put(r.dir, g.dir);
                put(r.tex0, g.tex0);
                put(r.dtex, g.dtex);
                put(r.tex_exit, g.tex_exit);
                g.last_length = r.last_length;
                g.samples = r.samples;
            }
            pass.storage(0, in.data(), m * sizeof(GlRay));
            return pass.storage(1, nullptr, m * sizeof(GlMarchResult));
        },
        [&](std::size_t base, std::size_t m, HarnessPass& pass, GLuint results) {
            std::vector<GlMarchResult> res(m);
            pass.read_storage(results, res.data(), m * sizeof(GlMarchResult));
            for (std::size_t i = 0; i < m; ++i) {
                RaycastResult& o = out[base + i];
                o.colour = {res[i].colour[0], res[i].colour[1], res[i].colour[2], res[i].colour[3]};
                o.samples = uint32_t(res[i].samples);
            }
        });
    return out;
}

std::vector<glm::dvec2> GlRaycastHarness::run_light(const RaycastFrameConstants& fc,
                                                    const std::vector<RaycastLightCase>& cases)
{
    ctx_.make_current();
    const GlProgram& prog = program(2);
    ctx_.gl().UseProgram(prog.id());
    set_raycast_frame_uniforms(ctx_, prog, fc);
    std::vector<glm::dvec2> out(cases.size());
    run_chunks(
        ctx_, prog, vao_, cases.size(), "the ray caster's light harness pass",
        [&](std::size_t base, std::size_t m, HarnessPass& pass) {
            std::vector<GlLightCase> in(m);
            for (std::size_t i = 0; i < m; ++i) {
                const RaycastLightCase& c = cases[base + i];
                in[i] = GlLightCase{};
                put(c.entry, in[i].entry);
                put(c.dir, in[i].dir);
                in[i].t = c.t;
                put(c.g, in[i].g);
            }
            pass.storage(0, in.data(), m * sizeof(GlLightCase));
            return pass.storage(1, nullptr, m * 2 * sizeof(double));
        },
        [&](std::size_t base, std::size_t m, HarnessPass& pass, GLuint results) {
            std::vector<double> res(m * 2);
            pass.read_storage(results, res.data(), res.size() * sizeof(double));
            for (std::size_t i = 0; i < m; ++i) out[base + i] = {res[2 * i], res[2 * i + 1]};
        });
    return out;
}

std::vector<RaycastRay> GlRaycastHarness::run_ray_published(const RaycastFrameConstants& fc,
                                                            const std::vector<glm::vec4>& texels)
{
    ctx_.make_current();
    const GlProgram& prog = program(3);
    ctx_.gl().UseProgram(prog.id());
    set_raycast_frame_uniforms(ctx_, prog, fc);
    std::vector<RaycastRay> out(texels.size() / 2);
    run_chunks(
        ctx_, prog, vao_, out.size(), "the ray caster's published ray harness pass",
        [&](std::size_t base, std::size_t m, HarnessPass& pass) {
            pass.storage(0, texels.data() + 2 * base, 2 * m * sizeof(glm::vec4));
            return pass.storage(1, nullptr, m * sizeof(GlRay));
        },
        [&](std::size_t base, std::size_t m, HarnessPass& pass, GLuint results) {
            std::vector<GlRay> res(m);
            pass.read_storage(results, res.data(), m * sizeof(GlRay));
            for (std::size_t i = 0; i < m; ++i) {
                const GlRay& g = res[i];
                RaycastRay& o = out[base + i];
                o.samples = g.samples;
                o.length = g.length;
                o.entry = get(g.entry);
                o.dir = get(g.dir);
                o.tex0 = {g.tex0[0], g.tex0[1], g.tex0[2]};
                o.dtex = {g.dtex[0], g.dtex[1], g.dtex[2]};
                o.tex_exit = {g.tex_exit[0], g.tex_exit[1], g.tex_exit[2]};
                o.last_length = g.last_length;
            }
        });
    return out;
}

}  // namespace uvr::gpu
