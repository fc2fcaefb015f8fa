// The HAVS fragment stage in GLSL (shaders/havs_fragment.frag) against its emulation (gpu/havs/havs_fragment.cpp), bit
// for bit, through the stage harness (gpu/havs/gl_havs_harness.h) under OSMesa (llvmpipe), and the GL context layer's
// errors. docs/spec.md §5 (stage level): at least a million random inputs per stage, with exact ties, empty and flush
// entries, +inf distances, zero- and maximum-length segments and alphas at the kill threshold. No OSMesa, no pass: a
// context that cannot be made fails these tests with the reason (CI installs libosmesa6-dev and libegl-mesa0).
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

#include "gpu/pipeline/denormals.h"
#include "gpu/gl/gl_context.h"
#include "gpu/havs/gl_havs_harness.h"
#include "gpu/havs/havs_fragment.h"
#include "gpu/pipeline/preintegration_table.h"
#include "gpu/pipeline/rasterize.h"
#include "reference/transfer_function.h"
#include "bit_compare.h"
#include "case_rng.h"
#include "kbuffer_cases.h"
#include "gl_harness.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;
using test::bits;
using test::Mismatches;

namespace {

using Gl = test::GlHarness<GlHavsFragmentHarness>;
Gl& gl(GlPlatform p) { return test::gl_harness<GlHavsFragmentHarness>(p); }

using test::KBufferGen;
using test::make_kbuffer_cases;
using test::next_down;
using test::next_up;

// Runs the emulation on every case and compares every output with the GL run's, bit for bit.
struct KBufferTally {
    uint64_t cases = 0, killed = 0, lookups = 0, zero_length = 0, max_length = 0;
};

void compare_kbuffer(const HavsFrameConstants& fc, const KBufferCases& cs, const KBufferResults& glr,
                     const SegmentShader* table_shader, Mismatches& mm, KBufferTally& tally)
{
    const int k = cs.k;
    for (std::size_t c = 0; c < cs.size(); ++c) {
        std::vector<KEntry> a(cs.entries.begin() + std::ptrdiff_t(c * std::size_t(k)),
                              cs.entries.begin() + std::ptrdiff_t((c + 1) * std::size_t(k)));
        glm::vec4 fb = cs.framebuffer[c];
        glm::vec4 args(-2.0f);
        const SegmentShader shade = [&](float uf, float ub, float tz, float len) {
            args = glm::vec4(uf, ub, tz, len);
            return table_shader ? (*table_shader)(uf, ub, tz, len) : cs.shade[c];
        };
        const bool written = havs_kbuffer(fc, cs.incoming[c], a.data(), k, fb, shade, nullptr);
        ++tally.cases;
        tally.killed += written ? 0 : 1;
        if (args.x != -2.0f) {
            ++tally.lookups;
            tally.zero_length += args.w == 0.0f ? 1 : 0;
            tally.max_length += fc.max_gap > 0.0f && args.w == fc.max_gap ? 1 : 0;
        }
        mm.check(written ? 1.0f : 0.0f, glr.written[c] ? 1.0f : 0.0f, c, "written");
        for (int ch = 0; ch < 4; ++ch) mm.check(fb[ch], glr.framebuffer[c][ch], c, "framebuffer");
        for (int ch = 0; ch < 4; ++ch) mm.check(args[ch], glr.shade_args[c][ch], c, "lookup argument");
        for (int e = 0; e < k; ++e) {
            mm.check(a[std::size_t(e)].x, glr.entries[c * std::size_t(k) + std::size_t(e)].x, c, "entry x");
            mm.check(a[std::size_t(e)].y, glr.entries[c * std::size_t(k) + std::size_t(e)].y, c, "entry distance");
        }
    }
}

HavsFrameConstants kbuffer_frame(float threshold, float max_gap)
{
    HavsFrameConstants fc;
    fc.threshold = threshold;
    fc.length_scale = (1.0f - 1.0f / 128.0f) / 3.0f;
    fc.length_bias = 1.0f / 256.0f;
    fc.max_gap = max_gap;
    return fc;
}

// ---- fragment-entry cases ----

// havs_fragment_entry's double values before the rounding to float (the emulation's own havs_fragment_values), so
// that the GL run's doubles can be compared too (rounding to float hides all but about one double-level difference in
// 2^29).
glm::dvec2 entry_values(const HavsFrameConstants& fc, const HavsFace& f, int pix_x, int pix_y, bool& snapped)
{
    const FragmentValues v = havs_fragment_values(fc, f, pix_x, pix_y);
    snapped = v.snapped;
    return {v.x, v.distance};
}

// A triangle in eye space seen through a perspective (or orthographic) camera onto a W x H window, with the
// constants havs.cpp computes: window coordinates and 1 / w in double, the rasterizer's snapped vertices, normalized
// scalars. Pixels: ones the rasterizer covers (the real inputs, slivers' snapping-only pixels included) and others
// anywhere near the triangle (extrapolation, the snapped branch).
struct EntryGen : test::CaseRng {
    bool ortho;
    int width = 640, height = 480;
    double fov_scale = 1.0 / std::tan(0.25), ortho_half_h = 3.0;
    explicit EntryGen(uint64_t seed, bool orthographic) : CaseRng(seed), ortho(orthographic) {}

