#include "gpu/vicp/gl_vicp_harness.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "gpu/gl/gl_harness_pass.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "gpu/vicp/gl_vicp_fragment.h"
#include "reference/error.h"

namespace uvr::gpu {

namespace {

// The std430 layouts of the harness shaders' case and result structs.
struct GlVertexCase {
    double shape[12], exact[12], s[4];
    uint32_t boundary, pad;
};
static_assert(sizeof(GlVertexCase) == 232, "GlVertexCase must match HarnessVertexCase in shaders/vicp_harness.vert");

struct GlCompositeCase {
    double segment[5];
    double pad;  // vec4 members align to 16 bytes
    float framebuffer[4], diagnostics[4], shade[4];
};
static_assert(sizeof(GlCompositeCase) == 96 && offsetof(GlCompositeCase, framebuffer) == 48,
              "GlCompositeCase must match HarnessCompositeCase in shaders/vicp_harness.frag");

struct GlCompositeResult {
    float framebuffer[4], diagnostics[4], shade_args[4];
    uint32_t written, pad[3];
};
static_assert(sizeof(GlCompositeResult) == 64,
              "GlCompositeResult must match HarnessCompositeResult in shaders/vicp_harness.frag");

void put(const glm::dvec3& v, double* out)
{
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}
glm::dvec3 get(const double* v) { return {v[0], v[1], v[2]}; }

// VicpDiagnostics as the shaders hold it: counts as exact floats.
void put(const VicpDiagnostics& d, float* out)
{
    out[0] = float(d.fragments);
    out[1] = float(d.ordering_errors);
    out[2] = d.last_back;
    out[3] = d.last_front;
}
VicpDiagnostics get_diagnostics(const float* v) { return {uint32_t(v[0]), uint32_t(v[1]), v[2], v[3]}; }

constexpr std::size_t kChunk = std::size_t(kHarnessWidth) * kHarnessRows;

}  // namespace

GlVicpTet pack_vicp_tet(const VicpTet& t)
{
    GlVicpTet g{};
    put(t.p0, g.p0);
    put(t.base, g.base);
    put(t.g, g.g);
    for (int i = 0; i < 3; ++i) {
        put(t.m[i], g.m + 3 * i);
        put(t.me[i], g.me + 3 * i);
    }
    g.det = t.det;
    g.s0 = t.s0;
    g.boundary = t.boundary;
    return g;
}

VicpTet unpack_vicp_tet(const GlVicpTet& g)
{
    VicpTet t;
    t.p0 = get(g.p0);
    t.base = get(g.base);
    t.g = get(g.g);
    for (int i = 0; i < 3; ++i) {
        t.m[i] = get(g.m + 3 * i);
        t.me[i] = get(g.me + 3 * i);
    }
    t.det = g.det;
    t.s0 = g.s0;
    t.boundary = g.boundary;
    return t;
}

GlVicpHarness::GlVicpHarness(GlContext& ctx) : ctx_(ctx)
{
    ctx_.make_current();
    GLint blocks = 0;
    ctx_.gl().GetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &blocks);
    if (blocks < 2)
        throw InputError("", "the VICP vertex stage harness needs storage buffers in the vertex stage, which " +
                                 ctx_.info().renderer + " lacks");
    ctx_.gl().GenVertexArrays(1, &vao_);
}

GlVicpHarness::~GlVicpHarness()
{
    const GlFunctions& gl = ctx_.gl();
    if (table_texture_) gl.DeleteTextures(1, &table_texture_);
    programs_.clear();
    if (vao_) gl.DeleteVertexArrays(1, &vao_);
}

const GlProgram& GlVicpHarness::program(int which)
{
    auto& p = programs_[which];
    if (!p) {
        if (which == 4) {
            p = std::make_unique<GlProgram>(
                ctx_,
                GlShaderSource{{"vicp_published.glsl", "vicp_published_vertex.vert", "vicp_harness.vert"},
                               {{"HARNESS_PUBLISHED_VERTEX", "1"}},
                               {}},
                GlShaderSource{
                    {"vicp_tet.glsl", "preintegration_table.frag", "vicp_fragment.frag", "vicp_harness.frag"},
                    {{"HARNESS_NONE", "1"}},
                    {}});
        } else if (which == 5) {
            p = std::make_unique<GlProgram>(
                ctx_, GlShaderSource{{"fullscreen.vert"}, {}, {}},
                GlShaderSource{{"vicp_tet.glsl", "preintegration_table.frag", "vicp_fragment.frag",
                                "vicp_published_fragment.frag", "vicp_harness.frag"},
                               {{"HARNESS_PUBLISHED_EXIT", "1"}},
                               {}});
        } else if (which == 0) {
            // A fragment stage is needed to link; with the rasterizer discarding it never runs.
            p = std::make_unique<GlProgram>(
                ctx_, GlShaderSource{{"vicp_tet.glsl", "vicp_vertex.vert", "vicp_harness.vert"}, {}, {}},
                GlShaderSource{{"vicp_tet.glsl", "preintegration_table.frag", "vicp_fragment.frag", "vicp_harness.frag"},
                               {{"HARNESS_NONE", "1"}},
                               {}});
        } else {
            GlShaderSource fs{
                {"vicp_tet.glsl", "preintegration_table.frag", "vicp_fragment.frag", "vicp_harness.frag"}, {}, {}};
            fs.defines.push_back({which == 1 ? "HARNESS_VALUES" : "HARNESS_COMPOSITE", "1"});
            if (which == 3) fs.defines.push_back({"HARNESS_SHADE_TABLE", "1"});
            p = std::make_unique<GlProgram>(ctx_, GlShaderSource{{"fullscreen.vert"}, {}, {}}, fs);
        }
    }
    return *p;
}

