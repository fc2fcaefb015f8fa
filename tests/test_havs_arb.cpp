// The paper's own ARB programs as a witness (docs/spec.md §7: --backend arb): their text is the paper's but
// for three repairs of the print; the fragment program computes the emulated k-buffer program's bits (--entries paper)
// on a million random cases; and whole frames through them equal the GLSL driver's and the emulation's.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <regex>

#include "bit_compare.h"
#include "case_rng.h"
#include "gl_frames.h"
#include "gpu/havs/gl_havs.h"
#include "gpu/havs/gl_havs_arb.h"
#include "gpu/gl/gl_harness_pass.h"
#include "gpu/havs/gl_havs_harness.h"
#include "mesh_scenes.h"
#include "reference/error.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;
using test::Scene;

namespace {

GlContext& compat()
{
    // Never destroyed, as gl_harness.h's contexts: Mesa's exit handlers may run before a static's destructor.
    static GlContext* const ctx = new GlContext(GlPlatform::osmesa, GlProfile::compatibility);
    ctx->make_current();
    return *ctx;
}

// The paper's appendices as printed (data/havs-paper/appendices.md): the vertex program is the first code block, the
// fragment program the other three (the print breaks it across pages).
std::pair<std::string, std::string> paper_programs()
{
    const std::string text = test::file_contents(test::data_path("havs-paper/appendices.md"));
    const std::regex block("```\n([\\s\\S]*?)```");
    std::vector<std::string> blocks;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), block); it != std::sregex_iterator(); ++it)
        blocks.push_back((*it)[1].str());
    REQUIRE(blocks.size() == 4);
    return {blocks[0], blocks[1] + blocks[2] + blocks[3]};
}

// Replaces the one occurrence of `from` in `s` (REQUIREs that there is exactly one).
void repair(std::string& s, const std::string& from, const std::string& to)
{
    const std::size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    REQUIRE(s.find(from, at + 1) == std::string::npos);
    s.replace(at, from.size(), to);
}

HavsOptions paper_options()
{
    HavsOptions o;
    o.k = kArbK;
    o.entries = EntryEncoding::paper;
    return o;
}

}  // namespace

TEST_CASE("the ARB programs are the paper's appendices but for three repairs of the print")
{
    auto [vp, fp] = paper_programs();
    SECTION("the printed vertex program does not load; the header repaired, it is shaders/havs_paper.vp")
    {
        const auto arb = load_arb_functions(compat());
        CHECK_THROWS_WITH(ArbProgram(compat(), *arb, arb::kVertexProgram, "printed", vp),
                          Catch::Matchers::Contains("does not load"));
        repair(vp, "!!ARBvpl.0", "!!ARBvp1.0");
        CHECK(vp == read_shader_file("havs_paper.vp"));
    }
    SECTION("the fragment program with the kill's SUB and the write-back's swizzles repaired is shaders/havs_paper.fp")
    {
        repair(fp, "SUB t.w, t, 0.99, c0.w;", "SUB t.w, 0.99, c0.w;");
        for (const char* pair : {"r1.zw, r2", "r3.zw, r4", "r5.zw, r6"})
            repair(fp, std::string("MOV ") + pair + ".xxy;", std::string("MOV ") + pair + ".xxxy;");
        CHECK(fp == read_shader_file("havs_paper.fp"));
    }
}