    HavsFrameConstants frame() const
    {
        HavsFrameConstants fc;
        fc.two_over_width = 2.0 / width;
        fc.two_over_height = 2.0 / height;
        if (ortho) {
            fc.origin_x = ortho_half_h * double(width) / double(height);
            fc.origin_y = ortho_half_h;
        }
        return fc;
    }
    glm::dvec3 window(const glm::dvec3& q, double& inv_w) const
    {
        const double aspect = double(width) / double(height);
        double nx, ny;
        if (ortho) {
            inv_w = 1.0;
            nx = q.x / (ortho_half_h * aspect);
            ny = q.y / ortho_half_h;
        } else {
            inv_w = 1.0 / -q.z;
            nx = q.x * fov_scale / aspect * inv_w;
            ny = q.y * fov_scale * inv_w;
        }
        return {(nx + 1.0) * 0.5 * width, (ny + 1.0) * 0.5 * height, 0.0};
    }
    glm::dvec3 point()
    {
        const double z = -uni(2.0, 12.0);
        const double r = ortho ? 3.0 : -z * 0.3;
        return {uni(-r, r), uni(-r, r), z};
    }
    void make(std::vector<HavsFace>& faces, std::vector<glm::ivec2>& pixels, std::size_t want)
    {
        HavsFace f;
        glm::dvec3 q[3] = {point(), point(), point()};
        const int shape = pick(4);
        const double size = shape == 0 ? 0.02 : shape == 1 ? 0.2 : 1.0;
        for (int j = 1; j < 3; ++j) q[j] = q[0] + (q[j] - q[0]) * size;
        if (pick(4) == 0) q[2] = q[0] + (q[1] - q[0]) * uni(0.0, 1.0) + glm::dvec3(uni(-1e-3, 1e-3)) * size;  // sliver
        if (pick(100) == 0) q[2] = q[pick(2)];  // degenerate: zero area (the weights divide by zero)
        WindowCoord wv[3];
        for (int j = 0; j < 3; ++j) {
            double inv_w = 0.0;
            const glm::dvec3 w = window(q[j], inv_w);
            f.inv_w[j] = float(inv_w);
            f.q[j] = glm::vec3(q[j]);
            f.v[j] = glm::dvec2(w.x, w.y);
            wv[j] = {float(w.x), float(w.y)};
            f.fx[j] = snap_to_fixed(wv[j].x);
            f.fy[j] = snap_to_fixed(wv[j].y);
            f.s[j] = float(pick(8) == 0 ? double(pick(2)) : uni(0.0, 1.0));
        }
        f.side = pick(3) == 0 ? kSideExit : pick(2) == 0 ? kSideEntry : kSideInterior;
        const Framebuffer fbuf{width, height, RenderTarget::fbo};
        std::vector<glm::ivec2> covered;
        rasterize_triangle(wv, fbuf, [&](int x, int y) { covered.push_back({x, y}); });
        double x0 = std::min({f.v[0].x, f.v[1].x, f.v[2].x}), x1 = std::max({f.v[0].x, f.v[1].x, f.v[2].x});
        double y0 = std::min({f.v[0].y, f.v[1].y, f.v[2].y}), y1 = std::max({f.v[0].y, f.v[1].y, f.v[2].y});
        const double margin = 2.0 + 0.5 * std::max(x1 - x0, y1 - y0);
        for (std::size_t i = 0; i < want; ++i) {
            glm::ivec2 p;
            if (!covered.empty() && pick(10) < 7) {
                p = covered[std::size_t(pick(int(covered.size())))];
            } else {
                p = {int(std::floor(uni(x0 - margin, x1 + margin))), int(std::floor(uni(y0 - margin, y1 + margin)))};
            }
            faces.push_back(f);
            pixels.push_back(p);
        }
    }
};

}  // namespace

