// The ground truth for regular grids (reference/volume_integrator) against what is known without it: Beer-
// Lambert's closed form in a constant volume, the tetrahedral reference on the same grid split into tetrahedra where
// the trilinear field is linear, and nested long-double quadrature of docs/spec.md §1's definitions where it is not.
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "quadrature_oracle.h"
#include "reference/cells.h"
#include "reference/ray_integrator.h"
#include "reference/topology.h"
#include "reference/volume_integrator.h"
#include "test_support.h"
#include "volume_scenes.h"

using namespace uvr;
using test::grid;

namespace {

// Agreement of two integrations of one ray in double: the quadrature's bar (kVolumeQuadratureTolerance, 1e-10) plus
// the rounding of a few hundred composited pieces (~1e-14 each) and of the tetrahedral reference's closed forms
// (~1e-15 each). The bar is 1e-9; anything skipped or doubled (a lost cell, a piece counted twice) costs
// orders of magnitude more.
constexpr double kRayTolerance = 1e-9;

// The same samples as a structured grid of points, split into tetrahedra.
TetMesh as_tetrahedra(const Volume& v)
{
    StructuredGrid g;
    g.source = "test grid";
    g.dims = v.dims;
    ScalarField f{"f", {}};
    std::size_t n = 0;
    for (int64_t k = 0; k < v.dims[2]; ++k)
        for (int64_t j = 0; j < v.dims[1]; ++j)
            for (int64_t i = 0; i < v.dims[0]; ++i) {
                g.points.push_back(v.origin + glm::dvec3(double(i), double(j), double(k)) * v.spacing);
                f.values.push_back(double(v.values[n++]));
            }
    g.point_fields.push_back(f);
    return tetrahedralize_structured(g);
}

TransferFunction ramp()
{
    TransferFunction tf;
    tf.color = {{0.0, {0.1, 0.2, 0.9}}, {0.5, {0.9, 0.8, 0.1}}, {1.0, {1.0, 0.1, 0.1}}};
    tf.extinction = {{0.0, 0.05}, {0.3, 0.8}, {0.6, 0.2}, {0.6, 1.4}, {1.0, 0.4}};  // with a jump at 0.6
    return tf;
}

// A linear field on a 6x5x7 grid of unequal spacing, integrated by the grid reference and by the tetrahedral reference
// on the same samples split into tetrahedra, ray by ray from four views at 32x32: their largest difference, the
// largest opacity, and the rays that meet the grid yet stay clear. Dyadic coefficients and coordinates, so that every
// sample is exact in the volume's float storage and the samples stay exactly linear.
struct LinearGridAgreement {
    double worst = 0.0, largest_alpha = 0.0;
    std::size_t clear_rays = 0;
};
LinearGridAgreement against_tetrahedra(const TransferFunction& tf)
{
    const auto linear = [](const glm::dvec3& p) { return 0.5 + 0.0625 * p.x - 0.03125 * p.y + 0.046875 * p.z; };
    const Volume v = grid({6, 5, 7}, {-1.0, 0.5, 2.0}, {0.75, 1.25, 0.5}, linear);
    const VolumeIntegrator vi(v, tf);
    const TetMesh mesh = as_tetrahedra(v);
    const MeshTopology topo = build_topology(mesh);
    const RayIntegrator ri(mesh, topo, 0, tf);
    LinearGridAgreement r;
    for (const auto& [az, el] : {std::pair{0.0, 0.0}, {30.0, 25.0}, {-75.0, -40.0}, {90.0, 0.0}}) {
        const Camera cam = default_camera(vi.bounds(), 1.0, az, el);
        for (int j = 0; j < 32; ++j)
            for (int i = 0; i < 32; ++i) {
                const Ray ray = camera_ray(cam, 32, 32, i, j);
                RayStats s1, s2;
                const glm::dvec4 a = vi.integrate(ray, s1), e = ri.integrate(ray, s2);
                for (int c = 0; c < 4; ++c) r.worst = std::max(r.worst, std::fabs(a[c] - e[c]));
                r.largest_alpha = std::max(r.largest_alpha, e.a);
                r.clear_rays += s2.entries > 0 && e.a == 0.0 ? 1 : 0;
            }
    }
    return r;
}

}  // namespace

