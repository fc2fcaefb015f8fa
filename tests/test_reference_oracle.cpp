// The ground truth on real data against a fully independent computation: each sampled ray is clipped against every
// tetrahedron by brute force in long double (no Embree, no walk, no adjacency), and the segments found are integrated
// by the quadrature oracle.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "quadrature_oracle.h"
#include "reference/dataset.h"
#include "reference/ray_integrator.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::Real;

namespace {

// Each segment's oracle agrees with the closed form to ~1e-14 (test_segment_integral); the brute-force clipping and
// the walk compute a ray's segment ends from the same planes with different rounding (~1e-15 relative). Over a ray of
// a few hundred segments both stay below 1e-12; 1e-9 keeps three orders of magnitude of margin and still catches a
// single skipped or doubled thin tetrahedron (its contribution at this transfer function is above 1e-7).
constexpr double kRayOracleTolerance = 1e-9;

struct Interval {
    Real t0, t1;
    uint32_t tet;
};

// [t0, t1] where the ray is inside tetrahedron `t` (empty when t1 <= t0).
Interval clip(const TetMesh& m, uint32_t t, const Ray& r)
{
    const Tet& T = m.tets[t];
    Real t0 = 0, t1 = INFINITY;
    for (int i = 0; i < 4; ++i) {
        const auto f = tet_face(T, i);
        const glm::dvec3 a = m.points[f[0]], b = m.points[f[1]], c = m.points[f[2]];
        const Real ux = Real(b.x) - a.x, uy = Real(b.y) - a.y, uz = Real(b.z) - a.z;
        const Real vx = Real(c.x) - a.x, vy = Real(c.y) - a.y, vz = Real(c.z) - a.z;
        const Real nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;  // outward
        const Real dn = nx * r.dir.x + ny * r.dir.y + nz * r.dir.z;
        const Real num = nx * (Real(a.x) - r.origin.x) + ny * (Real(a.y) - r.origin.y) + nz * (Real(a.z) - r.origin.z);
        if (dn == 0) {
            if (num < 0) return {0, 0, t};  // parallel and outside
            continue;
        }
        const Real th = num / dn;
        if (dn > 0)
            t1 = std::min(t1, th);
        else
            t0 = std::max(t0, th);
    }
    return {t0, t1, t};
}

Real scalar_at(const TetMesh& m, const std::vector<double>& v, uint32_t t, const Ray& r, Real tt)
{
    // Barycentric coordinates of the point in the tetrahedron, in long double.
    const Tet& T = m.tets[t];
    Real p[3] = {r.origin.x + tt * r.dir.x, r.origin.y + tt * r.dir.y, r.origin.z + tt * r.dir.z};
    Real e[3][3], d[3];
    for (int k = 0; k < 3; ++k) {
        for (int a = 0; a < 3; ++a) e[k][a] = Real(m.points[T[k + 1]][a]) - m.points[T[0]][a];
        d[k] = p[k] - m.points[T[0]][k];
    }
    // Solve e^T w = d by Cramer's rule.
    auto det3 = [](Real a[3][3]) {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    Real M[3][3];
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) M[row][col] = e[col][row];
    const Real D = det3(M);
    Real s = v[T[0]];
    for (int k = 0; k < 3; ++k) {
        Real Mk[3][3];
        for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 3; ++col) Mk[row][col] = col == k ? d[row] : M[row][col];
        s += det3(Mk) / D * (Real(v[T[k + 1]]) - v[T[0]]);
    }
    return s;
}

}  // namespace

TEST_CASE("the reference agrees with brute-force clipping and the quadrature oracle on Blunt Fin")
{
    LoadOptions o;
    o.q_file = uvr::test::data_path("vtk-data/bluntfinq.bin");
    const TetMesh mesh = *load_dataset(uvr::test::data_path("vtk-data/bluntfinxyz.bin"), o).mesh;
    const MeshTopology topo = build_topology(mesh);
    const Bounds b = mesh_bounds(mesh);
    const TransferFunction tf = default_transfer_function(field_range(mesh.fields[0]), glm::length(b.extent()));
    const RayIntegrator ri(mesh, topo, 0, tf);
    const SegmentIntegrator seg(tf);
    const int W = 512, H = 512;
    for (const double az : {0.0, 70.0}) {
        const Camera cam = default_camera(b, 1.0, az, 25.0);
        int hit_pixels = 0;
        for (int j = 40; j < H; j += 41)
            for (int i = 17; i < W; i += 37) {
                const Ray r = camera_ray(cam, W, H, i, j);
                std::vector<Interval> iv;
                for (uint32_t t = 0; t < mesh.tets.size(); ++t) {
                    if (is_degenerate(mesh, mesh.tets[t])) continue;
                    const Interval c = clip(mesh, t, r);
                    if (c.t1 > c.t0) iv.push_back(c);
                }
                std::sort(iv.begin(), iv.end(), [](const Interval& x, const Interval& y) { return x.t0 < y.t0; });
                glm::dvec4 expected(0.0);
                for (const Interval& x : iv) {
                    const double sf = double(scalar_at(mesh, mesh.fields[0].values, x.tet, r, x.t0));
                    const double sb = double(scalar_at(mesh, mesh.fields[0].values, x.tet, r, x.t1));
                    expected = composite_over(expected, uvr::test::oracle_segment(tf, sf, sb, double(x.t1 - x.t0)));
                }
                RayStats st;
                const glm::dvec4 got = ri.integrate(r, st);
                hit_pixels += iv.empty() ? 0 : 1;
                INFO("view " << az << ", pixel " << i << ", " << j << ": " << iv.size() << " segments, walk took "
                             << st.segments);
                CHECK(st.failures == 0);
                for (int k = 0; k < 4; ++k) CHECK(std::fabs(got[k] - expected[k]) <= kRayOracleTolerance);
            }
        INFO("pixels whose ray crosses the mesh: " << hit_pixels);
        CHECK(hit_pixels >= 30);  // the sample really crosses the mesh (Blunt Fin fills a third of the frame)
    }
}