TEST_CASE("GL context: OSMesa gives an OpenGL 4.5 core context and reports llvmpipe and the Mesa version")
{
    const GlInfo& info = gl(GlPlatform::osmesa).ctx->info();
    INFO(info.summary());
    CHECK_THAT(info.version, Catch::StartsWith("4.5"));
    CHECK_THAT(info.version, Catch::Contains("Mesa"));
    CHECK_THAT(info.renderer, Catch::Contains("llvmpipe"));
    CHECK(info.max_draw_buffers >= 8);
    CHECK(gl(GlPlatform::osmesa).harness->max_k() >= 12);
}

TEST_CASE("GL context: a platform name other than osmesa or egl is an input error")
{
    CHECK(parse_gl_platform("osmesa") == GlPlatform::osmesa);
    CHECK(parse_gl_platform("egl") == GlPlatform::egl);
    test::require_input_error([] { parse_gl_platform("glx"); }, {"--gl", "glx"});
}

TEST_CASE("GL errors: a shader that does not compile names its file and carries the GLSL log")
{
    GlContext& ctx = *gl(GlPlatform::osmesa).ctx;
    const std::string vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
    test::require_input_error(
        [&] { compile_program_from_strings(ctx, "broken.frag", vs, "#version 450 core\nvoid main() { x = 1; }\n"); },
        {"broken.frag", "does not compile", "error", "x"});

    // From files: the message names the file of the failing source string, not the prelude.
    test::TempDir dir("glsl");
    dir.write("fullscreen.vert", test::file_contents(shader_dir() + "/fullscreen.vert"));
    dir.write("bad.frag", "out vec4 c;\nvoid main()\n{\n    c = undefined_name;\n}\n");
    const char* env = std::getenv("UVR_SHADER_DIR");
    const std::string old = env ? env : "";
    ::setenv("UVR_SHADER_DIR", dir.file("").c_str(), 1);
    test::require_input_error([&] { GlProgram p(ctx, {{"fullscreen.vert"}, {}, {}}, {{"bad.frag"}, {}, {}}); },
                              {"bad.frag", "does not compile", "undefined_name"});
    test::require_input_error([&] { GlProgram p(ctx, {{"fullscreen.vert"}, {}, {}}, {{"absent.frag"}, {}, {}}); },
                              {"absent.frag", "cannot open"});
    if (env)
        ::setenv("UVR_SHADER_DIR", old.c_str(), 1);
    else
        ::unsetenv("UVR_SHADER_DIR");
    CHECK(shader_dir() != dir.file(""));
}

TEST_CASE("GL errors: an incomplete framebuffer is reported, not drawn into")
{
    GlContext& ctx = *gl(GlPlatform::osmesa).ctx;
    const GlFunctions& f = ctx.gl();
    GLuint fbo = 0;
    f.GenFramebuffers(1, &fbo);
    f.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    test::require_input_error([&] { check_framebuffer(ctx, "an empty FBO"); },
                              {"an empty FBO", "incomplete", "MISSING_ATTACHMENT"});
    f.BindFramebuffer(GL_FRAMEBUFFER, 0);
    f.DeleteFramebuffers(1, &fbo);
}

