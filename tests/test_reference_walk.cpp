// The ground truth's walk where it is hardest: rays that graze the edges of the faces they enter and cross.
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "reference/ray_integrator.h"
#include "box_mesh.h"
#include "test_support.h"

using namespace uvr;
using test::box_chord;
using test::box_mesh;

namespace {

// A homogeneous box's colour along one ray is Beer-Lambert's closed form of its chord. The walk's lengths are sums of
// double-precision ray parameters (about 1e-15 relative a step, a handful of steps in a box of two cells): 1e-9 is
// a million times that, while a run the walk loses or cuts short (a ray entering just beside an edge) changes alpha
// by up to 0.75 here.
constexpr double kRayTolerance = 1e-9;

}  // namespace

TEST_CASE("rays entering a hair beside a boundary edge are integrated whole")
{
    // Embree finds the entry face in float: a ray within float's rounding (about 1e-8 here) of an edge of the front
    // face z = 0 may be handed the face beside the one it crosses in double. Rays aimed 1e-12 to 1e-6 beside the inner
    // edge lines of that face (the middle grid lines and both diagonals of every cell), from random directions. (Beside
    // the box's own edges, where the ray grazes a side face, Embree's float entry can cost up to 6e-6 of alpha, with
    // this walk as with the previous one: docs/reference.md, "Known limits".)
    const TetMesh mesh = box_mesh(2, [](const glm::dvec3&) { return 0.5; });
    const MeshTopology topo = build_topology(mesh);
    TransferFunction tf;
    tf.color = {{0.0, glm::dvec3(0.9, 0.6, 0.3)}};
    tf.extinction = {{0.0, 0.7}};
    const RayIntegrator ri(mesh, topo, 0, tf);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    RayStats stats;
    double worst = 0.0;
    for (int n = 0; n < 20000; ++n) {
        const int ci = int(U(rng) * 2.0), cj = int(U(rng) * 2.0), line = int(U(rng) * 4.0);
        const double a = 0.1 + 0.8 * U(rng),
                     offset = (U(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -12.0 + 6.0 * U(rng));
        // A point on an inner edge line of the face, away from the box's own edges (x = 1 or y = 1, or a diagonal of
        // cell (ci, cj)), and the line's normal in the face.
        const glm::dvec2 on[4] = {{1.0, 2.0 * a}, {2.0 * a, 1.0}, {ci + a, cj + a}, {ci + a, cj + 1 - a}};
        const glm::dvec2 normal[4] = {{1, 0}, {0, 1}, {M_SQRT1_2, -M_SQRT1_2}, {M_SQRT1_2, M_SQRT1_2}};
        const glm::dvec2 target = on[line] + offset * normal[line];
        const double z = U(rng) * 2.0 - 1.0, phi = U(rng) * 2.0 * M_PI;  // a direction with dir.z >= 0.4
        const double dz = 0.4 + 0.6 * std::fabs(z), r = std::sqrt(1.0 - dz * dz);
        const glm::dvec3 dir(r * std::cos(phi), r * std::sin(phi), dz);
        const Ray ray{glm::dvec3(target, 0.0) - (1.0 + 2.0 * U(rng)) * dir, dir};
        const glm::dvec4 got = ri.integrate(ray, stats);
        double t0, t1;
        const double len = box_chord(ray, glm::dvec3(0.0), glm::dvec3(2.0), t0, t1) ? t1 - t0 : 0.0;
        const double alpha = 1.0 - std::exp(-0.7 * len);
        const glm::dvec4 want(glm::dvec3(0.9, 0.6, 0.3) * alpha, alpha);
        for (int k = 0; k < 4; ++k) worst = std::max(worst, std::fabs(got[k] - want[k]));
    }
    INFO("largest error " << worst << ", runs walked by planes " << stats.plane_walks);
    CHECK(stats.failures == 0);
    CHECK(worst <= kRayTolerance);
    // The case the test is for happened: entries just outside their face, which the walk hands to the plane walk.
    CHECK(stats.plane_walks > 0);
}