TEST_CASE("a constant volume gives Beer-Lambert's closed form, from outside and from a camera inside")
{
    const Volume v = grid({4, 5, 3}, {1.0, -2.0, 0.5}, {0.5, 0.25, 1.5}, [](const glm::dvec3&) { return 0.4; });
    TransferFunction tf;
    tf.color = {{0.0, {0.3, 0.6, 0.9}}};
    tf.extinction = {{0.0, 0.7}};
    const VolumeIntegrator vi(v, tf);
    const Bounds b = vi.bounds();
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    double worst = 0.0;
    int hits = 0;
    for (int r = 0; r < 2000; ++r) {
        // z first: the statements fix the order of the draws, not the compiler.
        const auto draw = [&] {
            const double z = U(rng), y = U(rng), x = U(rng);
            return glm::dvec3(x, y, z);
        };
        const glm::dvec3 target = b.lo + draw() * b.extent();
        // Half the rays from outside, half from a point inside the box.
        const glm::dvec3 from =
            r % 2 ? b.lo + draw() * b.extent() : target + 20.0 * glm::normalize(draw() - glm::dvec3(0.5));
        const Ray ray{from, glm::normalize(target - from)};
        double t0 = 0.0, t1 = INFINITY;
        for (int a = 0; a < 3; ++a) {
            double ta = (b.lo[a] - from[a]) / ray.dir[a], tb = (b.hi[a] - from[a]) / ray.dir[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        const double alpha = 1.0 - std::exp(-0.7 * (t1 - t0));
        RayStats st;
        const glm::dvec4 got = vi.integrate(ray, st);
        const glm::dvec4 want(0.3 * alpha, 0.6 * alpha, 0.9 * alpha, alpha);
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::fabs(got[c] - want[c]));
        hits += st.entries ? 1 : 0;
    }
    INFO("largest error " << worst);
    CHECK(hits == 2000);
    CHECK(worst <= kRayTolerance);
}

TEST_CASE("a linear field on a grid gives the tetrahedral reference's integral on the grid split into tetrahedra")
{
    // Trilinear interpolation of a linear field is that field, and so is the tetrahedra's linear interpolation: the
    // two references must agree ray by ray, through a transfer function with kinks and a jump.
    const LinearGridAgreement r = against_tetrahedra(ramp());
    INFO("largest difference " << r.worst << ", largest alpha " << r.largest_alpha);
    CHECK(r.largest_alpha > 0.5);
    CHECK(r.worst <= kRayTolerance);
}

TEST_CASE(
    "cells where extinction vanishes add nothing, and a cell whose ends are clear but not its inside is integrated")
{
    // The integrator skips a cell whose corners' range has zero extinction throughout. Here extinction is zero except
    // on a narrow peak and a box with jumps, each narrower than one cell's range of the linear field (about 0.11):
    // cells whose range holds the peak or the box between clear ends must be integrated, all others are clear. The
    // tetrahedral reference on the same grid has no such shortcut.
    TransferFunction tf = ramp();
    tf.extinction = {{0.0, 0.0},  {0.61, 0.0}, {0.62, 3.0}, {0.63, 0.0}, {0.75, 0.0},
                     {0.75, 2.0}, {0.78, 2.0}, {0.78, 0.0}, {1.0, 0.0}};
    const LinearGridAgreement r = against_tetrahedra(tf);
    INFO("largest difference " << r.worst << ", largest alpha " << r.largest_alpha
                               << ", rays through the grid left clear " << r.clear_rays);
    CHECK(r.largest_alpha > 0.3);  // the peak and the box are in the picture
    CHECK(r.clear_rays > 0);       // and rays that cross only clear cells
    CHECK(r.worst <= kRayTolerance);
}

TEST_CASE("a trilinear field: the cubic along the ray integrates as quadrature of the definitions does")
{
    // One cell with random corner values: along a ray the scalar is a true cubic. The oracle evaluates the trilinear
    // interpolation itself at each point and integrates docs/spec.md §1's definitions in long double, sharing nothing
    // with the integrator but the transfer function: the ray is cut where the scalar crosses a breakpoint (found by
    // dense sampling and bisection), and on each smooth piece C = integral of c tau exp(-T) by composite 20-point
    // Gauss-Legendre, with T at each node by the same rule from the piece's start.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    double corner[8];
    for (double& c : corner) c = double(float(U(rng)));  // as the volume stores it
    const Volume v = grid({2, 2, 2}, {0.0, 0.0, 0.0}, {2.0, 1.5, 3.0}, [&](const glm::dvec3& p) {
        return corner[(p.x > 0 ? 1 : 0) + (p.y > 0 ? 2 : 0) + (p.z > 0 ? 4 : 0)];
    });
    const TransferFunction tf = ramp();
    const VolumeIntegrator vi(v, tf);
    using R = test::Real;
    const auto& gl20 = test::gauss_legendre20();
    auto rule = [&](const std::function<R(R)>& f, R lo, R hi, int parts) {
        R sum = 0;
        for (int p = 0; p < parts; ++p) {
            const R a = lo + (hi - lo) * p / parts, b = lo + (hi - lo) * (p + 1) / parts;
            for (const auto& nw : gl20) sum += nw[1] * (b - a) / 2 * f((a + b) / 2 + (b - a) / 2 * nw[0]);
        }
        return sum;
    };
    double worst = 0.0;
    for (int r = 0; r < 6; ++r) {
        // From one face of the cell to the opposite one.
        // z first: the statements fix the order of the draws, not the compiler.
        const double az = U(rng) * 3.0, ay = U(rng) * 1.5, ez = U(rng) * 3.0, ey = U(rng) * 1.5;
        const glm::dvec3 a(0.0, ay, az), e(2.0, ey, ez);
        const R len = R(glm::length(e - a));
        const glm::dvec3 dir = (e - a) / double(len);
        auto s_at = [&](R t) {
            const R f[3] = {(a.x + t * dir.x) / 2, (a.y + t * dir.y) / R(1.5), (a.z + t * dir.z) / 3};
            R s = 0;
            for (int c = 0; c < 8; ++c)
                s += corner[c] * ((c & 1) ? f[0] : 1 - f[0]) * ((c & 2) ? f[1] : 1 - f[1]) * ((c & 4) ? f[2] : 1 - f[2]);
            return s;
        };
        std::vector<R> cuts{0, len};
        const int n = 20000;
        for (double br : tf.breakpoints())
            for (int i = 0; i < n; ++i) {
                R lo = len * i / n, hi = len * (i + 1) / n;
                if ((s_at(lo) < br) == (s_at(hi) < br)) continue;
                const bool rising = s_at(hi) > s_at(lo);
                for (int it = 0; it < 80; ++it) ((s_at((lo + hi) / 2) < br) == rising ? lo : hi) = (lo + hi) / 2;
                cuts.push_back((lo + hi) / 2);
            }
        std::sort(cuts.begin(), cuts.end());
        auto tau = [&](R t) { return R(tf.tau_at(double(s_at(t)))); };
        R T0 = 0, C[3] = {0, 0, 0};
        for (std::size_t k = 1; k < cuts.size(); ++k) {
            const R p0 = cuts[k - 1], p1 = cuts[k];
            for (int ch = 0; ch < 3; ++ch)
                C[ch] += rule(
                    [&](R t) {
                        const R T = T0 + rule(tau, p0, t, 4);
                        return R(tf.color_at(double(s_at(t)))[ch]) * tau(t) * std::exp(-T);
                    },
                    p0, p1, 16);
            T0 += rule(tau, p0, p1, 16);
        }
        RayStats st;
        const glm::dvec4 got = vi.integrate(Ray{a - 5.0 * dir, dir}, st);
        const double want[4] = {double(C[0]), double(C[1]), double(C[2]), double(1 - std::exp(-T0))};
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::fabs(got[c] - want[c]));
    }
    INFO("largest difference " << worst);
    CHECK(worst <= kRayTolerance);
}

