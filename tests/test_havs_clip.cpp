// The clip stage (gpu/pipeline/clip.h) and HAVS through it: views that cut the mesh at the near plane (a camera inside the mesh,
// on its boundary) or at the image's sides (a view closer than the mesh's size), the "a camera inside the
// mesh, a camera exactly on a face". The GL side of the same views is in test_havs_gl_frame.cpp.
#include <cmath>
#include <cstring>
#include <random>

#include <glm/geometric.hpp>

#include "gpu/pipeline/clip.h"
#include "havs_convergence.h"

using namespace uvr;
using namespace uvr::gpu;
using test::kConvergenceMax;
using test::kConvergenceRmse;
using test::Scene;
using test::box_scene;
using test::looking;

namespace {

// How far from a clip plane a crossing may lie, relative to the size of its clip coordinates. The crossing is
// interpolated in double between ends up to 14 units away, and its own coordinates can be a hundred times smaller
// than theirs (a crossing near the eye), so a few roundings of the ends' size become some 100 units of 2^-53 of its
// own: measured up to 2.4e-14 on the test's 20,000 pairs; 1e-13 is four times that.
constexpr double kCrossingTolerance = 1e-13;
// How exactly the near-plane sections of a box's cells add up to the box's cross-section, relative to the area: a
// few hundred sections, each area off by a few roundings (2^-53) of itself; measured 2.2e-16.
constexpr double kSectionAreaTolerance = 1e-14;
// How far a section's vertex may lie off the near plane (x = const, the view along +x): a position interpolated between
// ends within 4 units of the eye carries about one rounding of 4 (ulp 8.9e-16); measured 2.2e-16.
constexpr double kOnPlaneTolerance = 1e-15;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// HAVS (exact) against the reference, with the clip stage's counts.
void require_converges(const Scene& s, const Camera& cam, int width, int height, bool expect_near_sections)
{
    const test::HavsAndReference r = test::havs_and_reference(s, cam, width, height);
    const HavsStats& st = r.havs.stats;
    INFO("RMSE " << r.errors.rmse << ", max " << r.errors.max_abs << ", pixels over " << kConvergenceMax << ": "
                 << r.errors.over << "; " << st.clipped_faces << " faces clipped, " << st.culled_faces << " culled, "
                 << st.near_sections << " near sections, " << st.gpu_clipped << " triangles left for the GPU to clip, "
                 << st.max_fragments << " fragments at most");
    REQUIRE(st.max_fragments <= uint32_t(test::kConvergenceK));
    CHECK(st.clipped_faces > 0);
    CHECK(st.gpu_clipped == 0);
    if (expect_near_sections) CHECK(st.near_sections > 0);
    CHECK(r.errors.rmse <= kConvergenceRmse);
    CHECK(r.errors.max_abs <= kConvergenceMax);
    // The scene is not empty: the comparison has something to compare.
    double largest_alpha = 0.0;
    for (std::size_t p = 3; p < r.reference.rgba.size(); p += 4) largest_alpha = std::max(largest_alpha, double(r.reference.rgba[p]));
    CHECK(largest_alpha > 0.1);
}

}  // namespace

TEST_CASE("the clip stage makes a shared edge's crossing bit for bit the same from either end")
{
    const Camera cam = looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0});
    const ViewSetup vs = view_setup(cam, 64, 48, Bounds{{0, 0, 0}, {6, 6, 6}}, cam.eye);
    const ClipPlanes planes = inner_clip_planes(64, 48);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-8.0, 8.0), S(0.0, 1.0);
    int crossings = 0;
    for (int i = 0; i < 20000; ++i) {
        // Each vertex's scalar is drawn before its position: the statements fix the order, not the compiler.
        const double sa = S(rng);
        const glm::dvec3 pa{U(rng), U(rng), U(rng)};
        const double sb = S(rng);
        const glm::dvec3 pb{U(rng), U(rng), U(rng)};
        const ClipVertex a = clip_vertex(vs, pa, sa);
        const ClipVertex b = clip_vertex(vs, pb, sb);
        for (int plane = 0; plane < kClipPlaneCount; ++plane) {
            const double la = plane_value(planes, plane, a.c), lb = plane_value(planes, plane, b.c);
            if ((la < 0.0) == (lb < 0.0)) continue;
            ++crossings;
            const ClipVertex x = crossing(vs, planes, plane, a, b), y = crossing(vs, planes, plane, b, a);
            INFO("plane " << plane << ", pair " << i);
            REQUIRE((same_bits(x.p.x, y.p.x) && same_bits(x.p.y, y.p.y) && same_bits(x.p.z, y.p.z)));
            REQUIRE(same_bits(x.s, y.s));
            // On the plane, between the ends.
            const double size = std::fabs(x.c.x) + std::fabs(x.c.y) + std::fabs(x.c.z) + std::fabs(x.c.w);
            REQUIRE(std::fabs(plane_value(planes, plane, x.c)) <= kCrossingTolerance * size);
            REQUIRE(x.s >= std::min(a.s, b.s));
            REQUIRE(x.s <= std::max(a.s, b.s));
        }
    }
    CHECK(crossings > 10000);
}

