// The interpolation stage (gpu/pipeline/interpolation.h) against llvmpipe, bit for bit: random triangles drawn by the
// GL harness (gpu/gl/gl_interpolation_harness.h), each pixel's `smooth`, `noperspective` and `flat` varyings and
// gl_FragCoord.w compared with the emulation's, over more than a million (triangle, pixel) cases: triangles far from
// the framebuffer's origin, slivers, tiny and large w, both facings, values of every magnitude (docs/spec.md §7).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "gpu/gl/gl_harness_pass.h"
#include "gpu/gl/gl_interpolation_harness.h"
#include "gpu/pipeline/clip.h"
#include "gpu/pipeline/clip_position.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/interpolation.h"
#include "gpu/pipeline/view_setup.h"
#include "gpu/pipeline/rasterize.h"
#include "bit_compare.h"
#include "case_rng.h"
#include "gl_harness.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;
using test::bits;

namespace {

// The kinds of triangle a batch draws.
enum class Kind { ordinary, sliver, tiny_w, large_w, mixed_w, small_values };
const char* kind_name(Kind k)
{
    switch (k) {
    case Kind::ordinary: return "ordinary";
    case Kind::sliver: return "sliver";
    case Kind::tiny_w: return "tiny w";
    case Kind::large_w: return "large w";
    case Kind::mixed_w: return "mixed w";
    case Kind::small_values: return "small values";
    }
    return "?";
}

struct TriangleGen : test::CaseRng {
    int width, height;
    TriangleGen(uint64_t seed, int w, int h) : CaseRng(seed), width(w), height(h) {}

    float w_of(Kind k)
    {
        switch (k) {
        case Kind::tiny_w: return unif(1e-3f, 1e-2f);
        case Kind::large_w: return unif(1e2f, 1e4f);
        case Kind::mixed_w: return pick(2) ? unif(1e-2f, 0.1f) : unif(10.0f, 100.0f);
        default: return unif(0.25f, 4.0f);
        }
    }
    float value_of(Kind k, int range)
    {
        if (k == Kind::small_values) return unif(-1.0f, 1.0f) * 1e-37f;  // products with oow fall below 2^-126
        switch (range) {
        case 0: return unif(0.0f, 1.0f);                    // a normalized scalar
        case 1: return unif(-60.0f, -0.5f);                 // an eye-space depth
        case 2: return unif(-1.0f, 1.0f) * 1e4f;            // large
        default: return unif(-1.0f, 1.0f);
        }
    }
    InterpolationTriangle make(Kind k)
    {
        // Window positions around a centre anywhere in the framebuffer; radius 1 to 48 pixels.
        const double cx = uni(0.0, width), cy = uni(0.0, height), r = uni(1.0, 48.0);
        double wx[3], wy[3];
        for (int v = 0; v < 3; ++v) {
            wx[v] = cx + uni(-r, r);
            wy[v] = cy + uni(-r, r);
        }
        if (k == Kind::sliver) {
            // The third vertex a hundredth to one pixel off the line through the other two.
            const double t = uni(-0.5, 1.5), off = uni(0.01, 1.0) * (pick(2) ? 1.0 : -1.0);
            const double dx = wx[1] - wx[0], dy = wy[1] - wy[0], len = std::hypot(dx, dy) + 1e-9;
            wx[2] = wx[0] + t * dx - off * dy / len;
            wy[2] = wy[0] + t * dy + off * dx / len;
        }
        InterpolationTriangle tri{};
        const int range = pick(4);
        for (int v = 0; v < 3; ++v) {
            // Inside the frustum with a margin, so that the draw module clips nothing.
            const double nx = std::clamp(2.0 * wx[v] / width - 1.0, -0.999, 0.999);
            const double ny = std::clamp(2.0 * wy[v] / height - 1.0, -0.999, 0.999);
            const double nz = uni(-0.9, 0.9);
            const float w = w_of(k);
            tri.clip[v][0] = float(nx * w);
            tri.clip[v][1] = float(ny * w);
            tri.clip[v][2] = float(nz * w);
            tri.clip[v][3] = w;
            for (int c = 0; c < 4; ++c) tri.value[v][c] = value_of(k, range);
        }
        return tri;
    }
};

// Triangles as the clip stage hands them to the GPU (gpu/pipeline/clip.h): random triangles in a cube around an eye
// inside it, clipped against the near plane and the viewport's sides, drawn as the fans HAVS draws (poly[0], poly[i],
// poly[i + 1]); positions relative to the eye in float through the emulated clip_position (what the vertex shader
// computes), values (s, x, y, z) of the clipped vertex. Their vertices lie on the clip planes: w down to the near
// plane's, positions a quarter pixel inside the viewport's edges.
std::vector<InterpolationTriangle> clip_stage_fans(uint64_t seed, int width, int height, int count)
{
    test::CaseRng rng(seed);
    Camera cam;
    cam.eye = {0.1, 0.2, 0.5};
    cam.target = {0.0, 0.0, -1.0};
    cam.fovy_deg = 50.0;
    const Bounds bounds{{-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}};
    const ViewSetup vs = view_setup(cam, width, height, bounds, cam.eye);
    const ClipPlanes planes = inner_clip_planes(width, height);
    std::vector<InterpolationTriangle> out;
    std::vector<ClipVertex> poly, scratch;
    while (int(out.size()) < count) {
        poly.clear();
        // Inside the bounds, in front of the far plane view_setup puts behind them (the clip stage never crosses it).
        const glm::dvec3 c = rng.vec(0.4);
        for (int v = 0; v < 3; ++v) poly.push_back(clip_vertex(vs, c + rng.vec(0.6) - cam.eye, rng.uni(0.0, 1.0)));
        clip_polygon(vs, planes, poly, scratch);
        for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
            InterpolationTriangle t{};
            const ClipVertex* fan[3] = {&poly[0], &poly[i], &poly[i + 1]};
            for (int v = 0; v < 3; ++v) {
                const glm::vec3 p(fan[v]->p);
                const std::array<float, 4> clip = clip_position(vs.mvp, p);
                std::copy(clip.begin(), clip.end(), t.clip[v]);
                REQUIRE_FALSE(outside_gpu_frustum(clip));  // else the draw module would clip it
                const float value[4] = {float(fan[v]->s), p.x, p.y, p.z};
                std::copy(value, value + 4, t.value[v]);
            }
            out.push_back(t);
        }
    }
    return out;
}