std::vector<VicpTet> GlVicpHarness::run_vertex(const std::vector<VicpVertexCase>& cases)
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(0);
    gl.UseProgram(prog.id());
    gl.BindVertexArray(vao_);
    gl.Enable(GL_RASTERIZER_DISCARD);
    std::vector<VicpTet> out(cases.size());
    for (std::size_t base = 0; base < cases.size(); base += kChunk) {
        const std::size_t m = std::min(kChunk, cases.size() - base);
        std::vector<GlVertexCase> in(m);
        for (std::size_t i = 0; i < m; ++i) {
            const VicpVertexCase& c = cases[base + i];
            GlVertexCase& g = in[i];
            g = GlVertexCase{};
            for (int v = 0; v < 4; ++v) {
                put(c.shape[v], g.shape + 3 * v);
                put(c.exact[v], g.exact + 3 * v);
                g.s[v] = c.s[v];
            }
            g.boundary = c.boundary;
        }
        HarnessPass pass(gl);
        pass.storage(0, in.data(), m * sizeof(GlVertexCase));
        const GLuint results = pass.storage(1, nullptr, m * sizeof(GlVicpTet));
        pass.targets(ctx_, {GL_RGBA32F}, 1, 1);  // a complete framebuffer (EGL has no default one), never drawn into
        gl.DrawArrays(GL_POINTS, 0, GLsizei(m));
        std::vector<GlVicpTet> res(m);
        pass.read_storage(results, res.data(), m * sizeof(GlVicpTet));
        ctx_.check_error("the VICP vertex harness pass");
        for (std::size_t i = 0; i < m; ++i) out[base + i] = unpack_vicp_tet(res[i]);
    }
    gl.Disable(GL_RASTERIZER_DISCARD);
    return out;
}