TEST_CASE("near-plane sections of a box's cells tile the box's cross-section")
{
    // A camera inside a jittered 4^3 box looking along +x: the near plane is the plane x = eye.x + near, whose
    // cross-section with the box is the 4 x 4 square. The cells' sections must cover it once: their areas sum to 16.
    const TetMesh mesh = test::box_mesh(4, [](const glm::dvec3& p) { return p.x; }, 0.3, 5);
    for (const glm::dvec3 eye : {glm::dvec3(1.7, 2.2, 1.9), glm::dvec3(2.0, 2.0, 2.0)}) {
        const Camera cam = looking(eye, eye + glm::dvec3(1.0, 0.0, 0.0));
        const ViewSetup vs = view_setup(cam, 32, 32, mesh_bounds(mesh), cam.eye);
        REQUIRE(vs.near_cuts);
        const ClipPlanes planes = inner_clip_planes(32, 32);
        double area = 0.0, plane_x = 0.0;
        int sections = 0;
        std::vector<ClipVertex> poly;
        for (const Tet& t : mesh.tets) {
            ClipVertex v[4];
            for (int j = 0; j < 4; ++j) v[j] = clip_vertex(vs, mesh.points[t[std::size_t(j)]] - cam.eye, 0.0);
            near_section(vs, planes, v, poly);
            if (poly.empty()) continue;
            ++sections;
            REQUIRE(poly.size() >= 3);
            glm::dvec3 cross(0.0);
            for (std::size_t i = 0; i < poly.size(); ++i) cross += glm::cross(poly[i].p, poly[(i + 1) % poly.size()].p);
            area += 0.5 * glm::length(cross);
            plane_x = poly[0].p.x;
            for (const ClipVertex& p : poly) REQUIRE(std::fabs(p.p.x - plane_x) <= kOnPlaneTolerance);
        }
        INFO("eye " << eye.x << " " << eye.y << " " << eye.z << ": " << sections << " sections, area " << area
                    << ", plane at " << plane_x << " in front of the eye");
        CHECK(plane_x > 0.0);
        CHECK(plane_x <= 2.0 * kNearPlane * glm::length(mesh_bounds(mesh).extent()));
        CHECK(std::fabs(area - 16.0) <= kSectionAreaTolerance * 16.0);
    }
}

TEST_CASE("a camera inside the mesh or on its boundary: HAVS equals the reference")
{
    // The cases of the reference's own inside-camera test, which checks the reference against the analytic chord.
    for (const test::CutView& v : test::inside_box_views())
        DYNAMIC_SECTION(v.name) { require_converges(test::box_scene(6, v.jitter), v.camera, v.width, v.height, true); }
    SECTION("Blunt Fin, from inside its flow region")
    {
        const Scene s = test::blunt_fin();
        require_converges(s, test::inside_view(s), 96, 96, true);
    }
}

TEST_CASE("a view that cuts the mesh at the image's sides: HAVS equals the reference")
{
    // The camera outside the mesh but so close that the mesh fills more than the image: faces cross the side planes
    // (and the draw module would clip them), none the near plane.
    const Scene s = box_scene(6, 0.25);
    const test::HavsAndReference r = test::havs_and_reference(s, looking({3.1, 2.8, -1.5}, {3.0, 3.0, 6.0}, 60.0), 64, 64);
    INFO("RMSE " << r.errors.rmse << ", max " << r.errors.max_abs << "; " << r.havs.stats.clipped_faces
                 << " faces clipped, " << r.havs.stats.near_sections << " near sections");
    CHECK(r.havs.stats.clipped_faces > 0);
    CHECK(r.havs.stats.near_sections == 0);
    CHECK(r.havs.stats.gpu_clipped == 0);
    CHECK(r.errors.rmse <= kConvergenceRmse);
    CHECK(r.errors.max_abs <= kConvergenceMax);
}