namespace {

// Random cases for the paper's k-buffer program: stored entries with ties, empty entries (-1, 0), flush entries at
// 2^60 and +inf, negative and out-of-range scalars; incoming fragments whose distance ties a stored one; framebuffer
// alphas at, just below and just above the kill's 0.99.
ArbKBufferCases make_arb_cases(test::CaseRng& g, std::size_t n, const HavsFrameConstants& fc)
{
    ArbKBufferCases c;
    c.scalar.resize(n);
    c.eye.resize(n);
    c.entries.resize(n * kArbK);
    c.framebuffer.resize(n);
    const float alphas[] = {0.99f, std::nextafter(0.99f, 1.0f), std::nextafter(0.99f, 0.0f), 0.0f, 1.0f};
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 dir = glm::vec3(g.vec(1.0)) + glm::vec3(0.0f, 0.0f, -1.5f);
        c.eye[i] = dir * g.unif(0.05f, 3.0f);
        c.scalar[i] = g.pick(8) == 0 ? paper_exit_scalar(g.unif(0.0f, 1.0f)) : g.unif(-0.25f, 1.25f);
        const float incoming = havs_paper_entry(fc, HavsVaryings{c.eye[i], c.scalar[i], kSideInterior}).y;
        KEntry* a = &c.entries[i * kArbK];
        for (int e = 0; e < kArbK; ++e) {
            switch (g.pick(10)) {
            case 0: a[e] = kEmptyEntry; break;
            case 1:
                a[e] = kPaperFlushFragment;
                break;
            case 2: a[e] = KEntry{g.unif(-0.25f, 1.25f), std::numeric_limits<float>::infinity()}; break;
            case 3: a[e] = KEntry{g.unif(-0.25f, 1.25f), incoming}; break;                 // a tie with the fragment
            case 4: a[e] = e > 0 ? KEntry{g.unif(-0.25f, 1.25f), a[g.pick(e)].y} : kEmptyEntry; break;  // a tie
            case 5:
                a[e] = KEntry{paper_exit_scalar(g.unif(0.0f, 1.0f)), g.unif(0.0f, 5.0f)};
                break;
            default: a[e] = KEntry{g.unif(-0.25f, 1.25f), g.unif(0.0f, 5.0f)}; break;
            }
        }
        const float alpha = g.pick(4) == 0 ? alphas[g.pick(5)] : g.unif(0.0f, 1.0f);
        c.framebuffer[i] = glm::vec4(g.unif(0.0f, 1.0f), g.unif(0.0f, 1.0f), g.unif(0.0f, 1.0f), alpha);
    }
    return c;
}

// What both stage tests share: the harness, a small f32 table on texture 4, and the program's constants.
struct ArbStage {
    GlHavsArbHarness harness{compat()};
    TransferFunction tf = default_transfer_function(Range{0.0, 1.0}, 1.0);
    SegmentIntegrator integrator{tf};
    PreintegrationTable table = test::stage_test_table(integrator, TexelFormat::f32);
    LlvmpipeCpu cpu = host_llvmpipe_cpu();
    HavsFrameConstants fc = [this] {
        HavsFrameConstants c;
        c.paper_entries = true;
        c.threshold = 0.99f;
        c.length_scale = table.length_scale();
        c.length_bias = table.length_bias();
        return c;
    }();
    SegmentShader shade = [this](float uf, float ub, float tz, float) { return table.sample(uf, ub, tz, cpu); };
    ArbKBufferResults run(const ArbKBufferCases& cases) { return harness.run(table, fc.length_scale, fc.length_bias, cases); }
};

}  // namespace

TEST_CASE("the paper's ARB fragment program computes the emulated k-buffer program's bits on 1,048,576 random cases")
{
    ArbStage st;
    const HavsFrameConstants& fc = st.fc;
    const SegmentShader& shade = st.shade;

    test::CaseRng g(2024);
    const std::size_t n = std::size_t(4) * kHarnessWidth * kHarnessRows;
    const ArbKBufferCases cases = make_arb_cases(g, n, fc);
    const ArbKBufferResults r = st.run(cases);

    test::Mismatches mm;
    std::size_t killed = 0, composited = 0, ties = 0;
    for (std::size_t i = 0; i < n; ++i) {
        KEntry a[kArbK];
        std::copy(&cases.entries[i * kArbK], &cases.entries[i * kArbK] + kArbK, a);
        glm::vec4 fb = cases.framebuffer[i];
        const KEntry a0 = havs_paper_entry(fc, HavsVaryings{cases.eye[i], cases.scalar[i], kSideInterior});
        for (const KEntry& e : a) ties += e.y == a0.y ? 1 : 0;
        if (!havs_kbuffer(fc, a0, a, kArbK, fb, shade, nullptr)) ++killed;
        composited += fb != cases.framebuffer[i] ? 1 : 0;
        for (int c = 0; c < 4; ++c) mm.check(fb[c], r.framebuffer[i][c], i, "colour");
        for (int e = 0; e < kArbK; ++e) {
            mm.check(a[e].x, r.entries[i * kArbK + std::size_t(e)].x, i, "entry x");
            mm.check(a[e].y, r.entries[i * kArbK + std::size_t(e)].y, i, "entry distance");
        }
    }
    INFO(n << " cases: " << killed << " killed, " << composited << " changed the colour, " << ties
           << " stored entries tie the fragment (FMA3: " << st.cpu.fma << ")");
    CHECK(killed > 10000);
    CHECK(composited > 100000);
    CHECK(ties > 10000);
    mm.report("the paper's ARB fragment program");
}

