// The ground truth against scenes whose images are known in closed form (pbrt-style "expected value" tests).
#include <cmath>
#include <functional>
#include <numeric>
#include <random>

#include <glm/geometric.hpp>

#include "reference/builtin_mesh.h"
#include "reference/cells.h"
#include "reference/ray_integrator.h"
#include "reference/reference_renderer.h"
#include "box_mesh.h"
#include "test_support.h"

using namespace uvr;
using test::box_chord;
using test::box_mesh;

namespace {

// Per-pixel agreement with an analytic value: the integral itself is exact to ~1e-15 (test_segment_integral), a
// ray's length inside the mesh is a sum of double-precision plane distances (relative error ~1e-15 per step, a few
// hundred steps), and the image is rounded to float32 (6e-8 relative). 1e-6 absolute covers all of it with margin
// while any skipped tetrahedron (a leak) changes the transmittance by far more.
constexpr double kPixelTolerance = 1e-6;

TransferFunction homogeneous(double tau, glm::dvec3 c)
{
    TransferFunction tf;
    tf.color = {{0.0, c}};
    tf.extinction = {{0.0, tau}};
    return tf;
}

// Every pixel of `img` against the premultiplied RGBA `expected` gives its camera ray: the largest channel error, and
// the largest expected alpha (so that a test can require that the scene is not empty).
struct PixelCheck {
    double worst = 0.0, largest_alpha = 0.0;
};
PixelCheck check_pixels(const Image& img, const Camera& cam, const std::function<glm::dvec4(const Ray&)>& expected)
{
    PixelCheck pc;
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            const glm::dvec4 e = expected(camera_ray(cam, img.width, img.height, i, j));
            pc.largest_alpha = std::max(pc.largest_alpha, e.a);
            for (int k = 0; k < 4; ++k) pc.worst = std::max(pc.worst, std::fabs(img.pixel(i, j)[k] - e[k]));
        }
    return pc;
}

// Beer-Lambert along the chord of the box [lo, hi]: colour c, extinction tau.
glm::dvec4 beer_lambert(const Ray& r, const glm::dvec3& lo, const glm::dvec3& hi, double tau, const glm::dvec3& c)
{
    double t0, t1;
    const double len = box_chord(r, lo, hi, t0, t1) ? t1 - t0 : 0.0;
    const double alpha = 1.0 - std::exp(-tau * len);
    return glm::dvec4(c * alpha, alpha);
}

}  // namespace

TEST_CASE("a homogeneous box follows Beer-Lambert at every pixel")
{
    const TetMesh mesh = box_mesh(6, [](const glm::dvec3&) { return 0.5; }, 0.2);
    const MeshTopology topo = build_topology(mesh);
    const double tau = 0.3;
    const glm::dvec3 c(0.9, 0.6, 0.3);
    const RayIntegrator ri(mesh, topo, 0, homogeneous(tau, c));
    for (const double az : {0.0, 33.0, 45.0}) {
        const Camera cam = default_camera(mesh_bounds(mesh), 1.0, az, az / 2.0);
        ReferenceStats stats;
        const Image img = render_reference(ri, cam, 48, 48, stats);
        CHECK(stats.failures == 0);
        const double worst =
            check_pixels(img, cam, [&](const Ray& r) { return beer_lambert(r, glm::dvec3(0.0), glm::dvec3(6.0), tau, c); })
                .worst;
        INFO("azimuth " << az << ": largest error " << worst);
        CHECK(worst <= kPixelTolerance);
    }
}

TEST_CASE("a globally linear field across a box gives each ray one analytic segment")
{
    // s = x + 2y + 3z is linear in every tetrahedron and continuous: the whole chord is one linear segment, whose
    // integral the closed form gives directly (checked against the oracle in test_segment_integral).
    auto field = [](const glm::dvec3& p) { return (p.x + 2.0 * p.y + 3.0 * p.z) / 36.0; };
    const TetMesh mesh = box_mesh(6, field, 0.25, 5);
    const MeshTopology topo = build_topology(mesh);
    TransferFunction tf;
    tf.color = {{0.0, {1, 0, 0}}, {1.0, {0, 0, 1}}};
    tf.extinction = {{0.0, 0.05}, {1.0, 0.6}};
    const RayIntegrator ri(mesh, topo, 0, tf);
    const SegmentIntegrator seg(tf);
    const Camera cam = default_camera(mesh_bounds(mesh), 1.0, 20.0, 35.0);
    ReferenceStats stats;
    const Image img = render_reference(ri, cam, 40, 40, stats);
    CHECK(stats.failures == 0);
    const auto chord = [&](const Ray& r) {
        double t0, t1;
        return box_chord(r, glm::dvec3(0.0), glm::dvec3(6.0), t0, t1)
                   ? seg.integrate(field(r.origin + t0 * r.dir), field(r.origin + t1 * r.dir), t1 - t0)
                   : glm::dvec4(0.0);
    };
    const double worst = check_pixels(img, cam, chord).worst;
    INFO("largest error " << worst);
    CHECK(worst <= kPixelTolerance);
}