// The emulated pass: every triangle in order, each covered pixel overwritten, as the harness's program writes it.
InterpolationImages emulate(const std::vector<InterpolationTriangle>& tris, int width, int height)
{
    const FlushDenormals llvmpipe_mxcsr;
    const ViewportArithmetic arith = host_viewport_arithmetic();
    const Framebuffer fb{width, height, RenderTarget::fbo};
    const std::size_t n = std::size_t(width) * std::size_t(height) * 4;
    InterpolationImages out{std::vector<float>(n, kHarnessSentinel), std::vector<float>(n, kHarnessSentinel),
                            std::vector<float>(n, kHarnessSentinel), std::vector<float>(n, kHarnessSentinel)};
    for (std::size_t t = 0; t < tris.size(); ++t) {
        SetupVertex sv[3];
        WindowCoord win[3];
        for (int v = 0; v < 3; ++v) {
            sv[v] = setup_vertex(tris[t].clip[v], fb, arith);
            win[v] = WindowCoord{sv[v].x, sv[v].y};
        }
        const TriangleSetup ts = setup_triangle(win, fb);
        if (ts.empty()) continue;
        const AttributeSetup as = setup_attributes(sv, ts);
        AttributePlane planes[3][4];
        const Qualifier qs[3] = {Qualifier::smooth, Qualifier::noperspective, Qualifier::flat};
        for (int q = 0; q < 3; ++q)
            for (int c = 0; c < 4; ++c) {
                const float value[3] = {tris[t].value[0][c], tris[t].value[1][c], tris[t].value[2][c]};
                planes[q][c] = attribute_plane(as, sv, value, qs[q]);
            }
        std::vector<float>* images[3] = {&out.smooth, &out.noperspective, &out.flat};
        rasterize_triangle(win, fb, [&](int px, int py) {
            const std::size_t p = 4 * (std::size_t(py) * std::size_t(width) + std::size_t(px));
            const float factor = perspective_factor(as, px, py, arith);
            for (int q = 0; q < 3; ++q)
                for (int c = 0; c < 4; ++c) (*images[q])[p + c] = interpolate(planes[q][c], qs[q], px, py, factor, arith);
            out.info[p] = float(t);
            out.info[p + 1] = ts.facing == Facing::front ? 1.0f : 0.0f;
            out.info[p + 2] = frag_coord_w(as, px, py, arith);
            out.info[p + 3] = 0.0f;
        });
    }
    return out;
}