namespace {

// `cam` through the three drivers with --entries paper: ARB (with `per_draw` triangles a draw, and a texture barrier
// after each draw when `barrier`), GLSL and the emulation, bit for bit.
void require_arb_identical(const Scene& s, const Camera& cam, int width, int height, std::size_t per_draw, bool barrier)
{
    const HavsOptions o = paper_options();
    const HavsFrame emu = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, width, height);
    const HavsFrame glsl = GlHavsRenderer(test::osmesa(), s.mesh, s.topo, s.field, s.tf, o, false).render(cam, width,
                                                                                                           height);
    ArbHavsRenderer arb(compat(), s.mesh, s.topo, s.field, s.tf, o);
    arb.set_triangles_per_draw(per_draw);
    arb.set_barrier_after_each_draw(barrier);
    const HavsFrame frame = arb.render(cam, width, height);
    const auto none = [](std::size_t) { return false; };
    const auto nothing = [](std::size_t) { return std::string(); };
    const test::FrameDiff d_emu = test::diff_frames(frame.image, emu.image, none, nothing);
    const test::FrameDiff d_glsl = test::diff_frames(frame.image, glsl.image, none, nothing);
    INFO(width << " x " << height << ", view " << cam.eye.x << " " << cam.eye.y << " " << cam.eye.z << ", "
               << frame.stats.draws << " draws, barrier " << barrier << ": " << emu.stats.fragments
               << " fragments (emulation)");
    INFO("ARB vs emulation: " << d_emu.differing << " of " << d_emu.pixels << " pixels differ; " << d_emu.first);
    INFO("ARB vs GLSL: " << d_glsl.differing << " pixels differ; " << d_glsl.first);
    REQUIRE(emu.stats.fragments > 0);
    CHECK(emu.stats.gpu_clipped == 0);
    CHECK(d_emu.differing == 0);
    CHECK(d_glsl.differing == 0);
}

}  // namespace

TEST_CASE("uvr's --backend arb frames equal the GLSL driver's and the emulation's with --entries paper")
{
    SECTION("the built-in torus, one draw and many draws with texture barriers")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        for (const auto& [az, el] : {std::pair{0.0, 0.0}, {35.0, 40.0}})
            require_arb_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 96, 80, 0, false);
        require_arb_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 120.0, -20.0), 96, 80, 700, true);
    }
    SECTION("Blunt Fin")
    {
        const Scene s = test::blunt_fin();
        require_arb_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 20.0), 128, 96, 0, false);
    }
    SECTION("a view from inside the mesh (the clip stage's fans and near-plane sections)")
    {
        const Scene s = test::blunt_fin();
        require_arb_identical(s, test::inside_view(s), 96, 96, 0, false);
    }
}

TEST_CASE("the ARB backend refuses what the paper's programs cannot run, naming the option")
{
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    HavsOptions o = paper_options();
    SECTION("k other than 6")
    {
        o.k = 8;
        CHECK_THROWS_WITH(ArbHavsRenderer(compat(), s.mesh, s.topo, s.field, s.tf, o), Catch::Matchers::Contains("k is 6"));
    }
    SECTION("uvr's marked entries")
    {
        o.entries = EntryEncoding::marked;
        CHECK_THROWS_WITH(ArbHavsRenderer(compat(), s.mesh, s.topo, s.field, s.tf, o),
                          Catch::Matchers::Contains("--entries paper"));
    }
    SECTION("another kill threshold")
    {
        o.threshold = 0.9f;
        CHECK_THROWS_WITH(ArbHavsRenderer(compat(), s.mesh, s.topo, s.field, s.tf, o),
                          Catch::Matchers::Contains("--threshold 0.99"));
    }
    SECTION("an orthographic view")
    {
        ArbHavsRenderer arb(compat(), s.mesh, s.topo, s.field, s.tf, o);
        Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 0.0, 0.0);
        cam.orthographic = true;
        cam.ortho_height = 2.0;
        CHECK_THROWS_WITH(arb.render(cam, 32, 32), Catch::Matchers::Contains("perspective camera"));
    }
    SECTION("a core-profile context")
    {
        CHECK_THROWS_WITH(ArbHavsRenderer(test::osmesa(), s.mesh, s.topo, s.field, s.tf, o),
                          Catch::Matchers::Contains("compatibility-profile context"));
    }
}

