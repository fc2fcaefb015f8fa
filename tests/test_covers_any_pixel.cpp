// Whether a triangle covers any pixel (gpu/pipeline/rasterize.h: may_cover_pixel, covers_any_pixel), the test by which
// the GL drivers of HAVS leave out triangles that make no fragment (havs_sent_triangles). Both are held to the
// per-pixel reference rasterizer (rasterize_triangle_reference): a triangle the test calls uncovered must cover no
// pixel there, and one it calls covered must cover one.
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "gpu/pipeline/rasterize.h"
#include "test_support.h"

using namespace uvr::gpu;

namespace {

// The reference's answer: does any pixel pass its edge tests?
bool reference_covers(const WindowCoord v[3], const Framebuffer& fb)
{
    bool any = false;
    rasterize_triangle_reference(v, fb, [&](int, int) { any = true; });
    return any;
}

// Random triangles of the kinds a fine mesh sends: most are smaller than a pixel, so most cover none.
struct TriangleGen {
    std::mt19937 rng;
    std::uniform_real_distribution<double> u{0.0, 1.0};
    int width, height;

    TriangleGen(uint32_t seed, int w, int h) : rng(seed), width(w), height(h) {}

    // Vertices within `size` pixels of a random point of the framebuffer (and a little outside it).
    void small(double size, WindowCoord v[3])
    {
        const double bx = -2 + (width + 4) * u(rng), by = -2 + (height + 4) * u(rng);
        for (int i = 0; i < 3; ++i) v[i] = {float(bx + size * (u(rng) - 0.5)), float(by + size * (u(rng) - 0.5))};
    }
    // Vertices within 1/128 pixel of pixel centres (a few 1/256 steps of snapping), where covering is decided by the
    // fill rule.
    void near_centres(WindowCoord v[3])
    {
        const int cx = int(u(rng) * width), cy = int(u(rng) * height);
        for (int i = 0; i < 3; ++i) {
            const int dx = int(u(rng) * 3) - 1, dy = int(u(rng) * 3) - 1;
            v[i] = {float(cx + dx + 0.5 + (int(u(rng) * 5) - 2) / 256.0),
                    float(cy + dy + 0.5 + (int(u(rng) * 5) - 2) / 256.0)};
        }
    }
    // A long sliver between two random points, at most `width` pixels across.
    void sliver(double across, WindowCoord v[3])
    {
        v[0] = {float(u(rng) * width), float(u(rng) * height)};
        v[1] = {float(u(rng) * width), float(u(rng) * height)};
        const double s = u(rng), e = (2 * u(rng) - 1) * across;
        const double dx = v[1].x - v[0].x, dy = v[1].y - v[0].y, len = std::hypot(dx, dy) + 1e-30;
        v[2] = {float(v[0].x + s * dx - e * dy / len), float(v[0].y + s * dy + e * dx / len)};
    }
};

// Checks `n` triangles from `make`: may_cover_pixel never rules out a covered triangle, and covers_any_pixel agrees
// with the reference. Returns how many the quick test ruled out, and how many cover nothing.
struct Counts {
    int ruled_out = 0, uncovered = 0;
};
template <class Make>
Counts check(const Framebuffer& fb, int n, Make&& make)
{
    Counts c;
    for (int i = 0; i < n; ++i) {
        WindowCoord v[3];
        make(v);
        const bool ref = reference_covers(v, fb);
        const bool quick = may_cover_pixel(v);
        const bool full = covers_any_pixel(setup_triangle(v, fb));
        INFO("triangle " << i << ": (" << v[0].x << ", " << v[0].y << ") (" << v[1].x << ", " << v[1].y << ") ("
                         << v[2].x << ", " << v[2].y << "); reference " << ref << ", may_cover_pixel " << quick
                         << ", covers_any_pixel " << full);
        if (ref) REQUIRE(quick);
        REQUIRE(full == ref);
        c.ruled_out += quick ? 0 : 1;
        c.uncovered += ref ? 0 : 1;
    }
    return c;
}

}  // namespace

TEST_CASE("A triangle is called uncovered exactly when the rasterizer covers none of its pixels")
{
    // 40,000 triangles a kind: about as many as a 128 x 128 HAVS frame of a fine mesh sends.
    constexpr int kTriangles = 40000;
    for (const Framebuffer fb : {Framebuffer{37, 23, RenderTarget::fbo}, Framebuffer{37, 23, RenderTarget::window}}) {
        const std::string where = fb.target == RenderTarget::fbo ? " (fbo)" : " (window)";
        TriangleGen gen(fb.target == RenderTarget::fbo ? 11u : 12u, fb.width, fb.height);
        SECTION("smaller than a pixel" + where) {
            const Counts c = check(fb, kTriangles, [&](WindowCoord v[3]) { gen.small(0.8, v); });
            INFO(c.ruled_out << " ruled out early, " << c.uncovered << " uncovered");
            CHECK(c.ruled_out > kTriangles / 4);  // the quick test does most of the work, as in a fine mesh
            CHECK(c.uncovered > c.ruled_out);      // and covers_any_pixel decides the rest
        }
        SECTION("a few pixels wide (the pixel-by-pixel branch and the row spans)" + where) {
            const Counts c = check(fb, kTriangles, [&](WindowCoord v[3]) { gen.small(6.0, v); });
            CHECK(c.uncovered > 0);
            CHECK(c.uncovered < kTriangles);
        }
        SECTION("vertices near pixel centres, where the fill rule decides" + where) {
            const Counts c = check(fb, kTriangles, [&](WindowCoord v[3]) { gen.near_centres(v); });
            CHECK(c.uncovered > 0);
            CHECK(c.uncovered < kTriangles);
        }
        SECTION("slivers across the frame" + where) {
            const Counts c = check(fb, kTriangles, [&](WindowCoord v[3]) { gen.sliver(0.3, v); });
            CHECK(c.uncovered > 0);
            CHECK(c.uncovered < kTriangles);
        }
    }
    SECTION("NaN and out-of-range vertices are left to the full test, which finds nothing covered") {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        const Framebuffer fb{37, 23, RenderTarget::fbo};
        const WindowCoord with_nan[3] = {{1.5f, 1.5f}, {nan, 9.0f}, {9.0f, 1.5f}};
        CHECK(may_cover_pixel(with_nan));
        CHECK(covers_any_pixel(setup_triangle(with_nan, fb)) == reference_covers(with_nan, fb));
        const WindowCoord far[3] = {{1.5f, 1.5f}, {3e10f, 9.0f}, {9.0f, 1.5f}};
        CHECK(may_cover_pixel(far));
        CHECK(covers_any_pixel(setup_triangle(far, fb)) == reference_covers(far, fb));
    }
}