struct Tally {
    uint64_t cases = 0, coverage = 0, mismatches = 0;
    std::ostringstream first;
    void note(const std::string& what, std::size_t pixel, float emu, float glv)
    {
        if (mismatches++ < 8)
            first << what << " at pixel " << pixel << ": emulation " << emu << " (0x" << std::hex << bits(emu)
                  << "), GL " << glv << " (0x" << bits(glv) << std::dec << ")\n";
    }
};

void compare(const InterpolationImages& emu, const InterpolationImages& glv, const std::vector<InterpolationTriangle>& tris,
             Tally& tally)
{
    const char* names[3] = {"smooth", "noperspective", "flat"};
    const std::vector<float>* e[3] = {&emu.smooth, &emu.noperspective, &emu.flat};
    const std::vector<float>* g[3] = {&glv.smooth, &glv.noperspective, &glv.flat};
    for (std::size_t p = 0; p < emu.info.size() / 4; ++p) {
        const bool emu_covered = emu.info[4 * p] != kHarnessSentinel, gl_covered = glv.info[4 * p] != kHarnessSentinel;
        if (emu_covered != gl_covered || bits(emu.info[4 * p]) != bits(glv.info[4 * p])) {
            ++tally.coverage;
            continue;
        }
        if (!gl_covered) continue;
        ++tally.cases;
        const std::size_t t = std::size_t(glv.info[4 * p]);
        for (int q = 0; q < 3; ++q)
            for (int c = 0; c < 4; ++c)
                if (bits((*e[q])[4 * p + c]) != bits((*g[q])[4 * p + c]))
                    tally.note(std::string(names[q]) + "[" + std::to_string(c) + "] of triangle " + std::to_string(t),
                               p, (*e[q])[4 * p + c], (*g[q])[4 * p + c]);
        for (int c = 1; c < 3; ++c)
            if (bits(emu.info[4 * p + c]) != bits(glv.info[4 * p + c]))
                tally.note(c == 1 ? "gl_FrontFacing" : "gl_FragCoord.w", p, emu.info[4 * p + c], glv.info[4 * p + c]);
    }
    (void)tris;
}

// More than a million (triangle, pixel) cases in all (docs/spec.md §7 asks for a million).
const uint64_t kMinCases = test::random_cases(1000000);

void check_platform(GlPlatform platform)
{
    auto& g = test::gl_harness<GlInterpolationHarness>(platform);
    struct Batch {
        int width, height;
        Kind kind;
        int triangles;
        bool fans = false;
    };
    // 1024^2 batches of every kind, and two that put the triangles far from the origin along x and along y (a0 is
    // the plane's value at pixel (0, 0), so far triangles lose the most to its rounding).
    std::vector<Batch> batches;
    for (Kind k : {Kind::ordinary, Kind::sliver, Kind::tiny_w, Kind::large_w, Kind::mixed_w, Kind::small_values})
        batches.push_back({1024, 1024, k, int(test::random_cases(12000))});
    batches.push_back({8192, 128, Kind::ordinary, int(test::random_cases(8000))});
    batches.push_back({128, 8192, Kind::mixed_w, int(test::random_cases(8000))});
    batches.push_back({512, 384, Kind::ordinary, int(test::random_cases(3000)), true});
    Tally all;
    uint64_t seed = 1;
    for (const Batch& b : batches) {
        TriangleGen gen(seed++, b.width, b.height);
        std::vector<InterpolationTriangle> tris;
        if (b.fans)
            tris = clip_stage_fans(seed, b.width, b.height, b.triangles);
        else
            for (int i = 0; i < b.triangles; ++i) tris.push_back(gen.make(b.kind));
        const InterpolationImages glv = g.harness->run(tris, b.width, b.height);
        const InterpolationImages emu = emulate(tris, b.width, b.height);
        Tally tally;
        compare(emu, glv, tris, tally);
        INFO(gl_platform_name(platform) << ", " << (b.fans ? "clip-stage fan" : kind_name(b.kind)) << " triangles in " << b.width << "x" << b.height
                                        << ": " << tally.cases << " pixels compared\n"
                                        << tally.first.str());
        CHECK(tally.coverage == 0);
        CHECK(tally.mismatches == 0);
        all.cases += tally.cases;
    }
    INFO(all.cases << " (triangle, pixel) cases");
    CHECK(all.cases >= kMinCases);
}

}  // namespace

TEST_CASE("interpolated varyings equal llvmpipe's bit for bit (OSMesa)", "[interpolation][gl]")
{
    check_platform(GlPlatform::osmesa);
}

TEST_CASE("interpolated varyings equal llvmpipe's bit for bit (EGL)", "[interpolation][gl]")
{
    check_platform(GlPlatform::egl);
}