namespace {

// llvmpipe's fmin and fmax (gallivm's lp_build_min_ext / max_ext with GALLIVM_NAN_RETURN_OTHER): a NaN second operand
// yields the first, else x86's minps / maxps (a < b ? a : b, a > b ? a : b), which yield b when a is NaN.
float lp_fmin(float a, float b) { return std::isnan(b) ? a : (a < b ? a : b); }
float lp_fmax(float a, float b) { return std::isnan(b) ? a : (a > b ? a : b); }

// The paper's fragment program as Mesa compiles it for llvmpipe (docs/havs-arb.md "Compilation"): the ARB instructions
// are not exact, so NIR turns each SUB + CMP pair's distance channel, bcsel(a < b, a, b) and bcsel(a < b, b, a), into
// fmin and fmax; the other channels keep the select on a < b. Identical to havs_kbuffer unless a distance is NaN.
bool paper_program_on_llvmpipe(const HavsFrameConstants& fc, KEntry a0, KEntry* a, glm::vec4& fb,
                               const SegmentShader& shade)
{
    if (fc.threshold - fb.a < 0.0f) return false;
    KEntry r[kArbK + 1];
    r[0] = a0;
    for (int i = 1; i <= kArbK; ++i) {
        const KEntry ai = a[i - 1];
        const bool less = r[0].y < ai.y;
        r[i] = KEntry{less ? ai.x : r[0].x, lp_fmax(r[0].y, ai.y)};
        r[0] = KEntry{less ? r[0].x : ai.x, lp_fmin(ai.y, r[0].y)};
    }
    KEntry r7{r[1].y < r[2].y ? r[1].x : r[2].x, lp_fmin(r[2].y, r[1].y)};
    for (int i = 3; i <= kArbK; ++i) r7 = KEntry{r7.y < r[i].y ? r7.x : r[i].x, lp_fmin(r[i].y, r7.y)};
    const float length = r7.y - r[0].y;
    const glm::vec4 c =
        r[0].x < 0.0f ? glm::vec4(0.0f) : shade(r[0].x, r7.x, length * fc.length_scale + fc.length_bias, length);
    const float one_minus_a = 1.0f - fb.a;
    fb = glm::vec4(c.r * one_minus_a + fb.r, c.g * one_minus_a + fb.g, c.b * one_minus_a + fb.b,
                   c.a * one_minus_a + fb.a);
    for (int i = 1; i <= kArbK; ++i) a[i - 1] = r[i];
    return true;
}

}  // namespace

TEST_CASE("the paper's ARB fragment program on special values: differences only at NaN distances, from NIR's fmin/fmax")
{
    ArbStage st;
    const HavsFrameConstants& fc = st.fc;
    const SegmentShader& shade = st.shade;
    test::CaseRng g(77);
    const std::size_t n = std::size_t(kHarnessWidth) * kHarnessRows;
    ArbKBufferCases cases = make_arb_cases(g, n, fc);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < n; ++i) {
        switch (g.pick(6)) {
        case 0: cases.eye[i] = glm::vec3(0.0f); break;                   // |e| = 0: 0 * (1 / sqrt 0) = 0 * inf = NaN
        case 1: cases.eye[i] = glm::vec3(3e19f, 0.0f, -1.0f); break;     // e.e overflows: inf * (1 / inf) = NaN
        case 2: cases.eye[i] = glm::vec3(1e-39f, -2e-39f, 0.0f); break;  // denormal squares, flushed: NaN as well
        case 3: cases.scalar[i] = -0.0f; break;                          // reaches the program as +0
        case 4: cases.entries[i * kArbK + std::size_t(g.pick(kArbK))].y = nan; break;
        default: cases.entries[i * kArbK + std::size_t(g.pick(kArbK))].x = -0.0f; break;
        }
    }
    const ArbKBufferResults r = st.run(cases);
    test::Mismatches with_nan, without_nan, model;
    std::size_t nan_cases = 0;
    for (std::size_t i = 0; i < n; ++i) {
        KEntry a[kArbK], m[kArbK];
        std::copy(&cases.entries[i * kArbK], &cases.entries[i * kArbK] + kArbK, a);
        std::copy(a, a + kArbK, m);
        glm::vec4 fb = cases.framebuffer[i], fb_model = fb;
        // The point's constant attribute arrives as a0 + 0 x + 0 y: a -0 scalar as +0 (what `+ 0.0f` gives).
        const float received = cases.scalar[i] + 0.0f;
        const KEntry a0 = havs_paper_entry(fc, HavsVaryings{cases.eye[i], received, kSideInterior});
        havs_kbuffer(fc, a0, a, kArbK, fb, shade, nullptr);
        paper_program_on_llvmpipe(fc, a0, m, fb_model, shade);
        bool any_nan = std::isnan(a0.y);
        for (int e = 0; e < kArbK; ++e) any_nan = any_nan || std::isnan(cases.entries[i * kArbK + std::size_t(e)].y);
        nan_cases += any_nan ? 1 : 0;
        test::Mismatches& mm = any_nan ? with_nan : without_nan;
        for (int c = 0; c < 4; ++c) {
            mm.check(fb[c], r.framebuffer[i][c], i, "colour");
            model.check(fb_model[c], r.framebuffer[i][c], i, "colour (model)");
        }
        for (int e = 0; e < kArbK; ++e) {
            const KEntry& w = r.entries[i * kArbK + std::size_t(e)];
            mm.check(a[e].x, w.x, i, "entry x");
            mm.check(a[e].y, w.y, i, "entry distance");
            model.check(m[e].x, w.x, i, "entry x (model)");
            model.check(m[e].y, w.y, i, "entry distance (model)");
        }
    }
    INFO(nan_cases << " of " << n << " cases hold a NaN distance; the emulation differs from the ARB program on "
                   << with_nan.count << " of their values");
    CHECK(nan_cases > 100000);
    CHECK(with_nan.count > 0);  // the rewrite is real: without it the explanation below would be untested
    without_nan.report("the ARB program where no distance is NaN (the emulation)");
    model.report("the ARB program as NIR's fmin/fmax rewrite predicts it (every case)");
}