std::vector<VicpSegment> GlVicpHarness::run_values(const VicpFrameConstants& fc, const std::vector<VicpTet>& tets,
                                                   const std::vector<glm::ivec2>& pixels)
{
    if (tets.size() != pixels.size()) throw std::invalid_argument("run_values: one pixel per tetrahedron");
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(1);
    gl.UseProgram(prog.id());
    set_vicp_frame_uniforms(ctx_, prog, fc);
    gl.Uniform1i(prog.uniform("harness_width"), kHarnessWidth);
    gl.BindVertexArray(vao_);
    std::vector<VicpSegment> out(tets.size());
    for (std::size_t base = 0; base < tets.size(); base += kChunk) {
        const std::size_t m = std::min(kChunk, tets.size() - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        std::vector<GlVicpTet> in(m);
        for (std::size_t i = 0; i < m; ++i) in[i] = pack_vicp_tet(tets[base + i]);
        gl.Uniform1i(prog.uniform("harness_count"), GLint(m));
        HarnessPass pass(gl);
        pass.storage(0, in.data(), m * sizeof(GlVicpTet));
        pass.storage(1, pixels.data() + base, m * sizeof(glm::ivec2));
        const GLuint results = pass.storage(2, nullptr, m * 5 * sizeof(double));
        pass.targets(ctx_, {GL_RGBA32F}, w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        std::vector<double> res(m * 5);
        pass.read_storage(results, res.data(), res.size() * sizeof(double));
        ctx_.check_error("the VICP fragment-values harness pass");
        for (std::size_t i = 0; i < m; ++i) {
            const double* r = &res[i * 5];
            out[base + i] = VicpSegment{r[0], r[1], r[2], r[3], r[4]};
        }
    }
    return out;
}

std::vector<VicpCompositeResult> GlVicpHarness::run_composite(const VicpFrameConstants& fc,
                                                              const std::vector<VicpCompositeCase>& cases,
                                                              const PreintegrationTable* table)
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(table ? 3 : 2);
    gl.UseProgram(prog.id());
    set_vicp_frame_uniforms(ctx_, prog, fc);
    gl.Uniform1i(prog.uniform("harness_width"), kHarnessWidth);
    if (table) upload_preintegration_table(ctx_, *table, TextureFilter::linear, table_texture_);
    gl.BindVertexArray(vao_);
    std::vector<VicpCompositeResult> out(cases.size());
    for (std::size_t base = 0; base < cases.size(); base += kChunk) {
        const std::size_t m = std::min(kChunk, cases.size() - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        std::vector<GlCompositeCase> in(m);
        for (std::size_t i = 0; i < m; ++i) {
            const VicpCompositeCase& c = cases[base + i];
            const VicpSegment& s = c.segment;
            GlCompositeCase& g = in[i];
            g = GlCompositeCase{{s.s_front, s.s_back, s.t_in, s.t_out, s.length}, 0.0, {}, {}, {}};
            std::memcpy(g.framebuffer, &c.framebuffer[0], sizeof(g.framebuffer));
            put(c.diagnostics, g.diagnostics);
            std::memcpy(g.shade, &c.shade[0], sizeof(g.shade));
        }
        gl.Uniform1i(prog.uniform("harness_count"), GLint(m));
        HarnessPass pass(gl);
        pass.storage(0, in.data(), m * sizeof(GlCompositeCase));
        const GLuint results = pass.storage(1, nullptr, m * sizeof(GlCompositeResult));
        pass.targets(ctx_, {GL_RGBA32F}, w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        std::vector<GlCompositeResult> res(m);
        pass.read_storage(results, res.data(), m * sizeof(GlCompositeResult));
        ctx_.check_error("the VICP composite harness pass");
        for (std::size_t i = 0; i < m; ++i) {
            const GlCompositeResult& r = res[i];
            VicpCompositeResult& o = out[base + i];
            o.written = r.written != 0;
            std::memcpy(&o.framebuffer[0], r.framebuffer, sizeof(r.framebuffer));
            o.diagnostics = get_diagnostics(r.diagnostics);
            std::memcpy(&o.shade_args[0], r.shade_args, sizeof(r.shade_args));
        }
    }
    return out;
}

std::vector<VicpPublishedVaryings> GlVicpHarness::run_published_vertex(const VicpPublishedView& view,
                                                                       const std::vector<VicpPublishedVertex>& cases)
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(4);
    gl.UseProgram(prog.id());
    gl.Uniform1i(prog.uniform("vicp_published_orthographic"), view.orthographic);
    gl.Uniform3f(prog.uniform("vicp_published_direction"), view.direction.x, view.direction.y, view.direction.z);
    gl.BindVertexArray(vao_);
    gl.Enable(GL_RASTERIZER_DISCARD);
    std::vector<VicpPublishedVaryings> out(cases.size());
    for (std::size_t base = 0; base < cases.size(); base += kChunk) {
        const std::size_t m = std::min(kChunk, cases.size() - base);
        HarnessPass pass(gl);
        pass.storage(0, cases.data() + base, m * sizeof(VicpPublishedVertex));  // 11 floats a case, as the std430 array
        const GLuint results = pass.storage(1, nullptr, m * 8 * sizeof(float));
        pass.targets(ctx_, {GL_RGBA32F}, 1, 1);  // a complete framebuffer (EGL has no default one), never drawn into
        gl.DrawArrays(GL_POINTS, 0, GLsizei(m));
        std::vector<float> res(m * 8);
        pass.read_storage(results, res.data(), res.size() * sizeof(float));
        ctx_.check_error("the VICP published vertex harness pass");
        for (std::size_t i = 0; i < m; ++i) {
            const float* r = &res[8 * i];
            VicpPublishedVaryings& v = out[base + i];
            v.distance = {r[0], r[1], r[2]};
            v.s = r[3];
            v.scalar = {r[4], r[5], r[6]};
        }
    }
    gl.Disable(GL_RASTERIZER_DISCARD);
    return out;
}

std::vector<VicpPublishedExit> GlVicpHarness::run_published_exit(const std::vector<VicpPublishedVaryings>& cases)
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(5);
    gl.UseProgram(prog.id());
    gl.Uniform1i(prog.uniform("harness_width"), kHarnessWidth);
    gl.BindVertexArray(vao_);
    std::vector<VicpPublishedExit> out(cases.size());
    for (std::size_t base = 0; base < cases.size(); base += kChunk) {
        const std::size_t m = std::min(kChunk, cases.size() - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        std::vector<glm::vec4> in(2 * m);
        for (std::size_t i = 0; i < m; ++i) {
            const VicpPublishedVaryings& c = cases[base + i];
            in[2 * i] = glm::vec4(c.distance, c.s);
            in[2 * i + 1] = glm::vec4(c.scalar, 0.0f);
        }
        gl.Uniform1i(prog.uniform("harness_count"), GLint(m));
        HarnessPass pass(gl);
        pass.storage(0, in.data(), in.size() * sizeof(glm::vec4));
        const GLuint results = pass.storage(1, nullptr, m * sizeof(glm::vec4));
        pass.targets(ctx_, {GL_RGBA32F}, w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        std::vector<glm::vec4> res(m);
        pass.read_storage(results, res.data(), m * sizeof(glm::vec4));
        ctx_.check_error("the VICP published exit harness pass");
        for (std::size_t i = 0; i < m; ++i)
            out[base + i] = VicpPublishedExit{int(res[i].w), res[i].x, res[i].y, res[i].z};
    }
    return out;
}

}  // namespace uvr::gpu
