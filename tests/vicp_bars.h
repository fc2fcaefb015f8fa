// Issue 6's bars for VICP against the reference, and the reference image of a mesh scene, shared by the VICP tests
// (tests/test_vicp.cpp, tests/test_vicp_seed.cpp).
#pragma once

#include "mesh_scenes.h"
#include "reference/reference_renderer.h"

namespace uvr::test {

// With exact segments and a correct order, VICP computes the reference's integral per cell, up to float32 fragment
// values and compositing; the largest error is issue 4's bar for HAVS, whose errors come from the same roundings.
// (The cells' interior faces are where the rasterizer drew them, gpu/vicp/vicp_fragment.h "Snapping": that moves no
// boundary, and inside the mesh only splits a ray's path differently between its cells.)
constexpr double kVicpConvergenceRmse = 1e-5;
// The largest error on any pixel: this catches a region lost or composited out of order, which costs far more than
// the roundings do (a segment lost to snapping cost 0.016 on a Blunt Fin pixel before the fix of vicp_fragment.h, a
// pair of cells composited out of order 0.1 and more), while the roundings of fragment values at a grazing angle
// reach 1.5e-4 on a torus silhouette pixel (measured; HAVS's 1e-4 bar is for its own fragment values).
constexpr double kVicpConvergenceMax = 1e-3;

inline Image mesh_reference(const Scene& s, const Camera& cam, int w, int h)
{
    const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats rs;
    return render_reference(ri, cam, w, h, rs);
}

}  // namespace uvr::test