TEST_CASE("havs_kbuffer in GLSL computes the emulation's bits on 1,400,000 random cases (k = 1 .. 12)")
{
    GlHavsFragmentHarness& h = *gl(GlPlatform::osmesa).harness;
    struct Batch {
        int k;
        std::size_t n;
        float threshold, max_gap;
    };
    // Threshold 0.99 (the paper's) and 1 (no early termination); max_gap 0 (no limit) and 0.5 (dyadic, so that
    // maximum-length segments can be built exactly).
    const Batch batches[] = {{6, 400000, 0.99f, 0.5f}, {6, 200000, 1.0f, 0.0f}, {6, 150000, 0.99f, 0.0f},
                             {1, 150000, 0.99f, 0.5f}, {2, 150000, 0.99f, 0.5f}, {3, 100000, 1.0f, 0.5f},
                             {5, 100000, 0.99f, 0.5f}, {12, 150000, 0.99f, 0.5f}};
    Mismatches mm;
    KBufferTally t;
    uint64_t seed = 1;
    for (const Batch& b : batches) {
        KBufferGen g(seed++, b.max_gap);
        const KBufferCases cs = make_kbuffer_cases(g, b.k, test::random_cases(b.n), b.threshold);
        const HavsFrameConstants fc = kbuffer_frame(b.threshold, b.max_gap);
        const KBufferResults r = h.run_kbuffer(fc, cs, HarnessShade::per_case);
        compare_kbuffer(fc, cs, r, nullptr, mm, t);
    }
    INFO(t.cases << " cases, " << t.killed << " killed, " << t.lookups << " lookups, " << t.zero_length
                 << " of zero length, " << t.max_length << " of the maximum length");
    CHECK(t.cases >= test::random_cases(1000000));
    CHECK(t.killed > test::random_cases(10000));
    CHECK(t.lookups > test::random_cases(100000));
    CHECK(t.zero_length > test::random_cases(10000));
    CHECK(t.max_length > test::random_cases(1000));
    mm.report("havs_kbuffer");
}

TEST_CASE("havs_kbuffer in GLSL with the table in a real 3D texture computes the emulation's bits (f32, u16, u8)")
{
    GlHavsFragmentHarness& h = *gl(GlPlatform::osmesa).harness;
    const TransferFunction tf = default_transfer_function(Range{0.0, 1.0}, 1.0);
    const SegmentIntegrator integrator(tf);
    const LlvmpipeCpu cpu = host_llvmpipe_cpu();
    Mismatches mm;
    KBufferTally t;
    uint64_t seed = 100;
    for (TexelFormat format : {TexelFormat::f32, TexelFormat::u16, TexelFormat::u8}) {
        const PreintegrationTable table = test::stage_test_table(integrator, format);
        HavsFrameConstants fc = kbuffer_frame(0.99f, 0.5f);
        fc.length_scale = table.length_scale();
        fc.length_bias = table.length_bias();
        const SegmentShader lookup = [&](float uf, float ub, float tz, float) { return table.sample(uf, ub, tz, cpu); };
        KBufferGen g(seed++, 0.5f);
        const KBufferCases cs = make_kbuffer_cases(g, 6, test::random_cases(200000), 0.99f);
        const KBufferResults r = h.run_kbuffer(fc, cs, HarnessShade::table, &table);
        compare_kbuffer(fc, cs, r, &lookup, mm, t);
    }
    INFO(t.lookups << " table lookups in " << t.cases << " cases (FMA3: " << cpu.fma << ")");
    CHECK(t.lookups > test::random_cases(100000));
    mm.report("havs_kbuffer with the table");
}

TEST_CASE("havs_fragment_entry in GLSL computes the emulation's bits on 1,200,000 random fragments")
{
    GlHavsFragmentHarness& h = *gl(GlPlatform::osmesa).harness;
    Mismatches mm, mm_double;
    uint64_t snapped = 0, transcription_off = 0, cases_total = 0, at_range_end = 0;
    uint64_t seed = 200;
    for (bool ortho : {false, true}) {
        EntryGen g(seed++, ortho);
        std::vector<HavsFace> faces;
        std::vector<glm::ivec2> pixels;
        while (faces.size() < test::random_cases(600000)) g.make(faces, pixels, 1 + std::size_t(g.pick(40)));
        const HavsFrameConstants fc = g.frame();
        std::vector<glm::dvec2> values;
        const std::vector<KEntry> r = h.run_entry(fc, faces, pixels, &values);
        for (std::size_t i = 0; i < faces.size(); ++i) {
            const KEntry e = havs_fragment_entry(fc, faces[i], pixels[i].x, pixels[i].y);
            mm.check(e.x, r[i].x, i, "entry x");
            mm.check(e.y, r[i].y, i, "entry distance");
            bool sn = false;
            const glm::dvec2 d = entry_values(fc, faces[i], pixels[i].x, pixels[i].y, sn);
            snapped += sn ? 1 : 0;
            // A fragment outside its triangle whose scalar is exactly 0 or 1: extrapolation left [0, 1] and the
            // encoding clamped it (havs_fragment_values), so both twins' clamps are compared here.
            const double m = std::fabs(d.x);
            const bool outside = havs_fragment_values(fc, faces[i], pixels[i].x, pixels[i].y).outside;
            at_range_end += outside && (m == 1.0 || m == 2.0 || m == 4.0 || m == 8.0 || m == 16.0 || m == 32.0);
            if (bits(float(d.x)) != bits(e.x) || bits(float(d.y)) != bits(e.y)) ++transcription_off;
            for (int c = 0; c < 2; ++c) mm_double.check(d[c], values[i][c], i, c ? "distance" : "x");
        }
        cases_total += faces.size();
    }
    INFO(cases_total << " fragments, " << snapped << " took the snapped weights, " << at_range_end
                      << " outside their triangle with the scalar clamped to 0 or 1");
    CHECK(cases_total >= test::random_cases(1000000));
    CHECK(snapped > test::random_cases(20000));
    CHECK(at_range_end > test::random_cases(20000));
    CHECK(transcription_off == 0);
    mm.report("havs_fragment_entry");
    mm_double.report("havs_fragment_values (double)");
}