TEST_CASE("rays aimed exactly at vertices and edges of a structured grid do not leak")
{
    // An unjittered grid seen straight down an axis: every ray of an odd-sized image through the centre column hits
    // vertices and edges exactly; an orthographic camera aligned with the grid puts rays on faces and edges.
    const TetMesh mesh = box_mesh(4, [](const glm::dvec3&) { return 0.0; });
    const MeshTopology topo = build_topology(mesh);
    const double tau = 0.7;
    const RayIntegrator ri(mesh, topo, 0, homogeneous(tau, {1, 1, 1}));
    const double expected_alpha = 1.0 - std::exp(-tau * 4.0);
    SECTION("orthographic, rays through every vertex column, edge and face")
    {
        Camera cam;
        cam.eye = {2.0, 2.0, 10.0};
        cam.target = {2.0, 2.0, 0.0};
        cam.orthographic = true;
        cam.ortho_height = 4.0;
        // 16 pixels over a height of 4 put pixel centres at 0.125 + 0.25 k; shifting the eye by 0.125 moves them to
        // multiples of 0.25, so every 4th row and column of rays runs exactly along grid planes, and their crossings
        // run exactly through vertex columns.
        cam.eye += glm::dvec3(0.125, 0.125, 0.0);
        cam.target += glm::dvec3(0.125, 0.125, 0.0);
        ReferenceStats stats;
        const Image img = render_reference(ri, cam, 16, 16, stats);
        CHECK(stats.failures == 0);
        int on_vertex = 0;
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                const Ray r = camera_ray(cam, 16, 16, i, j);
                if (r.origin.x < 0.0 || r.origin.x > 4.0 || r.origin.y < 0.0 || r.origin.y > 4.0) continue;
                INFO("pixel " << i << ", " << j << " at (" << r.origin.x << ", " << r.origin.y << ")");
                const float a = img.pixel(i, j)[3];
                if (r.origin.x == 0.0 || r.origin.x == 4.0 || r.origin.y == 0.0 || r.origin.y == 4.0) {
                    // A ray lying in the mesh's outer boundary plane grazes it: inside and outside are both
                    // right, and the value must be one of the two, never something in between.
                    CHECK((a == 0.0f || std::fabs(a - expected_alpha) <= kPixelTolerance));
                    continue;
                }
                on_vertex += std::floor(r.origin.x) == r.origin.x && std::floor(r.origin.y) == r.origin.y;
                CHECK(std::fabs(a - expected_alpha) <= kPixelTolerance);
            }
        CHECK(on_vertex >= 9);  // the test really aims at interior vertices
    }
    SECTION("perspective rays through the grid's diagonal vertices")
    {
        Camera cam;
        cam.eye = {-3.0, -3.0, -3.0};
        cam.target = {2.0, 2.0, 2.0};
        cam.up = {0.0, 0.0, 1.0};
        cam.fovy_deg = 10.0;
        // The centre pixel of an odd image looks along the main diagonal through (0,0,0), (1,1,1), ... (4,4,4).
        ReferenceStats stats;
        const Image img = render_reference(ri, cam, 15, 15, stats);
        CHECK(stats.failures == 0);
        const Ray r = camera_ray(cam, 15, 15, 7, 7);
        double t0, t1;
        REQUIRE(box_chord(r, glm::dvec3(0.0), glm::dvec3(4.0), t0, t1));
        CHECK(std::fabs(img.pixel(7, 7)[3] - (1.0 - std::exp(-tau * (t1 - t0)))) <= kPixelTolerance);
    }
}

