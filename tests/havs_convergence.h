// The convergence bar, shared by the HAVS tests that compare a frame with the reference: exact segments, exact
// gaps, no early termination and k at least the largest fragment count make HAVS compute the reference's integral,
// up to float32 fragment values and compositing.
#pragma once

#include "gpu/havs/havs.h"
#include "gpu/vicp/vicp.h"
#include "mesh_scenes.h"
#include "image_errors.h"
#include "reference/reference_renderer.h"

namespace uvr::test {

// What stays is float32 fragment values and compositing. Each bar is sized from the largest figure the tests that
// use it measure (test_havs, test_havs_clip, test_havs_flush, test_sliver: run with both bars at 0, every check
// prints its figure), with room for another CPU's roundings: RMSE at most 7.8e-7 (test_havs_clip, a view that cuts
// the mesh), the bar 2.6 times that; the largest error at most 6.7e-5 (test_havs, the Oxygen Post), the bar 1.5
// times that.
constexpr double kConvergenceRmse = 2e-6;
constexpr double kConvergenceMax = 1e-4;

// The k of the convergence tests: more than any test scene puts on one pixel (each test requires it), so the
// k-buffer never overflows and no ordering error remains.
constexpr int kConvergenceK = 255;

inline gpu::HavsOptions exact_havs_options(int k)
{
    gpu::HavsOptions o;
    o.k = k;
    o.segment = gpu::SegmentMode::exact;
    o.threshold = 1.0f;
    return o;
}

// Every switch exact (docs/spec.md §7): HAVS with every fragment held, ties by facing, exact gaps, coverage,
// interpolation and segments, no termination; VICP with exact coverage, interpolation and segments, no termination.
inline gpu::HavsOptions havs_every_switch_exact()
{
    gpu::HavsOptions o = exact_havs_options(gpu::kEveryFragment);
    o.ties = gpu::TieOrder::facing;
    o.coverage = gpu::Coverage::exact;
    o.interpolation = gpu::InterpolationMode::exact;
    o.gaps = gpu::GapMode::exact;
    return o;
}
inline gpu::VicpOptions vicp_every_switch_exact()
{
    gpu::VicpOptions o;
    o.segment = gpu::SegmentMode::exact;
    o.coverage = gpu::Coverage::exact;
    o.interpolation = gpu::InterpolationMode::exact;
    o.threshold = 1.0f;
    return o;
}

// HAVS's frame (by default exact segments and k = kConvergenceK, the paper's interpolation and coverage), and the
// reference's.
struct HavsAndReference {
    gpu::HavsFrame havs;
    Image reference;
    ImageErrors errors;
};

inline HavsAndReference havs_and_reference(const Scene& s, const Camera& cam, int width, int height,
                                           const gpu::HavsOptions& options = exact_havs_options(kConvergenceK))
{
    HavsAndReference r;
    const gpu::HavsRenderer havs(s.mesh, s.topo, s.field, s.tf, options);
    r.havs = havs.render(cam, width, height);
    const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats rs;
    r.reference = render_reference(ri, cam, width, height, rs);
    r.errors = image_errors(r.havs.image, r.reference, kConvergenceMax);
    return r;
}

}  // namespace uvr::test
