#include "gpu/havs/gl_havs_harness.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>

#include "gpu/gl/gl_harness_pass.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "gpu/havs/gl_havs_arb.h"
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
            fs.defines.push_back({"HARNESS_PAPER", "1"});
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

std::vector<glm::vec4> GlHavsFragmentHarness::run_paper(const HavsFrameConstants& fc,
                                                        const std::vector<HavsVaryings>& v,
                                                        const std::vector<glm::vec3>& corners)
{
    if (v.size() != corners.size()) throw std::invalid_argument("run_paper: one corner triple per case");
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
        ctx_.check_error("the paper-entry harness pass");
        const std::vector<float> res = pass.read(0, w, h);
        for (std::size_t i = 0; i < m; ++i) out[base + i] = glm::vec4(res[4 * i], res[4 * i + 1], res[4 * i + 2], 0.0f);
    }
    return out;
}

// ---- The paper's ARB fragment program ----

namespace {
// The harness's vertex program: the point's clip position and both texture coordinates as they are.
constexpr const char* kArbPassThrough = "!!ARBvp1.0\n"
                                        "MOV result.position, vertex.position;\n"
                                        "MOV result.texcoord[0], vertex.texcoord[0];\n"
                                        "MOV result.texcoord[1], vertex.texcoord[1];\n"
                                        "END\n";
struct ArbCaseVertex {
    float position[3];  // clip coordinates (w is the default 1)
    float scalar;
    float eye[3];
};
}  // namespace

struct GlHavsArbHarness::Objects {
    std::unique_ptr<ArbFunctions> arb;
    std::unique_ptr<ArbProgram> vertex, fragment;
    GLuint table_texture = 0;
};

GlHavsArbHarness::GlHavsArbHarness(GlContext& ctx) : ctx_(ctx), gl_(std::make_unique<Objects>())
{
    gl_->arb = load_arb_functions(ctx_);
    gl_->vertex = std::make_unique<ArbProgram>(ctx_, *gl_->arb, arb::kVertexProgram, "the pass-through vertex program",
                                               kArbPassThrough);
    gl_->fragment = std::make_unique<ArbProgram>(ctx_, *gl_->arb, arb::kFragmentProgram,
                                                 shader_dir() + "/havs_paper.fp", read_shader_file("havs_paper.fp"));
}

GlHavsArbHarness::~GlHavsArbHarness()
{
    if (gl_->table_texture) ctx_.gl().DeleteTextures(1, &gl_->table_texture);
}