TEST_CASE("havs_paper_entry in GLSL computes the emulation's bits on 1,000,000 random varyings")
{
    // --interpolation gpu: the paper's DP3/RSQ/MUL distance (or -z, orthographic), the clamped scalar's encoding and
    // the outside mark from the corner weights, on varyings of every magnitude: a distance whose square underflows
    // (flushed: 0, then 0 * inf = NaN) or overflows, a zero eye position, scalars outside [0, 1] and NaN, corner
    // weights of -0 and exactly 0, all three sides.
    GlHavsFragmentHarness& h = *gl(GlPlatform::osmesa).harness;
    Mismatches mm;
    uint64_t cases_total = 0, nan_distance = 0, outside = 0;
    test::CaseRng g(300);
    for (bool ortho : {false, true}) {
        HavsFrameConstants fc;
        fc.orthographic = ortho;
        std::vector<HavsVaryings> v(test::random_cases(500000));
        std::vector<glm::vec3> corners(v.size());
        const float sides[3] = {kSideExit, kSideInterior, kSideEntry};
        for (std::size_t i = 0; i < v.size(); ++i) {
            const int kind = g.pick(10);
            const float scale = kind == 0 ? 1e-21f : kind == 1 ? 1e19f : kind == 2 ? 0.0f : g.unif(0.01f, 100.0f);
            v[i].eye = glm::vec3(g.unif(-1.0f, 1.0f), g.unif(-1.0f, 1.0f), g.unif(-1.0f, 0.0f)) * scale;
            const int sk = g.pick(12);
            v[i].s = sk == 0 ? std::nanf("") : sk == 1 ? 0.0f : sk == 2 ? 1.0f : g.unif(-0.5f, 1.5f);
            v[i].side = sides[g.pick(3)];
            for (int c = 0; c < 3; ++c) {
                const int ck = g.pick(8);
                corners[i][c] = ck == 0 ? -0.0f : ck == 1 ? 0.0f : g.unif(-0.2f, 1.2f);
            }
        }
        const std::vector<glm::vec4> r = h.run_paper(fc, v, corners);
        const FlushDenormals llvmpipe_mxcsr;
        for (std::size_t i = 0; i < v.size(); ++i) {
            HavsVaryings vi = v[i];
            vi.side = havs_paper_side(v[i].side, corners[i]);
            const KEntry e = havs_paper_entry(fc, vi);
            mm.check(e.x, r[i].x, i, "entry x");
            mm.check(e.y, r[i].y, i, "entry distance");
            mm.check(vi.side, r[i].z, i, "side");
            nan_distance += std::isnan(e.y) ? 1 : 0;
            outside += vi.side == kSideOutside ? 1 : 0;
        }
        cases_total += v.size();
    }
    INFO(cases_total << " cases, " << nan_distance << " with a NaN distance, " << outside << " marked outside");
    CHECK(cases_total >= test::random_cases(1000000));
    CHECK(nan_distance > test::random_cases(10000));
    CHECK(outside > test::random_cases(50000));
    mm.report("havs_paper_entry");
}

