// llvmpipe's rasterization rules (gpu/pipeline/rasterize.h): snapping, the fill rule, culling, framebuffer clipping,
// closed surfaces, and triangles whose coverage was recorded from a real OSMesa run (Mesa 22.3.6).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "gpu/pipeline/rasterize.h"
#include "reference/builtin_mesh.h"
#include "reference/camera.h"
#include "reference/cells.h"
#include "reference/topology.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

Framebuffer fbo(int w, int h) { return {w, h, RenderTarget::fbo}; }
Framebuffer window(int w, int h) { return {w, h, RenderTarget::window}; }

// Setup-space coordinates of a triangle; for an FBO these are GL window coordinates.
struct Tri {
    WindowCoord v[3];
};
Tri tri(float x0, float y0, float x1, float y1, float x2, float y2) { return {{{x0, y0}, {x1, y1}, {x2, y2}}}; }

// The same triangle given in GL window coordinates, in the setup space of `fb` (a window buffer flips y).
Tri in_setup_space(const Tri& t, const Framebuffer& fb)
{
    Tri s = t;
    if (fb.target == RenderTarget::window)
        for (auto& v : s.v) v.y = float(fb.height) - v.y;
    return s;
}

// Per-pixel coverage counts in GL rows (index y * width + x).
std::vector<int> counts(const Tri& t, const Framebuffer& fb, Facing* facing = nullptr)
{
    std::vector<int> c(std::size_t(fb.width) * std::size_t(fb.height), 0);
    const Facing f = rasterize_triangle(t.v, fb, [&](int x, int y) {
        REQUIRE(x >= 0);
        REQUIRE(x < fb.width);
        REQUIRE(y >= 0);
        REQUIRE(y < fb.height);
        ++c[std::size_t(y) * std::size_t(fb.width) + std::size_t(x)];
    });
    if (facing) *facing = f;
    return c;
}

bool covered(const std::vector<int>& c, const Framebuffer& fb, int x, int y)
{
    return c[std::size_t(y) * std::size_t(fb.width) + std::size_t(x)] > 0;
}

// Sorted pixel indices from the fast path and from the per-pixel path.
std::vector<int> pixels_fast(const WindowCoord v[3], const Framebuffer& fb)
{
    std::vector<int> p;
    rasterize_triangle(v, fb, [&](int x, int y) { p.push_back(y * fb.width + x); });
    std::sort(p.begin(), p.end());
    return p;
}
std::vector<int> pixels_reference(const WindowCoord v[3], const Framebuffer& fb)
{
    std::vector<int> p;
    rasterize_triangle_reference(v, fb, [&](int x, int y) { p.push_back(y * fb.width + x); });
    std::sort(p.begin(), p.end());
    return p;
}

// A GL-style perspective projection of docs/spec.md §2's default camera: eye space from the camera frame (x = r, y = u,
// looking down -z), a symmetric frustum with fovy and the framebuffer's aspect, near and far planes around the
// bounding sphere, then llvmpipe's viewport transform. Every mesh point is projected once, so shared vertices are
// bit-identical, as they are for GL.
std::vector<WindowCoord> project(const TetMesh& mesh, const Framebuffer& fb, double az, double el,
                                 Camera* out = nullptr)
{
    const Bounds b = mesh_bounds(mesh);
    const double aspect = double(fb.width) / double(fb.height);
    const Camera cam = default_camera(b, aspect, az, el);
    if (out) *out = cam;
    const CameraFrame fr = camera_frame(cam);
    const double dist = glm::length(cam.target - cam.eye), radius = 0.5 * glm::length(b.extent());
    const double near = 0.5 * (dist - radius), far = 2.0 * (dist + radius);
    const double fy = 1.0 / std::tan(0.5 * cam.fovy_deg * 3.14159265358979323846 / 180.0);
    std::vector<WindowCoord> w;
    for (const glm::dvec3& p : mesh.points) {
        const glm::dvec3 d = p - cam.eye;
        const double xe = glm::dot(d, fr.r), ye = glm::dot(d, fr.u), ze = -glm::dot(d, fr.f);
        const float clip[4] = {float(xe * fy / aspect), float(ye * fy),
                               float((ze * (far + near) + 2.0 * far * near) / (near - far)), float(-ze)};
        w.push_back(viewport_transform(clip, fb));
    }
    return w;
}

// Signed distance of (px, py) to the inside of a counter-clockwise convex polygon (positive inside).
double inside_distance(const std::vector<glm::dvec2>& hull, double px, double py)
{
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
        const glm::dvec2 e = b - a;
        d = std::min(d, (e.x * (py - a.y) - e.y * (px - a.x)) / glm::length(e));
    }
    return d;
}

