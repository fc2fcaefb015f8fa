// VICP's vertex and fragment programs in GLSL (shaders/vicp_vertex.vert, shaders/vicp_fragment.frag) against their
// emulations (gpu/vicp/vicp_vertex.cpp, gpu/vicp/vicp_fragment.cpp), bit for bit, through the VICP stage harness
// (gpu/vicp/gl_vicp_harness.h) under OSMesa (llvmpipe). docs/spec.md §5 (stage level): at least a million random inputs
// per stage, with exact ties, zero-length segments, opacities at the kill threshold, flat and sliver cells, faces the
// ray runs along. The emulation runs with denormals flushed, as llvmpipe runs shaders and as the emulated driver runs.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bit_compare.h"
#include "case_rng.h"
#include "gl_harness.h"
#include "test_support.h"
#include "box_mesh.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/vicp/gl_vicp_harness.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/vicp/vicp_setup.h"
#include "mesh_scenes.h"

using namespace uvr;
using namespace uvr::gpu;
using test::Mismatches;
using test::Scene;

namespace {

using Gl = test::GlHarness<GlVicpHarness>;
Gl& gl(GlPlatform p) { return test::gl_harness<GlVicpHarness>(p); }

// ---- vertex cases ----

// Tetrahedra of every size and place: the exact cell, and its shape as snapping moves it (each point by up to a
// thousandth of the cell's size, or not at all); slivers (a point near the plane of the others), flat cells (a point
// repeated: det 0, divisions by zero), scalars with ties and at 0 and 1, every boundary mask.
struct VertexGen : test::CaseRng {
    explicit VertexGen(uint64_t seed) : CaseRng(seed) {}

    VicpVertexCase make()
    {
        VicpVertexCase c;
        const double scales[5] = {1e-6, 1e-3, 1.0, 10.0, 1e4};
        const double size = scales[pick(5)], place = scales[pick(5)] * 10.0;
        const glm::dvec3 p0 = vec(place);
        for (int i = 0; i < 4; ++i) c.exact[i] = p0 + (i ? vec(size) : glm::dvec3(0.0));
        const int kind = pick(20);
        if (kind == 0) c.exact[3] = c.exact[pick(3)];  // flat
        if (kind == 1) {                                // sliver
            const glm::dvec3 w(uni(0, 1), uni(0, 1), uni(0, 1));
            c.exact[3] = (w.x * c.exact[0] + w.y * c.exact[1] + w.z * c.exact[2]) / (w.x + w.y + w.z) +
                         vec(size * 1e-9);
        }
        const double moved = pick(3) == 0 ? 0.0 : size * 1e-3;
        for (int i = 0; i < 4; ++i) c.shape[i] = c.exact[i] + (moved > 0.0 ? vec(moved) : glm::dvec3(0.0));
        for (int i = 0; i < 4; ++i) {
            const int s = pick(8);
            c.s[i] = s == 0 ? 0.0 : s == 1 ? 1.0 : s == 2 && i ? c.s[0] : uni(0.0, 1.0);
        }
        c.boundary = uint32_t(pick(16));
        return c;
    }
};

void compare_tets(const VicpTet& e, const VicpTet& g, std::size_t c, Mismatches& mm)
{
    for (int j = 0; j < 3; ++j) {
        mm.check(e.p0[j], g.p0[j], c, "p0");
        mm.check(e.base[j], g.base[j], c, "base");
        mm.check(e.g[j], g.g[j], c, "g");
        for (int i = 0; i < 3; ++i) {
            mm.check(e.m[i][j], g.m[i][j], c, "m");
            mm.check(e.me[i][j], g.me[i][j], c, "me");
        }
    }
    mm.check(e.det, g.det, c, "det");
    mm.check(e.s0, g.s0, c, "s0");
    mm.check(double(e.boundary), double(g.boundary), c, "boundary");
}

// ---- fragment-value cases, from real frames ----

// Every fragment the rasterizer makes for the cells of a real frame (the renderer's own inputs: constants from the
// snapped points, the pixels the front faces cover), and about one pixel in five elsewhere near the cell (rays that
// miss it: segments of no length). Every other case has its boundary mask replaced by a random one, so that both the
// snapped planes and the exact ones meet every kind of ray.
struct ValueCases {
    VicpFrameConstants fc;
    std::vector<VicpTet> tets;
    std::vector<glm::ivec2> pixels;
};

ValueCases frame_value_cases(const Scene& s, const Camera& cam, int size, std::size_t want, uint64_t seed)
{
    std::mt19937_64 rng(seed);
    const VicpMesh vm(s.mesh, s.topo, s.field, s.tf, VicpOptions{});
    const VicpFrameSetup fs = setup_vicp_frame(vm, cam, size, size);
    ValueCases vc;
    vc.fc = fs.constants;
    const Framebuffer fbuf{size, size, RenderTarget::fbo};
    // Cells in a shuffled order, so that a capped set still spans the frame.
    std::vector<std::size_t> slots(fs.stream.size());
    for (std::size_t i = 0; i < slots.size(); ++i) slots[i] = i;
    std::shuffle(slots.begin(), slots.end(), rng);
    for (std::size_t slot : slots) {
        if (vc.tets.size() >= want) break;
        const VicpCell& cell = fs.stream[slot];
        VicpTet tet = vm.constants(cell, fs.snapped);
        float x0 = 1e30f, x1 = -1e30f, y0 = 1e30f, y1 = -1e30f;
        for (int f = 0; f < 4; ++f) {
            WindowCoord wv[3];
            for (int j = 0; j < 3; ++j) {
                wv[j] = fs.win[cell.v[std::size_t(kVicpCorner[f][j])]];
                x0 = std::min(x0, wv[j].x), x1 = std::max(x1, wv[j].x);
                y0 = std::min(y0, wv[j].y), y1 = std::max(y1, wv[j].y);
            }
            const TriangleSetup ts = setup_triangle(wv, fbuf);
            if (ts.empty() || ts.facing != Facing::front) continue;
            rasterize_triangle(wv, fbuf, [&](int x, int y) {
                if (rng() % 2 == 0) tet.boundary = uint32_t(rng() % 16);
                else tet.boundary = cell.boundary;
                vc.tets.push_back(tet);
                vc.pixels.push_back({x, y});
                if (rng() % 5 == 0) {
                    vc.tets.push_back(tet);
                    vc.pixels.push_back({int(x0) - 2 + int(rng() % uint64_t(x1 - x0 + 5.0f)),
                                         int(y0) - 2 + int(rng() % uint64_t(y1 - y0 + 5.0f))});
                }
            });
        }
    }
    return vc;
}

// ---- composite cases ----

struct CompositeGen : test::CaseRng {
    explicit CompositeGen(uint64_t seed) : CaseRng(seed) {}