TEST_CASE("two disjoint blocks: the gap between them contributes nothing")
{
    TetMesh a = box_mesh(3, [](const glm::dvec3&) { return 0.0; }, 0.2, 3);
    const std::size_t np = a.points.size(), nt = a.tets.size();
    for (std::size_t i = 0; i < np; ++i) a.points.push_back(a.points[i] + glm::dvec3(0.0, 0.0, 5.0));
    for (std::size_t t = 0; t < nt; ++t) {
        Tet tt = a.tets[t];
        for (auto& v : tt) v += uint32_t(np);
        a.tets.push_back(tt);
    }
    a.fields[0].values.resize(a.points.size(), 0.0);
    finalize_mesh(a);
    const MeshTopology topo = build_topology(a);
    const double tau = 0.4;
    const RayIntegrator ri(a, topo, 0, homogeneous(tau, {0.5, 0.5, 0.5}));
    // Looking along z through both blocks: 3 + 3 units of medium, the 2-unit gap empty.
    Camera cam;
    cam.eye = {1.5, 1.5, 20.0};
    cam.target = {1.5, 1.5, 0.0};
    cam.orthographic = true;
    cam.ortho_height = 2.0;
    ReferenceStats stats;
    const Image img = render_reference(ri, cam, 8, 8, stats);
    CHECK(stats.failures == 0);
    CHECK(stats.entries == 2 * 64);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) CHECK(std::fabs(img.pixel(i, j)[3] - (1.0 - std::exp(-tau * 6.0))) <= kPixelTolerance);
}

TEST_CASE("the torus: rays through the hole see nothing, rays through the ring see both sides")
{
    const TetMesh torus = load_builtin("builtin:torus-small");
    const MeshTopology topo = build_topology(torus);
    const double tau = 0.8;
    const RayIntegrator ri(torus, topo, 0, homogeneous(tau, {1, 1, 1}));
    RayStats st;
    // Along the axis through the hole: empty.
    CHECK(ri.integrate({{0.0, 0.0, 5.0}, {0.0, 0.0, -1.0}}, st).a == 0.0);
    // In the equatorial plane through the centre: two chords of the tube, each 2r long (the polyhedral torus is a
    // little thinner than the smooth one: its faces are chords of the circles).
    const glm::dvec4 c = ri.integrate({{-5.0, 0.0, 0.0}, {1.0, 0.0, 0.0}}, st);
    CHECK(st.entries == 2);
    const double len = -std::log(1.0 - c.a) / tau;
    CHECK(len <= 4.0 * kTorusMinorRadius + 1e-12);
    CHECK(len >= 4.0 * kTorusMinorRadius * 0.95);
    CHECK(st.failures == 0);
}

TEST_CASE("the image does not depend on the order of vertices and tetrahedra")
{
    const TetMesh m = load_builtin("builtin:torus-small");
    TetMesh shuffled = m;
    std::mt19937 rng(99);
    std::vector<uint32_t> perm(m.points.size());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    for (std::size_t i = 0; i < m.points.size(); ++i) {
        shuffled.points[perm[i]] = m.points[i];
        shuffled.fields[0].values[perm[i]] = m.fields[0].values[i];
    }
    for (auto& t : shuffled.tets) {
        for (auto& v : t) v = perm[v];
        std::rotate(t.begin(), t.begin() + 1, t.end());  // an odd permutation: finalize re-orients
    }
    std::shuffle(shuffled.tets.begin(), shuffled.tets.end(), rng);
    finalize_mesh(shuffled);
    const TransferFunction tf = default_transfer_function(field_range(m.fields[0]), 3.0);
    const MeshTopology ta = build_topology(m), tb = build_topology(shuffled);
    const RayIntegrator ra(m, ta, 0, tf), rb(shuffled, tb, 0, tf);
    const Camera cam = default_camera(mesh_bounds(m), 1.0, 30.0, 40.0);
    ReferenceStats sa, sb;
    const Image a = render_reference(ra, cam, 64, 64, sa), b = render_reference(rb, cam, 64, 64, sb);
    double worst = 0.0;
    for (std::size_t k = 0; k < a.rgba.size(); ++k) worst = std::max(worst, double(std::fabs(a.rgba[k] - b.rgba[k])));
    INFO("largest difference " << worst);
    // The same segments are found; only the rounding of plane distances computed from differently ordered vertices
    // differs, far below the per-pixel tolerance.
    CHECK(worst <= kPixelTolerance);
    CHECK(sa.failures == 0);
    CHECK(sb.failures == 0);
}

