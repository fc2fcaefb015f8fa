#include "gpu/havs/gl_havs_harness.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>

#include "gpu/gl/gl_harness_pass.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "gpu/havs/gl_havs_fragment.h"
#include "reference/error.h"

namespace uvr::gpu {

namespace {

bool is_sentinel(const float* v)
{
    for (int c = 0; c < 4; ++c)
        if (std::memcmp(&v[c], &kHarnessSentinel, sizeof(float)) != 0) return false;
    return true;
}

}  // namespace

GlHavsFragmentHarness::GlHavsFragmentHarness(GlContext& ctx) : ctx_(ctx)
{
    ctx_.make_current();
    ctx_.gl().GenVertexArrays(1, &vao_);
}

GlHavsFragmentHarness::~GlHavsFragmentHarness()
{
    const GlFunctions& gl = ctx_.gl();
    if (table_texture_) gl.DeleteTextures(1, &table_texture_);
    programs_.clear();
    if (vao_) gl.DeleteVertexArrays(1, &vao_);
}

int GlHavsFragmentHarness::max_k() const { return (ctx_.info().max_draw_buffers - 2) * 2; }

const GlProgram& GlHavsFragmentHarness::program(int k, int mode)
{
    auto& p = programs_[{k, mode}];
    if (!p) {
        GlShaderSource vs{{"fullscreen.vert"}, {}, {}};
        GlShaderSource fs{{"preintegration_table.frag", "havs_fragment.frag", "havs_fragment_harness.frag"},
                          {{"HAVS_K", std::to_string(std::max(k, 1))}},
                          {}};
        if (k == -1) {
            fs.defines.push_back({"HARNESS_SEED", "1"});
        } else if (k == 0) {
            fs.defines.push_back({"HARNESS_ENTRY", "1"});
        } else {
            fs.defines.push_back({"HARNESS_KBUFFER", "1"});
            if (mode == int(HarnessShade::table)) fs.defines.push_back({"HARNESS_SHADE_TABLE", "1"});
        }
        p = std::make_unique<GlProgram>(ctx_, vs, fs);
    }
    return *p;
}

void GlHavsFragmentHarness::upload_table(const PreintegrationTable& table)
{
    upload_preintegration_table(ctx_, table, TextureFilter::linear, table_texture_);
}

KBufferResults GlHavsFragmentHarness::run_kbuffer(const HavsFrameConstants& fc, const KBufferCases& cases,
                                                  HarnessShade shade, const PreintegrationTable* table)
{
    const int k = cases.k;
    if (k < 1 || k > max_k())
        throw InputError("", "the GL k-buffer harness takes k from 1 to " + std::to_string(max_k()) + ", not " +
                                 std::to_string(k));
    const std::size_t n = cases.size();
    if (cases.entries.size() != n * std::size_t(k) || cases.framebuffer.size() != n ||
        (shade == HarnessShade::per_case && cases.shade.size() != n))
        throw std::invalid_argument("run_kbuffer: inconsistent case arrays");
    if (shade == HarnessShade::table && !table) throw std::invalid_argument("run_kbuffer: no table");
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(k, int(shade));
    gl.UseProgram(prog.id());
    set_havs_frame_uniforms(ctx_, prog, fc);
    gl.Uniform1i(prog.uniform("harness_width"), kHarnessWidth);
    gl.Uniform1i(prog.uniform("harness_base"), 0);
    if (shade == HarnessShade::table) upload_table(*table);
    gl.BindVertexArray(vao_);

    const int layers = (k + 1) / 2;
    KBufferResults res;
    res.written.resize(n);
    res.entries.resize(n * std::size_t(k));
    res.framebuffer.resize(n);
    res.shade_args.resize(n);
    const std::size_t chunk = std::size_t(kHarnessWidth) * kHarnessRows;
    for (std::size_t base = 0; base < n; base += chunk) {
        const std::size_t m = std::min(chunk, n - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        const std::size_t px = std::size_t(w) * std::size_t(h);
        // Inputs; the padding pixels past the last case get empty entries and a transparent framebuffer.
        std::vector<float> entries(px * std::size_t(layers) * 4, 0.0f), fbuf(px * 4, 0.0f), inc(px * 4, 0.0f),
            col(px * 4, 0.0f);
        for (std::size_t i = 0; i < px; ++i) {
            for (int e = 0; e < 2 * layers; ++e) {
                const KEntry v = (i < m && e < k) ? cases.entries[(base + i) * std::size_t(k) + std::size_t(e)]
                                                  : kEmptyEntry;
                float* t = &entries[(std::size_t(e / 2) * px + i) * 4 + std::size_t(e % 2) * 2];
                t[0] = v.x;
                t[1] = v.y;
            }
            if (i >= m) continue;
            const glm::vec4& f = cases.framebuffer[base + i];
            std::memcpy(&fbuf[i * 4], &f[0], sizeof(float) * 4);
            inc[i * 4] = cases.incoming[base + i].x;
            inc[i * 4 + 1] = cases.incoming[base + i].y;
            if (shade == HarnessShade::per_case) std::memcpy(&col[i * 4], &cases.shade[base + i][0], sizeof(float) * 4);
        }
        HarnessPass pass(gl);
        pass.texture(GL_TEXTURE_2D_ARRAY, 0);
        gl.TexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA32F, w, h, layers, 0, GL_RGBA, GL_FLOAT, entries.data());
        pass.input_2d(1, fbuf, w, h);
        pass.input_2d(2, inc, w, h);
        pass.input_2d(3, col, w, h);
        pass.targets(ctx_, std::vector<GLenum>(std::size_t(2 + layers), GL_RGBA32F), w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        ctx_.check_error("the k-buffer harness pass");
        const std::vector<float> out_fb = pass.read(0, w, h), out_args = pass.read(1, w, h);
        std::vector<std::vector<float>> out_entries;
        for (int j = 0; j < layers; ++j) out_entries.push_back(pass.read(2 + j, w, h));
        ctx_.check_error("reading the k-buffer harness's targets back");
        for (std::size_t i = 0; i < m; ++i) {
            bool discarded = is_sentinel(&out_fb[i * 4]) && is_sentinel(&out_args[i * 4]);
            for (int j = 0; j < layers; ++j) discarded = discarded && is_sentinel(&out_entries[std::size_t(j)][i * 4]);
            const std::size_t c = base + i;
            res.written[c] = discarded ? 0 : 1;
            if (discarded) {
                res.framebuffer[c] = cases.framebuffer[c];
                res.shade_args[c] = glm::vec4(-2.0f);
                for (int e = 0; e < k; ++e) res.entries[c * std::size_t(k) + std::size_t(e)] =
                    cases.entries[c * std::size_t(k) + std::size_t(e)];
                continue;
            }
            std::memcpy(&res.framebuffer[c][0], &out_fb[i * 4], sizeof(float) * 4);
            std::memcpy(&res.shade_args[c][0], &out_args[i * 4], sizeof(float) * 4);
            for (int e = 0; e < k; ++e) {
                const float* t = &out_entries[std::size_t(e / 2)][i * 4 + std::size_t(e % 2) * 2];
                res.entries[c * std::size_t(k) + std::size_t(e)] = KEntry{t[0], t[1]};
            }
        }
    }
    return res;
}

std::vector<KEntry> GlHavsFragmentHarness::run_entry(const HavsFrameConstants& fc, const std::vector<HavsFace>& faces,
                                                     const std::vector<glm::ivec2>& pixels,
                                                     std::vector<glm::dvec2>* values)
{
    if (faces.size() != pixels.size()) throw std::invalid_argument("run_entry: one pixel per face");
    if (values) values->assign(faces.size(), glm::dvec2(0.0));
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(0, 0);
    gl.UseProgram(prog.id());
    set_havs_frame_uniforms(ctx_, prog, fc);
    gl.Uniform1i(prog.uniform("harness_width"), kHarnessWidth);
    gl.Uniform1i(prog.uniform("harness_base"), 0);
    gl.BindVertexArray(vao_);
    const std::size_t n = faces.size();
    std::vector<KEntry> out(n);
    const std::size_t chunk = std::size_t(kHarnessWidth) * kHarnessRows;
    for (std::size_t base = 0; base < n; base += chunk) {
        const std::size_t m = std::min(chunk, n - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        const std::size_t px = std::size_t(w) * std::size_t(h);
        std::vector<GlHavsFace> packed(px, pack_havs_face(faces[base]));  // padding repeats the first case
        std::vector<glm::ivec2> pix(px, pixels[base]);
        for (std::size_t i = 0; i < m; ++i) {
            packed[i] = pack_havs_face(faces[base + i]);
            pix[i] = pixels[base + i];
        }
        HarnessPass pass(gl);
        pass.texel_buffer(kHavsFaceUnit, packed.data(), packed.size() * sizeof(GlHavsFace));
        pass.storage(1, pix.data(), pix.size() * sizeof(glm::ivec2));
        pass.targets(ctx_, {GL_RGBA32F, GL_RGBA32UI}, w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        ctx_.check_error("the fragment-entry harness pass");
        const std::vector<float> res = pass.read(0, w, h);
        const std::vector<uint32_t> dbl = values ? pass.read_uint(1, w, h) : std::vector<uint32_t>();
        ctx_.check_error("reading the fragment-entry harness's targets back");
        for (std::size_t i = 0; i < m; ++i) {
            out[base + i] = KEntry{res[i * 4], res[i * 4 + 1]};
            if (!values) continue;
            // unpackDouble2x32 gives (low, high) words.
            const uint64_t x = uint64_t(dbl[i * 4]) | (uint64_t(dbl[i * 4 + 1]) << 32);
            const uint64_t d = uint64_t(dbl[i * 4 + 2]) | (uint64_t(dbl[i * 4 + 3]) << 32);
            (*values)[base + i] = glm::dvec2(std::bit_cast<double>(x), std::bit_cast<double>(d));
        }
    }
    return out;
}

std::vector<glm::vec4> GlHavsFragmentHarness::run_seed(const HavsFrameConstants& fc, const std::vector<HavsVaryings>& v,
                                                      const std::vector<glm::vec3>& corners)
{
    if (v.size() != corners.size()) throw std::invalid_argument("run_seed: one corner triple per case");
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    const GlProgram& prog = program(-1, 0);
    gl.UseProgram(prog.id());
    set_havs_frame_uniforms(ctx_, prog, fc);
    gl.BindVertexArray(vao_);
    const std::size_t n = v.size();
    std::vector<glm::vec4> out(n);
    const std::size_t chunk = std::size_t(kHarnessWidth) * kHarnessRows;
    for (std::size_t base = 0; base < n; base += chunk) {
        const std::size_t m = std::min(chunk, n - base);
        const int w = kHarnessWidth, h = int((m + std::size_t(w) - 1) / std::size_t(w));
        // Two RGBA32F inputs per case: (eye, s) and (side, corners); padding repeats the first case.
        std::vector<float> a(4 * std::size_t(w) * std::size_t(h)), b(a.size());
        for (std::size_t i = 0; i < std::size_t(w) * std::size_t(h); ++i) {
            const std::size_t c = base + (i < m ? i : 0);
            const float ai[4] = {v[c].eye.x, v[c].eye.y, v[c].eye.z, v[c].s};
            const float bi[4] = {v[c].side, corners[c].x, corners[c].y, corners[c].z};
            std::copy(ai, ai + 4, &a[4 * i]);
            std::copy(bi, bi + 4, &b[4 * i]);
        }
        HarnessPass pass(gl);
        pass.input_2d(0, a, w, h);
        pass.input_2d(1, b, w, h);
        pass.targets(ctx_, {GL_RGBA32F}, w, h);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        ctx_.check_error("the seed-entry harness pass");
        const std::vector<float> res = pass.read(0, w, h);
        for (std::size_t i = 0; i < m; ++i) out[base + i] = glm::vec4(res[4 * i], res[4 * i + 1], res[4 * i + 2], 0.0f);
    }
    return out;
}

}  // namespace uvr::gpu
