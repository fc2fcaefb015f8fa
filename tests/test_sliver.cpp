// The degenerate geometry: a conforming mesh holding a tetrahedron of 1e-12 relative volume (a sliver between two
// layers of cells) and coplanar faces. Every algorithm that renders tetrahedral meshes gives a finite image; the
// reference stays watertight against the analytic chord (the mesh is a convex bipyramid, so Beer-Lambert along each
// ray's chord through it is the expected value), and HAVS and VICP with exact segments equal the reference.
#include <cmath>

#include <glm/geometric.hpp>

#include "gpu/vicp/vicp.h"
#include "havs_convergence.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

// The reference against Beer-Lambert's closed form: the bar of test_reference_analytic.cpp (double integration, a
// float32 image: a few roundings of an alpha below 1).
constexpr double kAnalyticTolerance = 1e-6;
// HAVS and VICP with exact segments against the reference: HAVS's convergence bars (tests/havs_convergence.h), and
// VICP's largest error, 1e-3 (tests/test_vicp.cpp, where its size is explained; its RMSE bar is HAVS's).
using test::kConvergenceMax;
using test::kConvergenceRmse;
constexpr double kVicpMax = 1e-3;

constexpr double kExtinction = 2.0;
// The sliver's height below the middle triangle: its volume is 1e-12 of its longest edge cubed, two orders of
// magnitude above what the data model calls degenerate (kDegenerateRelativeVolume), so it is a real cell.
constexpr double kSliverHeight = 1.2e-12;

// The bipyramid: triangle ABC in the plane z = 0, apexes P above and Q below; the point D lies kSliverHeight below the
// triangle, so the cells are (A, B, C, P) above, the sliver (A, B, C, D), and three cells from D down to Q.
struct Bipyramid {
    glm::dvec3 a{0.0, 0.0, 0.0}, b{1.0, 0.0, 0.0}, c{0.5, std::sqrt(0.75), 0.0};
    glm::dvec3 g = (a + b + c) / 3.0;
    glm::dvec3 p = g + glm::dvec3(0.0, 0.0, 0.8), q = g - glm::dvec3(0.0, 0.0, 0.8);
    glm::dvec3 d = glm::dvec3(0.45, 0.3, -kSliverHeight);
};

test::Scene sliver_scene()
{
    const Bipyramid bp;
    TetMesh m;
    m.source = "sliver bipyramid";
    m.points = {bp.a, bp.b, bp.c, bp.p, bp.q, bp.d};
    m.tets = {{0, 1, 2, 3}, {0, 1, 2, 5}, {0, 1, 5, 4}, {1, 2, 5, 4}, {2, 0, 5, 4}};
    ScalarField f{"s", {}};
    for (const auto& x : m.points) f.values.push_back(x.x + x.y + x.z);
    m.fields.push_back(f);
    finalize_mesh(m);
    test::Scene s = test::make_scene(std::move(m), 0);
    s.tf.color = {{0.0, {0.2, 0.6, 1.0}}};
    s.tf.extinction = {{0.0, kExtinction}};
    return s;
}

// The chord of the convex bipyramid along r: the intersection of the half-spaces of its six faces.
double chord(const Ray& r)
{
    const Bipyramid bp;
    const glm::dvec3 faces[6][3] = {{bp.a, bp.b, bp.p}, {bp.b, bp.c, bp.p}, {bp.c, bp.a, bp.p},
                                    {bp.b, bp.a, bp.q}, {bp.c, bp.b, bp.q}, {bp.a, bp.c, bp.q}};
    double t0 = 0.0, t1 = INFINITY;
    for (const auto& f : faces) {
        glm::dvec3 n = glm::cross(f[1] - f[0], f[2] - f[0]);
        if (glm::dot(n, bp.g - f[0]) > 0.0) n = -n;  // outward
        const double num = glm::dot(n, f[0] - r.origin), den = glm::dot(n, r.dir);
        if (den == 0.0) {
            if (num < 0.0) return 0.0;  // parallel and outside
            continue;
        }
        const double t = num / den;
        if (den < 0.0)
            t0 = std::max(t0, t);
        else
            t1 = std::min(t1, t);
    }
    return t1 > t0 ? t1 - t0 : 0.0;
}

}  // namespace

TEST_CASE("a mesh with a sliver of 1e-12 volume: every algorithm gives a finite image, the reference the analytic one")
{
    const test::Scene s = sliver_scene();
    REQUIRE(s.mesh.tets.size() == 5);
    const Bounds bounds = mesh_bounds(s.mesh);
    const int size = 64;
    // Through the sliver (from +z, across its plane), grazing it (from +y at 89 degrees: rays nearly in the plane z = 0
    // of its large faces, which the cells above and below share), and obliquely.
    for (const auto& [az, el] : {std::pair{0.0, 0.0}, {0.0, 89.0}, {35.0, 25.0}}) {
        const Camera cam = default_camera(bounds, 1.0, az, el);
        const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
        ReferenceStats rs;
        const Image ref = render_reference(ri, cam, size, size, rs);
        double worst = 0.0, largest_alpha = 0.0;
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
                const double alpha = 1.0 - std::exp(-kExtinction * chord(camera_ray(cam, size, size, i, j)));
                largest_alpha = std::max(largest_alpha, alpha);
                worst = std::max(worst, std::fabs(double(ref.pixel(i, j)[3]) - alpha));
            }
        VicpOptions vo;
        vo.segment = SegmentMode::exact;
        vo.interpolation = InterpolationMode::exact;
        const VicpFrame vicp = VicpRenderer(s.mesh, s.topo, s.field, s.tf, vo).render(cam, size, size);
        const HavsFrame havs =
            HavsRenderer(s.mesh, s.topo, s.field, s.tf, test::exact_havs_options(test::kConvergenceK)).render(cam, size, size);
        // The default configurations (pre-integrated tables) too: finite is all that is asked of them here.
        const VicpFrame vicp_table = VicpRenderer(s.mesh, s.topo, s.field, s.tf, VicpOptions{}).render(cam, size, size);
        const HavsFrame havs_table = HavsRenderer(s.mesh, s.topo, s.field, s.tf, HavsOptions{}).render(cam, size, size);
        const test::ImageErrors ev = test::image_errors(vicp.image, ref), eh = test::image_errors(havs.image, ref);
        INFO("view az " << az << " el " << el << ": reference against the chord " << worst << " (largest alpha "
                        << largest_alpha << ", " << rs.failures << " abandoned rays); VICP RMSE " << ev.rmse << " max "
                        << ev.max_abs << "; HAVS RMSE " << eh.rmse << " max " << eh.max_abs);
        CHECK(largest_alpha > 0.5);
        CHECK(rs.failures == 0);
        CHECK(worst <= kAnalyticTolerance);
        CHECK(test::all_finite(ref));
        CHECK(test::all_finite(vicp.image));
        CHECK(test::all_finite(havs.image));
        CHECK(test::all_finite(vicp_table.image));
        CHECK(test::all_finite(havs_table.image));
        CHECK(ev.rmse <= kConvergenceRmse);
        CHECK(ev.max_abs <= kVicpMax);
        CHECK(eh.rmse <= kConvergenceRmse);
        CHECK(eh.max_abs <= kConvergenceMax);
    }
}