    VicpCompositeCase make(float threshold)
    {
        VicpCompositeCase c;
        VicpSegment& s = c.segment;
        s.s_front = pick(6) == 0 ? double(pick(2)) : uni(0.0, 1.0);
        s.s_back = pick(6) == 0 ? s.s_front : pick(6) == 0 ? double(pick(2)) : uni(0.0, 1.0);
        s.t_in = uni(0.5, 20.0);
        switch (pick(8)) {
        case 0: s.length = 0.0; break;                          // a ray that grazes the cell
        case 1: s.length = -uni(0.0, 1.0); break;              // a ray that misses it (covered by snapping)
        case 2: s.length = std::ldexp(uni(0.5, 1.0), -160 + pick(40)); break;  // rounds to float 0 or a denormal
        case 3: s.length = uni(2.0, 5.0); break;               // beyond the table's longest segment
        default: s.length = uni(0.0, 2.0);
        }
        s.t_out = s.t_in + s.length;
        float a;
        switch (pick(8)) {
        case 0: a = threshold; break;
        case 1: a = std::nextafter(threshold, 2.0f); break;
        case 2: a = std::nextafter(threshold, -1.0f); break;
        case 3: a = float(pick(2)); break;
        default: a = unif(0.0f, 1.0f);
        }
        c.framebuffer = {unif(0.0f, 1.0f) * a, unif(0.0f, 1.0f) * a, unif(0.0f, 1.0f) * a, a};
        // Diagnostics: the farthest segment so far ends where this one does, or begins there (ties), or elsewhere.
        VicpDiagnostics& d = c.diagnostics;
        d.fragments = uint32_t(pick(1000));
        d.ordering_errors = uint32_t(pick(3));
        const float back = float(s.t_out), front = float(s.t_in);
        switch (pick(5)) {
        case 0: d.last_front = back, d.last_back = back + 1.0f; break;
        case 1: d.last_back = back, d.last_front = front; break;
        case 2: d.last_back = front, d.last_front = front - 1.0f; break;
        default: d.last_front = unif(0.0f, 20.0f), d.last_back = d.last_front + unif(0.0f, 2.0f);
        }
        const float ca = pick(10) == 0 ? float(pick(2)) : unif(0.0f, 1.0f);
        c.shade = {unif(0.0f, 1.0f) * ca, unif(0.0f, 1.0f) * ca, unif(0.0f, 1.0f) * ca, ca};
        return c;
    }
};

struct CompositeTally {
    uint64_t cases = 0, killed = 0, lookups = 0, no_length = 0, ordering_errors = 0;
};

void compare_composite(const VicpFrameConstants& fc, const std::vector<VicpCompositeCase>& cs,
                       const std::vector<VicpCompositeResult>& glr, const SegmentShader* table_shader, Mismatches& mm,
                       CompositeTally& t)
{
    const FlushDenormals as_the_renderer_runs;
    for (std::size_t c = 0; c < cs.size(); ++c) {
        glm::vec4 fb = cs[c].framebuffer, args(-2.0f);
        VicpDiagnostics d = cs[c].diagnostics;
        const SegmentShader shade = [&](float uf, float ub, float tz, float len) {
            args = glm::vec4(uf, ub, tz, len);
            return table_shader ? (*table_shader)(uf, ub, tz, len) : cs[c].shade;
        };
        const bool written = vicp_composite(fc, cs[c].segment, fb, shade, &d);
        ++t.cases;
        t.killed += written ? 0 : 1;
        t.lookups += args.x != -2.0f ? 1 : 0;
        t.no_length += written && args.x == -2.0f ? 1 : 0;
        t.ordering_errors += d.ordering_errors > cs[c].diagnostics.ordering_errors ? 1 : 0;
        const VicpCompositeResult& r = glr[c];
        mm.check(written ? 1.0f : 0.0f, r.written ? 1.0f : 0.0f, c, "written");
        for (int ch = 0; ch < 4; ++ch) {
            mm.check(fb[ch], r.framebuffer[ch], c, "framebuffer");
            mm.check(args[ch], r.shade_args[ch], c, "lookup argument");
        }
        mm.check(float(d.fragments), float(r.diagnostics.fragments), c, "fragments");
        mm.check(float(d.ordering_errors), float(r.diagnostics.ordering_errors), c, "ordering errors");
        mm.check(d.last_back, r.diagnostics.last_back, c, "last back");
        mm.check(d.last_front, r.diagnostics.last_front, c, "last front");
    }
}

VicpFrameConstants composite_frame(float threshold)
{
    VicpFrameConstants fc;
    fc.threshold = threshold;
    fc.length_scale = (1.0f - 1.0f / 128.0f) / 3.0f;
    fc.length_bias = 1.0f / 256.0f;
    return fc;
}

}  // namespace