// Andrew's monotone chain, counter-clockwise.
std::vector<glm::dvec2> convex_hull(std::vector<glm::dvec2> p)
{
    std::sort(p.begin(), p.end(), [](auto a, auto b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    auto cross = [](glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    std::vector<glm::dvec2> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);
    return h;
}

// A box split into tetrahedra, with uneven spacing so that faces have different shapes.
TetMesh box_mesh()
{
    const double xs[] = {0.0, 0.3, 1.1, 1.5}, ys[] = {0.0, 0.9, 1.2}, zs[] = {0.0, 0.4, 0.5, 1.3, 2.0};
    StructuredGrid g;
    g.source = "box";
    g.dims = {4, 3, 5};
    for (double z : zs)
        for (double y : ys)
            for (double x : xs) g.points.push_back({x, y, z});
    return tetrahedralize_structured(g);
}

bool ray_hits_box(const Ray& r, glm::dvec3 lo, glm::dvec3 hi)
{
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / r.dir[a];
        double ta = (lo[a] - r.origin[a]) * inv, tb = (hi[a] - r.origin[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

uint64_t fnv1a(const std::vector<int>& idx)
{
    uint64_t h = 1469598103934665603ull;
    for (int i : idx) {
        h ^= uint64_t(i);
        h *= 1099511628211ull;
    }
    return h;
}

}  // namespace

TEST_CASE("Snapping puts pixel centres on multiples of 256 and rounds half to even")
{
    SECTION("pixel centres") {
        CHECK(snap_to_fixed(0.5f) == 0);
        CHECK(snap_to_fixed(10.5f) == 2560);
        CHECK(snap_to_fixed(-3.5f) == -1024);
        CHECK(snap_to_fixed(10.0f) == 2432);  // a pixel corner is half a pixel off the centres' lattice
    }
    SECTION("ties go to the even neighbour, as _mm_cvtps_epi32 does") {
        CHECK(snap_to_fixed(10.5f + 0.5f / 256) == 2560);
        CHECK(snap_to_fixed(10.5f + 1.5f / 256) == 2562);
        CHECK(snap_to_fixed(0.5f - 0.5f / 256) == 0);
        CHECK(snap_to_fixed(0.5f - 1.5f / 256) == -2);
    }
    SECTION("coordinates that differ by less than 1/256 pixel snap alike, and so do their triangles") {
        CHECK(snap_to_fixed(10.5f + 0.1f / 256) == snap_to_fixed(10.5f + 0.3f / 256));
        const Framebuffer fb = fbo(16, 16);
        const Tri a = tri(2.5f + 0.1f / 256, 1, 12, 6, 2.5f, 11);
        const Tri b = tri(2.5f + 0.4f / 256, 1, 12, 6, 2.5f - 0.3f / 256, 11);
        CHECK(counts(a, fb) == counts(b, fb));
        // Half a step off rounds back onto the centre (even), one and a half steps off does not: column 2 is lost.
        const Tri on = tri(2.5f + 0.5f / 256, 1, 12, 6, 2.5f + 0.5f / 256, 11);
        const Tri off = tri(2.5f + 1.5f / 256, 1, 12, 6, 2.5f + 1.5f / 256, 11);
        CHECK(covered(counts(on, fb), fb, 2, 6));
        CHECK_FALSE(covered(counts(off, fb), fb, 2, 6));
    }
    SECTION("NaN and out-of-range values give cvtps' integer indefinite") {
        CHECK(snap_to_fixed(std::numeric_limits<float>::quiet_NaN()) == INT32_MIN);
        CHECK(snap_to_fixed(1e10f) == INT32_MIN);
        CHECK(snap_to_fixed(-1e10f) == INT32_MIN);
    }
}

TEST_CASE("A pixel centre exactly on an edge is covered on left and bottom edges, not on right and top edges")
{
    for (const Framebuffer& fb : {fbo(12, 10), window(12, 10)}) {
        const std::string on = fb.target == RenderTarget::fbo ? " (fbo)" : " (window)";
        SECTION("vertical edge through the centres of column 5" + on) {
            // The edge x = 5.5 from y = 1 to 9: the left edge of the right triangle, the right edge of the left one.
            const Tri right = in_setup_space(tri(5.5f, 1, 9, 5, 5.5f, 9), fb);
            const Tri left = in_setup_space(tri(5.5f, 1, 5.5f, 9, 2, 5), fb);
            const auto r = counts(right, fb), l = counts(left, fb);
            for (int y = 1; y <= 8; ++y) {
                INFO("row " << y);
                CHECK(covered(r, fb, 5, y));
                CHECK_FALSE(covered(l, fb, 5, y));
            }
        }
        SECTION("horizontal edge through the centres of row 4 (GL y up)" + on) {
            const Tri above = in_setup_space(tri(1, 4.5f, 9, 4.5f, 5, 8), fb);
            const Tri below = in_setup_space(tri(1, 4.5f, 5, 1, 9, 4.5f), fb);
            const auto a = counts(above, fb), b = counts(below, fb);
            for (int x = 1; x <= 8; ++x) {
                INFO("column " << x);
                CHECK(covered(a, fb, x, 4));
                CHECK_FALSE(covered(b, fb, x, 4));
            }
        }
        SECTION("sloped edge through centres" + on) {
            // The edge from (1.5, 0.5) to (9.5, 8.5) passes through the centres of the pixels with x == y + 1.
            const Tri upper_left = in_setup_space(tri(1.5f, 0.5f, 9.5f, 8.5f, 1.5f, 8.5f), fb);
            const Tri lower_right = in_setup_space(tri(1.5f, 0.5f, 9.5f, 0.5f, 9.5f, 8.5f), fb);
            const auto ul = counts(upper_left, fb), lr = counts(lower_right, fb);
            for (int y = 1; y <= 7; ++y) {
                INFO("pixel " << y + 1 << ", " << y);
                // For the lower-right triangle the edge has its interior to the right: a left edge.
                CHECK(covered(lr, fb, y + 1, y));
                CHECK_FALSE(covered(ul, fb, y + 1, y));
            }
        }
        SECTION("both windings cover the same pixels with opposite facings" + on) {
            const Tri ccw = in_setup_space(tri(1.5f, 1.5f, 9.5f, 3.5f, 4.5f, 8.5f), fb);
            const Tri cw = {{ccw.v[0], ccw.v[2], ccw.v[1]}};
            Facing f1 = Facing::none, f2 = Facing::none;
            CHECK(counts(ccw, fb, &f1) == counts(cw, fb, &f2));
            CHECK(f1 == Facing::front);  // counter-clockwise in GL window coordinates
            CHECK(f2 == Facing::back);
        }
        SECTION("a shared edge through centres is covered exactly once" + on) {
            const Tri a = in_setup_space(tri(0.5f, 0.5f, 11.5f, 9.5f, 0.5f, 9.5f), fb);
            const Tri b = in_setup_space(tri(0.5f, 0.5f, 11.5f, 0.5f, 11.5f, 9.5f), fb);
            const auto ca = counts(a, fb), cb = counts(b, fb);
            for (int y = 0; y < fb.height; ++y)
                for (int x = 0; x < fb.width; ++x) {
                    INFO("pixel " << x << ", " << y);
                    // The square [0.5, 11.5] x [0.5, 9.5]: its bottom and left sides are in, top and right are out.
                    const int expected = (x <= 10 && y <= 8) ? 1 : 0;
                    CHECK(ca[std::size_t(y * fb.width + x)] + cb[std::size_t(y * fb.width + x)] == expected);
                }
        }
    }
}

TEST_CASE("A vertex exactly at a pixel centre is covered by exactly one triangle of a fan around it")
{
    const Framebuffer fb = fbo(20, 16);
    SECTION("a fan of six triangles") {
        const float cx = 10.5f, cy = 7.5f;
        const float ring[6][2] = {{14, 7.5f}, {12, 11}, {9, 12}, {6.5f, 7}, {8.5f, 3}, {13, 4}};
        std::vector<int> sum(std::size_t(fb.width * fb.height), 0);
        for (int i = 0; i < 6; ++i) {
            const Tri t = tri(cx, cy, ring[i][0], ring[i][1], ring[(i + 1) % 6][0], ring[(i + 1) % 6][1]);
            const auto c = counts(t, fb);
            for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += c[k];
        }
        CHECK(sum[std::size_t(7 * fb.width + 10)] == 1);
        CHECK(*std::max_element(sum.begin(), sum.end()) == 1);
    }
    SECTION("the owner is the triangle that lies up and to the right of the vertex") {
        CHECK(covered(counts(tri(10.5f, 7.5f, 14.5f, 7.5f, 10.5f, 11.5f), fb), fb, 10, 7));
        CHECK_FALSE(covered(counts(tri(10.5f, 7.5f, 10.5f, 11.5f, 6.5f, 7.5f), fb), fb, 10, 7));
        CHECK_FALSE(covered(counts(tri(10.5f, 7.5f, 6.5f, 7.5f, 10.5f, 3.5f), fb), fb, 10, 7));
        CHECK_FALSE(covered(counts(tri(10.5f, 7.5f, 10.5f, 3.5f, 14.5f, 7.5f), fb), fb, 10, 7));
    }
}

TEST_CASE("Zero-area triangles cover nothing")
{
    const Framebuffer fb = fbo(16, 16);
    auto check_empty = [&](const Tri& t) {
        Facing f = Facing::front;
        const auto c = counts(t, fb, &f);
        CHECK(f == Facing::none);
        CHECK(std::count(c.begin(), c.end(), 0) == long(c.size()));
    };
    SECTION("collinear vertices") { check_empty(tri(1.5f, 1.5f, 5.5f, 5.5f, 12.5f, 12.5f)); }
    SECTION("a repeated vertex") { check_empty(tri(1, 2, 9, 14, 1, 2)); }
    SECTION("a sliver whose float area is not zero but whose snapped area is") {
        // The third vertex is 1/1024 pixel off the line: it snaps back onto it.
        check_empty(tri(1.5f, 1.5f, 13.5f, 1.5f, 7.5f, 1.5f + 1.0f / 1024));
    }
}

TEST_CASE("Triangles partly outside the framebuffer are cut at its border")
{
    // The same triangle in a 40 x 30 framebuffer and, shifted by (40, 30), in a 120 x 90 one: the small result is the
    // window of the large one. Coordinates on a 1/64 grid keep the shift exact in float.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> ux(-20 * 64, 60 * 64), uy(-15 * 64, 45 * 64);
    for (const RenderTarget target : {RenderTarget::fbo, RenderTarget::window}) {
        const Framebuffer small{40, 30, target}, large{120, 90, target};
        for (int n = 0; n < 200; ++n) {
            Tri a, b;
            for (int k = 0; k < 3; ++k) {
                a.v[k] = {float(ux(rng)) / 64, float(uy(rng)) / 64};
                b.v[k] = {a.v[k].x + 40, a.v[k].y + 30};
            }
            // In a window buffer setup space counts from the top, but the large framebuffer has 30 rows above the small
            // window as well as below it, so the shift is (40, 30) in setup space for both targets.
            const auto cs = counts(a, small), cl = counts(b, large);
            INFO("triangle " << n);
            int mismatched = 0;
            for (int y = 0; y < small.height; ++y)
                for (int x = 0; x < small.width; ++x)
                    if (cs[std::size_t(y * small.width + x)] != cl[std::size_t((y + 30) * large.width + x + 40)])
                        ++mismatched;
            CHECK(mismatched == 0);
        }
    }
}

TEST_CASE("Huge triangles do not overflow")
{
    const Framebuffer fb = fbo(64, 48);
    SECTION("one triangle with vertices a million pixels away covers every pixel once") {
        const auto c = counts(tri(-1e6f, -1e6f, 1e6f, -1e6f, 32, 1e6f), fb);
        CHECK(std::count(c.begin(), c.end(), 1) == long(c.size()));
    }
    SECTION("two huge triangles sharing a diagonal through pixel centres cover every pixel exactly once") {
        // The diagonal from (32 - 1e6, 24 - 1e6) to (32 + 1e6, 24 + 1e6) runs through the centres with x - y == 8.
        const float lo_x = 32 - 1e6f, hi_x = 32 + 1e6f, lo_y = 24 - 1e6f, hi_y = 24 + 1e6f;
        const auto a = counts(tri(lo_x, lo_y, hi_x, lo_y, hi_x, hi_y), fb);
        const auto b = counts(tri(lo_x, lo_y, hi_x, hi_y, lo_x, hi_y), fb);
        for (std::size_t k = 0; k < a.size(); ++k) {
            INFO("pixel " << k % 64 << ", " << k / 64);
            CHECK(a[k] + b[k] == 1);
        }
    }
    SECTION("beyond about 2 million pixels the emulation gives up (llvmpipe never receives such a vertex)") {
        Facing f = Facing::front;
        const auto c = counts(tri(-1e7f, -1e7f, 1e7f, -1e7f, 32, 1e7f), fb, &f);
        CHECK(f == Facing::none);
        CHECK(std::count(c.begin(), c.end(), 0) == long(c.size()));
    }
}

TEST_CASE("The span fast path covers exactly the pixels of the per-pixel path")
{
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (const Framebuffer& fb : {fbo(41, 29), window(41, 29), fbo(16, 70)}) {
        const double w = fb.width, h = fb.height;
        auto quarter = [&](double lo, double hi) { return float(std::floor((lo + u(rng) * (hi - lo)) * 4) / 4); };
        auto near_centre = [&](double n) {
            return float(std::floor(u(rng) * n) + 0.5 + (std::floor(u(rng) * 9) - 4) / 512.0);
        };
        const char* kinds[] = {"quarter-pixel grid", "near pixel centres", "anywhere, also outside", "small",
                               "sliver"};
        for (int kind = 0; kind < 5; ++kind) {
            SECTION(std::string(kinds[kind]) + (fb.target == RenderTarget::fbo ? " (fbo " : " (window ") +
                    std::to_string(fb.width) + "x" + std::to_string(fb.height) + ")") {
                for (int n = 0; n < 600; ++n) {
                    WindowCoord v[3];
                    for (auto& p : v) {
                        if (kind == 0) p = {quarter(-2, w + 2), quarter(-2, h + 2)};
                        if (kind == 1) p = {near_centre(w), near_centre(h)};
                        if (kind == 2) p = {float(-w + 3 * w * u(rng)), float(-h + 3 * h * u(rng))};
                    }
                    if (kind == 3) {
                        const float bx = float(u(rng) * w), by = float(u(rng) * h);
                        for (auto& p : v) p = {bx + float(4 * u(rng) - 2), by + float(4 * u(rng) - 2)};
                    }
                    if (kind == 4) {
                        v[0] = {float(u(rng) * w), float(u(rng) * h)};
                        v[1] = {float(u(rng) * w), float(u(rng) * h)};
                        const float s = float(u(rng)), e = float((2 * u(rng) - 1) * 0.01);
                        const float dx = v[1].x - v[0].x, dy = v[1].y - v[0].y;
                        v[2] = {v[0].x + s * dx - e * dy, v[0].y + s * dy + e * dx};
                    }
                    INFO("triangle " << n << ": (" << v[0].x << ", " << v[0].y << ") (" << v[1].x << ", " << v[1].y
                                     << ") (" << v[2].x << ", " << v[2].y << ")");
                    const auto fast = pixels_fast(v, fb), ref = pixels_reference(v, fb);
                    REQUIRE(std::adjacent_find(fast.begin(), fast.end()) == fast.end());  // each pixel once
                    REQUIRE(fast == ref);
                }
            }
        }
    }
}

TEST_CASE("Vertex order changes the facing, not the covered pixels")
{
    const Framebuffer fb = fbo(30, 20);
    const WindowCoord a{3.25f, 2.5f}, b{27.5f, 6.75f}, c{11.5f, 18.5f};  // counter-clockwise in GL coordinates
    const WindowCoord orders[6][3] = {{a, b, c}, {b, c, a}, {c, a, b}, {a, c, b}, {c, b, a}, {b, a, c}};
    const auto expected = pixels_fast(orders[0], fb);
    CHECK(expected.size() > 100);
    for (int i = 0; i < 6; ++i) {
        INFO("order " << i);
        CHECK(pixels_fast(orders[i], fb) == expected);
        CHECK(setup_triangle(orders[i], fb).facing == (i < 3 ? Facing::front : Facing::back));
    }
}

TEST_CASE("The viewport transform repeats llvmpipe's float operations")
{
    SECTION("exact cases, and the flipped viewport of a window buffer") {
        const float clip[4] = {0.25f, 0.25f, 0.0f, 1.0f};
        const WindowCoord f = viewport_transform(clip, fbo(64, 32));
        const WindowCoord w = viewport_transform(clip, window(64, 32));
        CHECK(f.x == 40.0f);
        CHECK(f.y == 20.0f);
        CHECK(w.x == 40.0f);
        CHECK(w.y == 12.0f);
        const float clip2[4] = {1.0f, -1.0f, 0.0f, 2.0f};  // x / w = 0.5, y / w = -0.5
        CHECK(viewport_transform(clip2, fbo(64, 32)).x == 48.0f);
        CHECK(viewport_transform(clip2, fbo(64, 32)).y == 8.0f);
    }
    SECTION("multiply-add is fused when the CPU has FMA3") {
        // A vertex of the OSMesa-recorded cases below, where the fused and the separate results snap differently.
        const float clip[4] = {-0x1.81ef04p-1f, -0x1.66f9b6p-1f, 0.0f, 0x1.c0b824p-1f};
        const Framebuffer fb = fbo(50, 37);
        const float xn = clip[0] * (1.0f / clip[3]);
        const WindowCoord fused = viewport_transform(clip, fb, ViewportArithmetic::fused);
        const WindowCoord separate = viewport_transform(clip, fb, ViewportArithmetic::separate);
        CHECK(fused.x == std::fma(xn, 25.0f, 25.0f));
        CHECK(snap_to_fixed(fused.x) != snap_to_fixed(separate.x));
#if defined(__x86_64__)
        CHECK((host_viewport_arithmetic() == ViewportArithmetic::fused) == bool(__builtin_cpu_supports("fma")));
#endif
    }
}

TEST_CASE("Coverage and facing match OSMesa on triangles recorded from Mesa 22.3.6 llvmpipe")
{
    // Recorded with a 3.3 core context (OSMesaCreateContextAttribs), gl_Position = the clip coordinates below, an
    // RGBA32F FBO or a GL_FLOAT OSMesa buffer, additive blending of gl_FrontFacing ? red : green, on an x86-64 CPU
    // with FMA3 (Debian 12, libosmesa6 22.3.6-1+deb12u2, LLVM 15.0.6). pixels and hash (FNV-1a over the covered
    // indices y * width + x, GL rows, ascending) describe what OSMesa covered; Facing::none with 0 pixels means no
    // pixel was drawn. docs/rasterizer.md describes the larger randomized runs behind these.
    struct Recorded {
        RenderTarget target;
        int width, height;
        float clip[3][4];
        Facing facing;
        long pixels;
        uint64_t hash;
    };
    constexpr RenderTarget kFbo = RenderTarget::fbo, kWindow = RenderTarget::window;
    static const Recorded cases[] = {
        {kFbo, 50, 37, {{0x1.70a3d8p-2f, -0x1.759f22p-2f, 0, 1}, {-0x1.6147aep-1f, 0x1.9f2298p-3f, 0, 1},
            {0x1.b33334p-1f, 0x1.298376p-1f, 0, 1}}, Facing::back, 293, 0x42c93fadbd115f17ull},  // grid4
        {kFbo, 50, 37, {{0x1.0f5c28p-1f, 0x1.9f2298p-2f, 0, 1}, {0x1.570a3ep-1f, 0x1.3759f2p-1f, 0, 1},
            {-0x1.4cccccp-1f, -0x1.4c1bacp-4f, 0, 1}}, Facing::front, 40, 0xb700d8c8923f37fbull},  // grid4
        {kFbo, 50, 37, {{0x1.99999ap-2f, 0x1.8375ap-1f, 0, 1}, {0x1.eb851ep-6f, -0x1.0dd67cp-1f, 0, 1},
            {-0x1.dc28f6p-1f, -0x1.7c8a6p-1f, 0, 1}}, Facing::back, 265, 0x93fd46496829ce78ull},  // grid4
        {kWindow, 50, 37, {{0x1.333334p-1f, -0x1.45306ep-1f, 0, 1}, {0x1.1eb852p-1f, 0x1.8375ap-3f, 0, 1},
            {-0x1.c28f5cp-4f, -0x1.9f2298p-1f, 0, 1}}, Facing::front, 136, 0x827d9ebe30e8669dull},  // grid4
        {kWindow, 50, 37, {{-0x1.47ae14p-4f, -0x1.59f22ap-2f, 0, 1}, {-0x1.70a3d8p-1f, 0x1.306eb4p-2f, 0, 1},
            {-0x1.c7ae14p-1f, 0x1.c8a60ep-2f, 0, 1}}, Facing::front, 4, 0x0ff48c9823c51565ull},  // grid4
        {kWindow, 50, 37, {{0x1.c28f5cp-1f, -1, 0, 1}, {0x1.fae148p-1f, 0x1.f22984p-3f, 0, 1},
            {0x1.c28f5cp-3f, -0x1.f914c2p-1f, 0, 1}}, Facing::front, 192, 0x48aab1b338bea8efull},  // grid4
        {kFbo, 48, 40, {{-0x1.5aaaaap-6f, -0x1.73599ap-1f, 0, 1}, {0x1.352aaap-1f, -0x1.d98cccp-1f, 0, 1},
            {0x1.7faaaap-3f, -0x1.736666p-1f, 0, 1}}, Facing::front, 7, 0x665b6d6b378914c3ull},  // ties
        {kFbo, 48, 40, {{-0x1.fd5556p-5f, 0x1.003334p-3f, 0, 1}, {0x1.2a2aaap-3f, -0x1.663334p-3f, 0, 1},
            {0x1.d52aaap-3f, 0x1.733334p-1f, 0, 1}}, Facing::front, 50, 0xc0820e587728e671ull},  // ties
        {kFbo, 48, 40, {{-0x1.2b2aaap-3f, -0x1.0cf334p-1f, 0, 1}, {0x1.354p-1f, -0x1.666666p-3f, 0, 1},
            {0x1.4a8aaap-1f, -0x1.cc3334p-3f, 0, 1}}, Facing::back, 12, 0x6921867837402925ull},  // ties
        {kWindow, 48, 40, {{-0x1.2b5556p-3f, 0x1.194cccp-2f, 0, 1}, {-0x1.958p-2f, 0x1.7fccccp-2f, 0, 1},
            {0x1.b53556p-1f, 0x1.19e666p-2f, 0, 1}}, Facing::back, 25, 0x3cd5328d5db06ed6ull},  // ties
        {kWindow, 48, 40, {{0x1.fep-5f, -0x1.3fe666p-1f, 0, 1}, {-0x1.8p-3f, -0x1.d9999ap-1f, 0, 1},
            {-0x1.f53556p-1f, -0x1.734cccp-1f, 0, 1}}, Facing::back, 66, 0xd598f7d6faf257a5ull},  // ties
        {kWindow, 48, 40, {{0x1.757556p-1f, -0x1.cc3334p-3f, 0, 1}, {-0x1.15p-2f, -0x1.0cccccp-1f, 0, 1},
            {0x1.3fcp-2f, 0x1.f3p-1f, 0, 1}}, Facing::back, 315, 0xc3091bb5e8cf2b1aull},  // ties
        {kFbo, 50, 37, {{-0x1.81ef04p-1f, -0x1.66f9b6p-1f, 0, 0x1.c0b824p-1f},
            {-0x1.81ef04p-1f, 0x1.66f9b6p-1f, 0, 0x1.c0b824p-1f},
            {0x1.ccccccp-1f, 0, 0, 1}}, Facing::back, 674, 0xcc2b2337b57d4dd9ull},  // fma
        {kFbo, 50, 37, {{-0x1.204862p+1f, -0x1.4980b6p+1f, 0, 0x1.9be0e4p+1f},
            {-0x1.204862p+1f, 0x1.4980b6p+1f, 0, 0x1.9be0e4p+1f},
            {0x1.ccccccp-1f, 0, 0, 1}}, Facing::back, 577, 0xf2730787333740aaull},  // fma
        {kFbo, 50, 37, {{-0x1.c8bfbep+0f, -0x1.a8d81cp+0f, 0, 0x1.098712p+1f},
            {-0x1.c8bfbep+0f, 0x1.a8d81cp+0f, 0, 0x1.098712p+1f},
            {0x1.ccccccp-1f, 0, 0, 1}}, Facing::back, 674, 0xcc2b2337b57d4dd9ull},  // fma
        {kWindow, 50, 37, {{-0x1.5b16e2p+0f, -0x1.8cb7c4p+0f, 0, 0x1.efe5b6p+0f},
            {-0x1.5b16e2p+0f, 0x1.8cb7c4p+0f, 0, 0x1.efe5b6p+0f},
            {-0x1.ccccccp-1f, 0, 0, 1}}, Facing::front, 86, 0x6ecfe8fa862ebd3eull},  // fma
        {kWindow, 50, 37, {{-0x1.0ef524p+0f, -0x1.085fc2p+0f, 0, 0x1.4a77b2p+0f},
            {-0x1.0ef524p+0f, 0x1.085fc2p+0f, 0, 0x1.4a77b2p+0f},
            {0x1.ccccccp-1f, 0, 0, 1}}, Facing::back, 624, 0x569b0ce78c13a99eull},  // fma
        {kFbo, 50, 37, {{-0x1.3c287p+1f, -0x1.004d76p+1f, 0, 0x1.8b328cp+1f},
            {0x1.3c287p+1f, -0x1.004d76p+1f, 0, 0x1.8b328cp+1f},
            {0, 0x1.ccccccp-1f, 0, 1}}, Facing::front, 554, 0xce7656a5bf563388ull},  // fmay
        {kFbo, 50, 37, {{-0x1.2958b4p+1f, -0x1.e24312p+0f, 0, 0x1.73aee2p+1f},
            {0x1.2958b4p+1f, -0x1.e24312p+0f, 0, 0x1.73aee2p+1f},
            {0, -0x1.ccccccp-1f, 0, 1}}, Facing::back, 74, 0x864a414b45ecdb90ull},  // fmay
        {kWindow, 50, 37, {{-0x1.eb8f24p+0f, 0x1.8e7f2p+0f, 0, 0x1.333976p+1f},
            {0x1.eb8f24p+0f, 0x1.8e7f2p+0f, 0, 0x1.333976p+1f},
            {0, -0x1.ccccccp-1f, 0, 1}}, Facing::back, 554, 0x1fa788872b89f6b4ull},  // fmay
        {kWindow, 50, 37, {{-0x1.00c14cp+1f, 0x1.a04ab2p+0f, 0, 0x1.40f19ep+1f},
            {0x1.00c14cp+1f, 0x1.a04ab2p+0f, 0, 0x1.40f19ep+1f},
            {0, -0x1.ccccccp-1f, 0, 1}}, Facing::back, 554, 0x1fa788872b89f6b4ull},  // fmay
        {kWindow, 50, 37, {{-0x1.436b9cp+1f, 0x1.06468p+1f, 0, 0x1.944682p+1f},
            {0x1.436b9cp+1f, 0x1.06468p+1f, 0, 0x1.944682p+1f},
            {0, -0x1.ccccccp-1f, 0, 1}}, Facing::back, 594, 0xa9e9173c8f80e26cull},  // fmay
        {kFbo, 50, 37, {{-0x1.a5c68ep-7f, 0x1.8560dep-2f, 0, 1}, {-0x1.988fdcp-4f, 0x1.cb6eb4p-2f, 0, 1},
            {-0x1.50e1c8p-4f, 0x1.dbdd68p-2f, 0, 1}}, Facing::back, 1, 0x44c050d473d24f78ull},  // small
        {kFbo, 50, 37, {{0x1.477348p-1f, 0x1.136f1p-2f, 0, 1}, {0x1.5f7348p-1f, 0x1.fd5aacp-3f, 0, 1},
            {0x1.5d35d6p-1f, 0x1.ea53cp-3f, 0, 1}}, Facing::none, 0, 0x14650fb0739d0383ull},  // small
        {kFbo, 50, 37, {{0x1.b17d4p-3f, 0x1.4e699ep-1f, 0, 1}, {0x1.f92b56p-3f, 0x1.64e628p-1f, 0, 1},
            {0x1.4c5e88p-3f, 0x1.3101d4p-1f, 0, 1}}, Facing::none, 0, 0x14650fb0739d0383ull},  // small
        {kWindow, 50, 37, {{-0x1.dbc4eap-1f, -0x1.ef8c8ap-1f, 0, 1}, {-0x1.53b2cap-2f, -0x1.9d5e44p-2f, 0, 1},
            {-0x1.92cf28p-1f, -0x1.a3022ap-1f, 0, 1}}, Facing::front, 2, 0x985fcd00c38cba8aull},  // small
        {kWindow, 50, 37, {{0x1.a25edcp-3f, -0x1.db2bbcp-1f, 0, 1}, {-0x1.dee8d2p-3f, -0x1.989386p-1f, 0, 1},
            {-0x1.76239p-4f, -0x1.ee32a8p-1f, 0, 1}}, Facing::front, 12, 0x05f1a906d5f84e49ull},  // small
        {kFbo, 90, 70, {{0x1.19d742p-2f, 0x1.91646cp-4f, 0, 1}, {0x1.303da8p-2f, 0x1.3c627p-5f, 0, 1},
            {0x1.2c6318p-2f, 0x1.911e2ap-5f, 0, 1}}, Facing::none, 0, 0x14650fb0739d0383ull},  // sliver
        {kFbo, 90, 70, {{0x1.4d6ebep-4f, 0x1.b754a2p-1f, 0, 1}, {0x1.286f44p-1f, -0x1.c8e1cap-5f, 0, 1},
            {0x1.85ccbep-2f, 0x1.2e560cp-2f, 0, 1}}, Facing::back, 6, 0x06e4083591154a86ull},  // sliver
        {kWindow, 90, 70, {{0x1.446c2cp+0f, 0x1.0b9a98p-1f, 0, 0x1.eec7e2p+0f},
            {-0x1.4d452ep-2f, -0x1.b7babep-3f, 0, 0x1.84fa9ep-2f},
            {0x1.4786ap-5f, -0x1.0374d8p-4f, 0, 0x1.748024p+1f}}, Facing::back, 74, 0x3c40a97a4e3e6225ull},  // persp
        {kWindow, 90, 70, {{-0x1.5faa54p-1f, -0x1.534274p-1f, 0, 0x1.0cd9dep+1f},
            {-0x1.5fcdd4p-5f, 0x1.dadb82p+0f, 0, 0x1.fb0428p+0f},
            {0x1.19dde8p-1f, 0x1.6ae3ccp+1f, 0, 0x1.c9769cp+1f}}, Facing::back, 209, 0x8b135e24056a5d08ull},  // persp
        {kFbo, 200, 150, {{-0x1.dd32cep-1f, 0x1.18ea48p-1f, 0, 1}, {-0x1.737dbap-6f, 0x1.7d89ccp-1f, 0, 1},
            {0x1.8ad0dp-1f, -0x1.a4da56p-2f, 0, 1}}, Facing::back, 4529, 0xdff7be1ebc683562ull},  // rand
    };
    int separate_differs = 0;
    for (std::size_t n = 0; n < std::size(cases); ++n) {
        const Recorded& r = cases[n];
        INFO("case " << n);
        const Framebuffer fb{r.width, r.height, r.target};
        for (const ViewportArithmetic arith : {ViewportArithmetic::fused, ViewportArithmetic::separate}) {
            WindowCoord v[3];
            for (int k = 0; k < 3; ++k) v[k] = viewport_transform(r.clip[k], fb, arith);
            std::vector<int> idx;
            const Facing f = rasterize_triangle(v, fb, [&](int x, int y) { idx.push_back(y * fb.width + x); });
            std::sort(idx.begin(), idx.end());
            const bool same = long(idx.size()) == r.pixels && fnv1a(idx) == r.hash &&
                              (r.pixels == 0 || f == r.facing);
            if (arith == ViewportArithmetic::fused)
                CHECK(same);
            else if (!same)
                ++separate_differs;
        }
    }
    CHECK(separate_differs > 0);  // the recorded cases do tell fused from separate arithmetic
}

TEST_CASE("Front faces of a convex mesh cover each pixel inside its silhouette exactly once")
{
    const TetMesh box = box_mesh();
    const MeshTopology topo = build_topology(box);
    const Framebuffer fb = fbo(96, 72);
    const double views[][2] = {{0, 0}, {30, 20}, {-65, 40}, {140, -35}, {90, 0}};
    for (const auto& view : views) {
        SECTION("view " + std::to_string(int(view[0])) + "," + std::to_string(int(view[1]))) {
            Camera cam;
            const std::vector<WindowCoord> w = project(box, fb, view[0], view[1], &cam);
            std::vector<int> front(std::size_t(fb.width * fb.height), 0), back = front;
            std::vector<glm::dvec2> hull_points;
            for (const Face& f : topo.faces) {
                if (!f.boundary()) continue;
                const WindowCoord v[3] = {w[f.v[0]], w[f.v[1]], w[f.v[2]]};
                for (const WindowCoord& p : v) hull_points.push_back({p.x, p.y});
                std::vector<int>& target = setup_triangle(v, fb).facing == Facing::front ? front : back;
                rasterize_triangle(v, fb, [&](int x, int y) { ++target[std::size_t(y * fb.width + x)]; });
            }
            const std::vector<glm::dvec2> hull = convex_hull(hull_points);
            const Bounds b = mesh_bounds(box);
            long inside = 0, wrong = 0, double_hits = 0, unbalanced = 0, spec_disagree = 0;
            for (int y = 0; y < fb.height; ++y)
                for (int x = 0; x < fb.width; ++x) {
                    const std::size_t k = std::size_t(y * fb.width + x);
                    if (front[k] > 1) ++double_hits;
                    if (front[k] != back[k]) ++unbalanced;
                    // Snapping moves vertices by at most 1/512 pixel: 0.01 pixel from the silhouette is unambiguous.
                    const double d = inside_distance(hull, x + 0.5, y + 0.5);
                    if (d > 0.01) {
                        ++inside;
                        if (front[k] != 1) ++wrong;
                    } else if (d < -0.01 && front[k] != 0) {
                        ++wrong;
                    }
                    // GL row y is image row height - 1 - y: the ray of docs/spec.md §2 through that pixel hits the box
                    // iff covered.
                    if (std::fabs(d) > 0.05 &&
                        ray_hits_box(camera_ray(cam, fb.width, fb.height, x, spec_row(y, fb.height)), b.lo, b.hi) !=
                            (front[k] == 1))
                        ++spec_disagree;
                }
            INFO(inside << " pixels inside the silhouette");
            CHECK(inside > 500);
            CHECK(double_hits == 0);
            CHECK(wrong == 0);
            CHECK(unbalanced == 0);
            CHECK(spec_disagree == 0);
        }
    }
}

TEST_CASE("Each tetrahedron's faces cover every pixel as often front-facing as back-facing")
{
    struct Named {
        const char* name;
        TetMesh mesh;
    };
    const Named meshes[] = {{"box", box_mesh()}, {"torus-small", load_builtin("builtin:torus-small")}};
    for (const Named& m : meshes) {
        const MeshTopology topo = build_topology(m.mesh);
        for (const Framebuffer& fb : {fbo(80, 60), window(80, 60)}) {
            SECTION(std::string(m.name) + (fb.target == RenderTarget::fbo ? " (fbo)" : " (window)")) {
                const std::vector<WindowCoord> w = project(m.mesh, fb, 25, 35);
                // Every unique face rasterized once, as HAVS draws them; facing with the face's own orientation,
                // which points out of tet[0] (and into tet[1]).
                std::vector<std::vector<int>> pixels(topo.faces.size());
                std::vector<int> sign(topo.faces.size(), 0);
                std::vector<int> surface(std::size_t(fb.width * fb.height), 0);
                long front_hits = 0, back_hits = 0;
                for (std::size_t i = 0; i < topo.faces.size(); ++i) {
                    const Face& f = topo.faces[i];
                    const WindowCoord v[3] = {w[f.v[0]], w[f.v[1]], w[f.v[2]]};
                    const Facing facing = rasterize_triangle(v, fb, [&](int x, int y) {
                        pixels[i].push_back(y * fb.width + x);
                    });
                    sign[i] = facing == Facing::front ? 1 : -1;
                    if (f.boundary())
                        for (int p : pixels[i]) surface[std::size_t(p)] += sign[i];
                }
                std::vector<int> acc(surface.size(), 0);
                long unbalanced_tets = 0;
                for (std::size_t t = 0; t < m.mesh.tets.size(); ++t) {
                    for (int j = 0; j < 4; ++j) {
                        const int32_t fi = topo.tet_faces[t][std::size_t(j)];
                        const bool own = topo.faces[std::size_t(fi)].tet[0] == int32_t(t);
                        const int s = own ? sign[std::size_t(fi)] : -sign[std::size_t(fi)];
                        for (int p : pixels[std::size_t(fi)]) {
                            acc[std::size_t(p)] += s;
                            (s > 0 ? front_hits : back_hits) += 1;
                        }
                    }
                    bool balanced = true;
                    for (int j = 0; j < 4; ++j)
                        for (int p : pixels[std::size_t(topo.tet_faces[t][std::size_t(j)])]) {
                            if (acc[std::size_t(p)] != 0) balanced = false;
                            acc[std::size_t(p)] = 0;
                        }
                    if (!balanced) ++unbalanced_tets;
                }
                INFO(m.mesh.tets.size() << " tetrahedra, " << topo.faces.size() << " faces");
                CHECK(front_hits > 1000);
                CHECK(unbalanced_tets == 0);
                CHECK(front_hits == back_hits);
                // The boundary alone is a closed surface too.
                CHECK(std::count(surface.begin(), surface.end(), 0) == long(surface.size()));
            }
        }
    }
}