TEST_CASE("volume reference on degenerate rays and volumes: finite, and nothing where there is no interior")
{
    const auto field = [](const glm::dvec3& p) { return 0.5 + 0.1 * std::sin(p.x) * std::cos(p.y + p.z); };
    const Volume v = grid({5, 5, 5}, {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, field);
    const VolumeIntegrator vi(v, ramp());
    RayStats st;
    SECTION("a ray along a face of the box, along a grid plane, through grid vertices")
    {
        for (const Ray& ray : {Ray{{-1.0, 0.0, 2.0}, {1.0, 0.0, 0.0}}, Ray{{-1.0, 2.0, 2.0}, {1.0, 0.0, 0.0}},
                               Ray{{-1.0, -1.0, -1.0}, glm::normalize(glm::dvec3(1.0))},
                               Ray{{4.0, 4.0, -3.0}, {0.0, 0.0, 1.0}}}) {
            const glm::dvec4 c = vi.integrate(ray, st);
            INFO("ray from " << ray.origin.x << " " << ray.origin.y << " " << ray.origin.z);
            for (int k = 0; k < 4; ++k) CHECK(std::isfinite(c[k]));
            CHECK(c.a > 0.0);  // each of these runs inside the closed box for a positive length
        }
    }
    SECTION("a ray that only touches the box at an edge, and one that misses it")
    {
        // Through the edge x = 0, y = 4 at z = 2, outside the box before and after it.
        const glm::dvec4 edge = vi.integrate(Ray{{-1.0, 3.0, 2.0}, glm::normalize(glm::dvec3(1.0, 1.0, 0.0))}, st);
        const glm::dvec4 miss = vi.integrate(Ray{{-1.0, 6.0, 2.0}, {1.0, 0.0, 0.0}}, st);
        CHECK(edge.a <= 1e-12);  // a zero-length chord, up to the rounding of the slab test
        CHECK(miss.a == 0.0);
    }
    SECTION("a one-voxel-thick volume has no interior: transparent, not NaN")
    {
        const Volume flat = grid({4, 4, 1}, {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, field);
        const VolumeIntegrator fi(flat, ramp());
        const glm::dvec4 c = fi.integrate(Ray{{1.5, 1.5, -2.0}, {0.0, 0.0, 1.0}}, st);
        CHECK(c == glm::dvec4(0.0));
    }
}