TEST_CASE("uvr render --backend arb writes the paper's frame and reports its entries, and refuses misuse")
{
    using test::run_uvr;
    test::TempDir tmp("arb");
    SECTION("the frame equals --backend emu --entries paper, bit for bit, and the JSON says paper")
    {
        const std::string arb = tmp.file("arb.npy"), emu = tmp.file("emu.npy");
        const auto r = run_uvr("render builtin:torus-small --algo havs --backend arb --size 48x40 --json --out '" +
                               arb + "'");
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        CHECK_THAT(r.out, Catch::Contains("\"entries\": \"paper\""));
        REQUIRE(run_uvr("render builtin:torus-small --algo havs --entries paper --size 48x40 --out '" + emu + "'")
                    .exit_code == 0);
        CHECK(test::file_contents(arb) == test::file_contents(emu));
    }
    SECTION("with VICP, with k = 8, with EGL, and with --diagnostics")
    {
        const auto vicp = run_uvr("render builtin:torus-small --algo vicp --backend arb --out '" + tmp.file("v.npy") + "'");
        CHECK(vicp.exit_code != 0);
        CHECK_THAT(vicp.err, Catch::Contains("--backend must be one of emu, gl with --algo vicp"));
        const auto k8 = run_uvr("render builtin:torus-small --algo havs --backend arb --k 8 --out '" + tmp.file("k.npy") + "'");
        CHECK(k8.exit_code != 0);
        CHECK_THAT(k8.err, Catch::Contains("k is 6"));
        const auto egl = run_uvr("render builtin:torus-small --algo havs --backend arb --gl egl --out '" +
                                 tmp.file("e.npy") + "'");
        CHECK(egl.exit_code != 0);
        CHECK_THAT(egl.err, Catch::Contains("--gl osmesa"));
        const auto diag = run_uvr("render builtin:torus-small --algo havs --backend arb --diagnostics '" +
                                  tmp.file("d") + "' --out '" + tmp.file("d.npy") + "'");
        CHECK(diag.exit_code != 0);
        CHECK_THAT(diag.err, Catch::Contains("no per-pixel diagnostics"));
    }
    SECTION(
        "--entries paper without the paper's interpolation or with VTK's gaps, an unknown encoding, the old spelling")
    {
        const std::string out = " --out '" + tmp.file("n.npy") + "'";
        const auto exact =
            run_uvr("render builtin:torus-small --algo havs --entries paper --interpolation exact" + out);
        CHECK(exact.exit_code != 0);
        CHECK_THAT(exact.err, Catch::Contains("--entries paper needs the paper's interpolation"));
        const auto maxgap = run_uvr("render builtin:torus-small --algo havs --entries paper --gaps maxgap" + out);
        CHECK(maxgap.exit_code != 0);
        CHECK_THAT(maxgap.err, Catch::Contains("no maximum-gap rule"));
        const auto other = run_uvr("render builtin:torus-small --algo havs --entries sided" + out);
        CHECK(other.exit_code != 0);
        CHECK_THAT(other.err, Catch::Contains("--entries must be marked or paper, not 'sided'"));
        // The spelling the option had before is refused with the one that replaced it.
        const auto old = run_uvr("render builtin:torus-small --algo havs --entries seed" + out);
        CHECK(old.exit_code == 1);
        CHECK_THAT(old.err, Catch::Contains("--entries seed is now spelled --entries paper"));
        CHECK(!std::filesystem::exists(tmp.file("n.npy")));
    }
}
