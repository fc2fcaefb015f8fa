// The bars for VICP against the reference, and the reference image of a mesh scene, shared by the VICP tests
// (tests/test_vicp.cpp, tests/test_vicp_published.cpp).
#pragma once

#include "mesh_scenes.h"
#include "reference/reference_renderer.h"

namespace uvr::test {

// With exact segments and a correct order, VICP computes the reference's integral per cell, up to float32 fragment
// values and compositing, the roundings HAVS's frames have too.
// (The cells' interior faces are where the rasterizer drew them, gpu/vicp/vicp_fragment.h "Snapping": that moves no
// boundary, and inside the mesh only splits a ray's path differently between its cells.)
// Sized as HAVS's bars are (tests/havs_convergence.h), from the largest figures of the tests that use them (test_vicp,
// test_vicp_published, run with both bars at 0): RMSE at most 1.2e-6, the bar 2.5 times that.
constexpr double kVicpConvergenceRmse = 3e-6;
// The largest error on any pixel: this catches a region lost or composited out of order, which costs far more than
// the roundings do (a segment lost to snapping costs 0.016 on a Blunt Fin pixel, a pair of cells composited out of
// order 0.1 and more), while the roundings of fragment values at a grazing angle reach 1.55e-4 on a torus silhouette
// pixel (test_vicp, the largest measured), the bar 2.6 times that.
constexpr double kVicpConvergenceMax = 4e-4;

inline Image mesh_reference(const Scene& s, const Camera& cam, int w, int h)
{
    const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats rs;
    return render_reference(ri, cam, w, h, rs);
}

}  // namespace uvr::test