TEST_CASE("a camera inside the mesh, or exactly on its boundary, sees the analytic chord from the eye on")
{
    // The linear field of the test above, so that the cut first segment's scalar is checked too.
    auto field = [](const glm::dvec3& p) { return (p.x + 2.0 * p.y + 3.0 * p.z) / 36.0; };
    TransferFunction tf;
    tf.color = {{0.0, {1, 0, 0}}, {1.0, {0, 0, 1}}};
    tf.extinction = {{0.0, 0.05}, {1.0, 0.6}};
    const SegmentIntegrator seg(tf);
    struct Case {
        const char* what;
        glm::dvec3 eye, target;
        double jitter;
    };
    for (const Case& c : {Case{"inside a cell", {2.3, 3.1, 2.7}, {6.0, 4.0, 5.0}, 0.25},
                          Case{"exactly on a grid vertex, rays along edges and faces", {3.0, 3.0, 3.0}, {6.0, 3.0, 3.0}, 0.0},
                          Case{"exactly on a boundary face, looking in", {3.2, 2.9, 0.0}, {3.0, 3.0, 6.0}, 0.0},
                          Case{"on a boundary face, looking out", {3.2, 2.9, 6.0}, {3.0, 3.0, 9.0}, 0.0}}) {
        INFO(c.what);
        const TetMesh mesh = box_mesh(6, field, c.jitter, 9);
        const MeshTopology topo = build_topology(mesh);
        const RayIntegrator ri(mesh, topo, 0, tf);
        Camera cam;
        cam.eye = c.eye;
        cam.target = c.target;
        cam.up = glm::dvec3(0.0, 1.0, 0.0) + glm::dvec3(0.0, 0.0, 0.1);
        cam.fovy_deg = 100.0;
        ReferenceStats stats;
        const Image img = render_reference(ri, cam, 40, 40, stats);
        CHECK(stats.failures == 0);
        const PixelCheck pc = check_pixels(img, cam, [&](const Ray& r) {
            double t0, t1;
            return box_chord(r, glm::dvec3(0.0), glm::dvec3(6.0), t0, t1)
                       ? seg.integrate(field(r.origin + t0 * r.dir), field(r.origin + t1 * r.dir), t1 - t0)
                       : glm::dvec4(0.0);
        });
        const double worst = pc.worst, largest_alpha = pc.largest_alpha;
        INFO("largest error " << worst << ", largest expected alpha " << largest_alpha);
        CHECK(worst <= kPixelTolerance);
        if (std::string(c.what).find("looking out") == std::string::npos) CHECK(largest_alpha > 0.1);
    }
}

TEST_CASE("far from the origin: coordinates at 1e8 with features at 1e-3 keep Beer-Lambert")
{
    // The box of the first test scaled to cells of 1e-3 and moved to 1e8: its features are 1e-11 of its coordinates.
    constexpr double kOffset = 1e8, kCell = 1e-3;
    TetMesh mesh = box_mesh(6, [](const glm::dvec3&) { return 0.5; }, 0.2);
    for (auto& p : mesh.points) p = glm::dvec3(kOffset) + p * kCell;
    const MeshTopology topo = build_topology(mesh);
    const double tau = 0.3 / kCell;
    const glm::dvec3 c(0.9, 0.6, 0.3);
    const RayIntegrator ri(mesh, topo, 0, homogeneous(tau, c));
    const Camera cam = default_camera(mesh_bounds(mesh), 1.0, 33.0, 16.5);
    ReferenceStats stats;
    const Image img = render_reference(ri, cam, 48, 48, stats);
    CHECK(stats.failures == 0);
    const PixelCheck pc = check_pixels(img, cam, [&](const Ray& r) {
        return beer_lambert(r, glm::dvec3(kOffset), glm::dvec3(kOffset + 6.0 * kCell), tau, c);
    });
    const double worst = pc.worst, largest_alpha = pc.largest_alpha;
    INFO("largest error " << worst << ", largest alpha " << largest_alpha);
    // The same tolerance as at the origin: the walk forms every plane distance from differences of nearby points
    // (a - origin, exact for points within a factor of two of each other), so coordinates at 1e8 cost no precision.
    CHECK(worst <= kPixelTolerance);
    CHECK(largest_alpha > 0.5);
}