#if defined(__x86_64__)
TEST_CASE("denormals: llvmpipe flushes them (DAZ and FTZ), and so does the emulated fragment stage")
{
    // llvmpipe runs shaders with the x86 MXCSR's denormals-are-zero and flush-to-zero bits set, whatever the thread
    // (LP_NUM_THREADS 0, 1, 2 alike). With gradual underflow the emulation would differ on colours with denormals and
    // on compositing that underflows ("as is" below, asserted to differ, so that a Mesa that stops flushing is
    // noticed); under FlushDenormals (gpu/pipeline/denormals.h), which the emulated driver sets around its fragment
    // stage, it computes the GL bits exactly. Denormal distances differ even then (llvmpipe also flushes some distances
    // the program only moves); the entry stage never produces them. docs/gl-backend.md.
    GlHavsFragmentHarness& h = *gl(GlPlatform::osmesa).harness;
    std::mt19937_64 rng(300);
    auto uni = [&](float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); };
    auto tiny = [&] { return std::ldexp(uni(0.0f, 1.0f), -126 - int(rng() % 24)); };  // denormals, some zero
    HavsFrameConstants fc = kbuffer_frame(1.0f, 0.5f);
    const char* names[4] = {"denormal segment colours", "denormal framebuffer colours", "underflowing compositing",
                            "denormal distances"};
    std::ostringstream measured;
    for (int family = 0; family < 4; ++family) {
        KBufferGen g(301 + uint64_t(family), 0.5f);
        KBufferCases cs = make_kbuffer_cases(g, 2, 50000, 1.0f);
        for (std::size_t i = 0; i < cs.size(); ++i) {
            if (family == 0) cs.shade[i] = {tiny(), tiny(), uni(0.0f, 1.0f), tiny()};
            if (family == 1) cs.framebuffer[i] = {tiny(), tiny(), tiny(), uni(0.0f, 0.9f)};
            if (family == 2) {  // c (1 - alpha) below 2^-126
                cs.shade[i] = glm::vec4(std::ldexp(1.0f, -100 - int(rng() % 20)));
                cs.framebuffer[i] = {0.0f, 0.0f, 0.0f, 1.0f - std::ldexp(1.0f, -int(rng() % 24) - 1)};
            }
            if (family == 3) {
                cs.incoming[i].y = tiny() * 4.0f;
                cs.entries[2 * i].y = tiny() * 4.0f;
            }
        }
        const KBufferResults r = h.run_kbuffer(fc, cs, HarnessShade::per_case);
        Mismatches plain, flushed;
        KBufferTally t1, t2;
        compare_kbuffer(fc, cs, r, nullptr, plain, t1);
        {
            const FlushDenormals as_the_renderer_runs;
            compare_kbuffer(fc, cs, r, nullptr, flushed, t2);
        }
        measured << names[family] << ": " << plain.summary("as is") << "; " << flushed.summary("under DAZ and FTZ")
                 << "\n";
        INFO(names[family]);
        CHECK(plain.count > 0);  // llvmpipe does flush (a Mesa that stops changes docs/gl-backend.md)
        if (family < 3) flushed.report("the emulation under DAZ and FTZ");
    }
    WARN("measured on 50,000 cases each (k = 2):\n" << measured.str());
}
#endif

TEST_CASE("EGL: the surfaceless (or device) context runs the same shaders and computes the same bits")
{
    Gl& e = gl(GlPlatform::egl);
    INFO(e.ctx->info().summary());
    CHECK_THAT(e.ctx->info().version, Catch::StartsWith("4.5"));
    Mismatches mm;
    KBufferTally t;
    KBufferGen g(400, 0.5f);
    const KBufferCases cs = make_kbuffer_cases(g, 6, 100000, 0.99f);
    const HavsFrameConstants fc = kbuffer_frame(0.99f, 0.5f);
    compare_kbuffer(fc, cs, e.harness->run_kbuffer(fc, cs, HarnessShade::per_case), nullptr, mm, t);
    EntryGen eg(401, false);
    std::vector<HavsFace> faces;
    std::vector<glm::ivec2> pixels;
    while (faces.size() < 100000) eg.make(faces, pixels, 1 + std::size_t(eg.pick(40)));
    const HavsFrameConstants efc = eg.frame();
    const std::vector<KEntry> r = e.harness->run_entry(efc, faces, pixels);
    for (std::size_t i = 0; i < faces.size(); ++i) {
        const KEntry x = havs_fragment_entry(efc, faces[i], pixels[i].x, pixels[i].y);
        mm.check(x.x, r[i].x, i, "entry x");
        mm.check(x.y, r[i].y, i, "entry distance");
    }
    mm.report("EGL: havs_kbuffer and havs_fragment_entry");
}