ArbKBufferResults GlHavsArbHarness::run(const PreintegrationTable& table, float length_scale, float length_bias,
                                        const ArbKBufferCases& cases)
{
    const GlFunctions& gl = ctx_.gl();
    const ArbFunctions& arb = *gl_->arb;
    constexpr int W = kHarnessWidth, H = kHarnessRows, K = kArbK;
    upload_preintegration_table(ctx_, table, TextureFilter::linear, gl_->table_texture);
    ArbKBufferResults out;
    out.entries.resize(cases.size() * K);
    out.framebuffer.resize(cases.size());
    for (std::size_t c0 = 0; c0 < cases.size(); c0 += std::size_t(W) * H) {
        const std::size_t n = std::min(std::size_t(W) * H, cases.size() - c0);
        HarnessPass pass(gl);
        // Textures 0-3, filled with the cases' colour and entries, bound on units 0-3 and as attachments 0-3.
        std::vector<float> texels[4];
        for (auto& t : texels) t.assign(std::size_t(W) * H * 4, 0.0f);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec4& f = cases.framebuffer[c0 + i];
            std::copy(&f.x, &f.x + 4, &texels[0][4 * i]);
            for (int e = 0; e < K; ++e) {
                const KEntry& a = cases.entries[(c0 + i) * K + std::size_t(e)];
                texels[1 + e / 2][4 * i + 2 * std::size_t(e % 2)] = a.x;
                texels[1 + e / 2][4 * i + 2 * std::size_t(e % 2) + 1] = a.y;
            }
        }
        for (int t = 0; t < 4; ++t) pass.input_2d(t, texels[t], W, H);
        gl.ActiveTexture(GL_TEXTURE4);
        gl.BindTexture(GL_TEXTURE_3D, gl_->table_texture);
        gl.GenFramebuffers(1, &pass.fbo);
        gl.BindFramebuffer(GL_FRAMEBUFFER, pass.fbo);
        GLenum bufs[4];
        for (int t = 0; t < 4; ++t) {
            gl.FramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + t), GL_TEXTURE_2D,
                                    pass.textures[std::size_t(t)], 0);
            bufs[t] = GLenum(GL_COLOR_ATTACHMENT0 + t);
        }
        gl.DrawBuffers(4, bufs);
        check_framebuffer(ctx_, "the ARB harness");
        gl.Viewport(0, 0, W, H);
        gl.Disable(GL_BLEND);
        gl.Disable(GL_DEPTH_TEST);
        gl.Disable(GL_CULL_FACE);
        // One point a case at its pixel's centre: x = (px + 0.5) / (W / 2) - 1 is exact in float, and so is the
        // viewport transform's x * W / 2 + W / 2 (W = 1024, H = 256).
        std::vector<ArbCaseVertex> points(n);
        for (std::size_t i = 0; i < n; ++i) {
            const int px = int(i % W), py = int(i / W);
            const glm::vec3& e = cases.eye[c0 + i];
            points[i] = ArbCaseVertex{{(float(px) + 0.5f) / (0.5f * W) - 1.0f, (float(py) + 0.5f) / (0.5f * H) - 1.0f,
                                       0.0f},
                                      cases.scalar[c0 + i],
                                      {e.x, e.y, e.z}};
        }
        GLuint buffer = 0;
        gl.GenBuffers(1, &buffer);
        pass.buffers.push_back(buffer);
        gl.BindVertexArray(0);
        gl.BindBuffer(GL_ARRAY_BUFFER, buffer);
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(n * sizeof(ArbCaseVertex)), points.data(), GL_STREAM_DRAW);
        arb.EnableClientState(arb::kVertexArray);
        arb.VertexPointer(3, GL_FLOAT, sizeof(ArbCaseVertex), nullptr);
        arb.ClientActiveTexture(GL_TEXTURE0);
        arb.EnableClientState(arb::kTexCoordArray);
        arb.TexCoordPointer(1, GL_FLOAT, sizeof(ArbCaseVertex),
                            reinterpret_cast<const void*>(offsetof(ArbCaseVertex, scalar)));
        arb.ClientActiveTexture(GL_TEXTURE1);
        arb.EnableClientState(arb::kTexCoordArray);
        arb.TexCoordPointer(3, GL_FLOAT, sizeof(ArbCaseVertex), reinterpret_cast<const void*>(offsetof(ArbCaseVertex, eye)));
        arb.ClientActiveTexture(GL_TEXTURE0);
        arb.PointSize(1.0f);
        gl.Enable(arb::kVertexProgram);
        gl.Enable(arb::kFragmentProgram);
        gl_->vertex->bind();
        gl_->fragment->bind();
        arb.ProgramLocalParameter4fARB(arb::kFragmentProgram, 0, 1.0f / float(W), 1.0f / float(H), length_scale,
                                       length_bias);
        gl.DrawArrays(GL_POINTS, 0, GLsizei(n));
        gl.Finish();
        gl.Disable(arb::kVertexProgram);
        gl.Disable(arb::kFragmentProgram);
        for (GLenum unit : {GL_TEXTURE1, GL_TEXTURE0}) {  // the arrays point into this pass's buffer, deleted next
            arb.ClientActiveTexture(unit);
            arb.DisableClientState(arb::kTexCoordArray);
        }
        arb.DisableClientState(arb::kVertexArray);
        ctx_.check_error("the ARB harness pass");
        std::vector<float> read(std::size_t(W) * H * 4);
        gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
        for (int t = 0; t < 4; ++t) {
            gl.ReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + t));
            gl.ReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, read.data());
            for (std::size_t i = 0; i < n; ++i) {
                if (t == 0) {
                    out.framebuffer[c0 + i] = glm::vec4(read[4 * i], read[4 * i + 1], read[4 * i + 2], read[4 * i + 3]);
                    continue;
                }
                for (int h = 0; h < 2; ++h)
                    out.entries[(c0 + i) * K + std::size_t(2 * (t - 1) + h)] =
                        KEntry{read[4 * i + 2 * std::size_t(h)], read[4 * i + 2 * std::size_t(h) + 1]};
            }
        }
        ctx_.check_error("reading the ARB harness back");
    }
    return out;
}

}  // namespace uvr::gpu