TEST_CASE("VICP's vertex program in GLSL computes the emulation's bits on 1,000,000 random tetrahedra")
{
    GlVicpHarness& h = *gl(GlPlatform::osmesa).harness;
    VertexGen g(1);
    std::vector<VicpVertexCase> cases(test::random_cases(1000000));
    for (auto& c : cases) c = g.make();
    const std::vector<VicpTet> r = h.run_vertex(cases);
    Mismatches mm;
    uint64_t flat = 0;
    const FlushDenormals as_the_renderer_runs;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const VicpTet e = vicp_tet_constants(cases[i].shape, cases[i].exact, cases[i].s, cases[i].boundary);
        flat += e.det == 0.0 ? 1 : 0;
        compare_tets(e, r[i], i, mm);
    }
    INFO(flat << " flat tetrahedra");
    CHECK(flat > test::random_cases(10000));
    mm.report("vicp_tet_constants");
}

TEST_CASE("VICP's fragment values in GLSL compute the emulation's bits on 1,200,000 fragments of real frames")
{
    GlVicpHarness& h = *gl(GlPlatform::osmesa).harness;
    const Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const auto linear = [](const glm::dvec3& p) { return 0.1 * p.x + 0.2 * p.y + 0.3 * p.z; };
    const Scene grid = test::make_scene(test::box_mesh(4, linear, 0.0), 0);
    const Scene fin = test::blunt_fin();
    struct View {
        const Scene* scene;
        double az, el;
        bool ortho;
        int size;
        std::size_t want;
    };
    const View views[] = {{&torus, 0.0, 0.0, false, 160, 200000},  {&torus, 35.0, 40.0, false, 160, 200000},
                          {&torus, 20.0, 50.0, true, 160, 150000},  {&grid, 0.0, 0.0, true, 81, 100000},
                          {&grid, 90.0, 0.0, false, 81, 100000},    {&fin, -40.0, 70.0, false, 256, 300000},
                          {&fin, 0.0, 0.0, false, 256, 300000}};
    Mismatches mm;
    uint64_t total = 0, empty = 0, seed = 10;
    for (const View& v : views) {
        Camera cam = default_camera(mesh_bounds(v.scene->mesh), 1.0, v.az, v.el);
        if (v.ortho) {
            cam.orthographic = true;
            cam.ortho_height = v.scene == &grid ? 9.0 : 1.2 * mesh_bounds(v.scene->mesh).extent().y;
        }
        const ValueCases vc = frame_value_cases(*v.scene, cam, v.size, test::random_cases(v.want), seed++);
        const std::vector<VicpSegment> r = h.run_values(vc.fc, vc.tets, vc.pixels);
        const FlushDenormals as_the_renderer_runs;
        for (std::size_t i = 0; i < vc.tets.size(); ++i) {
            const VicpSegment e = vicp_fragment_values(vc.fc, vc.tets[i], vc.pixels[i].x, vc.pixels[i].y);
            empty += e.length <= 0.0 ? 1 : 0;
            mm.check(e.s_front, r[i].s_front, i, "s_front");
            mm.check(e.s_back, r[i].s_back, i, "s_back");
            mm.check(e.t_in, r[i].t_in, i, "t_in");
            mm.check(e.t_out, r[i].t_out, i, "t_out");
            mm.check(e.length, r[i].length, i, "length");
        }
        total += vc.tets.size();
    }
    INFO(total << " fragments, " << empty << " with segments of no length");
    CHECK(total >= test::random_cases(1000000));
    CHECK(empty > test::random_cases(50000));
    mm.report("vicp_fragment_values (double)");
}

TEST_CASE("VICP's compositing in GLSL computes the emulation's bits on 1,000,000 random cases")
{
    GlVicpHarness& h = *gl(GlPlatform::osmesa).harness;
    Mismatches mm;
    CompositeTally t;
    uint64_t seed = 20;
    for (float threshold : {1.0f, 0.99f}) {
        CompositeGen g(seed++);
        std::vector<VicpCompositeCase> cs(test::random_cases(500000));
        for (auto& c : cs) c = g.make(threshold);
        const VicpFrameConstants fc = composite_frame(threshold);
        compare_composite(fc, cs, h.run_composite(fc, cs), nullptr, mm, t);
    }
    INFO(t.cases << " cases, " << t.killed << " killed, " << t.lookups << " lookups, " << t.no_length
                 << " without length, " << t.ordering_errors << " counted ordering errors");
    CHECK(t.cases >= test::random_cases(1000000));
    CHECK(t.killed > test::random_cases(10000));
    CHECK(t.lookups > test::random_cases(100000));
    CHECK(t.no_length > test::random_cases(100000));
    CHECK(t.ordering_errors > test::random_cases(100000));
    mm.report("vicp_composite");
}

TEST_CASE("VICP's compositing in GLSL with the table in a real 3D texture computes the emulation's bits")
{
    GlVicpHarness& h = *gl(GlPlatform::osmesa).harness;
    const TransferFunction tf = default_transfer_function(Range{0.0, 1.0}, 1.0);
    const SegmentIntegrator integrator(tf);
    const LlvmpipeCpu cpu = host_llvmpipe_cpu();
    Mismatches mm;
    CompositeTally t;
    uint64_t seed = 30;
    for (TexelFormat format : {TexelFormat::f32, TexelFormat::u16, TexelFormat::u8}) {
        const PreintegrationTable table = test::stage_test_table(integrator, format);
        VicpFrameConstants fc = composite_frame(0.99f);
        fc.length_scale = table.length_scale();
        fc.length_bias = table.length_bias();
        const SegmentShader lookup = [&](float uf, float ub, float tz, float) { return table.sample(uf, ub, tz, cpu); };
        CompositeGen g(seed++);
        std::vector<VicpCompositeCase> cs(test::random_cases(150000));
        for (auto& c : cs) c = g.make(0.99f);
        compare_composite(fc, cs, h.run_composite(fc, cs, &table), &lookup, mm, t);
    }
    INFO(t.lookups << " table lookups in " << t.cases << " cases (FMA3: " << cpu.fma << ")");
    CHECK(t.lookups > test::random_cases(100000));
    mm.report("vicp_composite with the table");
}

TEST_CASE("EGL: VICP's stages compute the same bits through the surfaceless (or device) context")
{
    Gl& e = gl(GlPlatform::egl);
    INFO(e.ctx->info().summary());
    Mismatches mm;
    VertexGen vg(40);
    std::vector<VicpVertexCase> vcases(100000);
    for (auto& c : vcases) c = vg.make();
    const std::vector<VicpTet> r = e.harness->run_vertex(vcases);
    CompositeGen cg(41);
    std::vector<VicpCompositeCase> cs(100000);
    for (auto& c : cs) c = cg.make(0.99f);
    const VicpFrameConstants fc = composite_frame(0.99f);
    const std::vector<VicpCompositeResult> cr = e.harness->run_composite(fc, cs);
    CompositeTally t;
    compare_composite(fc, cs, cr, nullptr, mm, t);
    const FlushDenormals as_the_renderer_runs;
    for (std::size_t i = 0; i < vcases.size(); ++i)
        compare_tets(vicp_tet_constants(vcases[i].shape, vcases[i].exact, vcases[i].s, vcases[i].boundary), r[i], i,
                     mm);
    mm.report("EGL: vicp_tet_constants and vicp_composite");
}
