// Ray fragments: the runs of pixels' rays through one part of a mesh, and their compositing into an image. A part
// traced on its own gives each ray's runs through its cells; the parts' runs of one ray are disjoint intervals, so
// compositing all of them front to back gives the whole mesh's reference up to the order of the additions
// (docs/distributed.md).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "reference/camera.h"
#include "reference/image.h"
#include "reference/ray_integrator.h"
#include "reference/reference_renderer.h"

namespace uvr {

struct Fragment {
    uint32_t pixel = 0;  // y * width + x
    RayRun run;
};

// Every pixel's ray through `integrator`'s mesh, one fragment per run that has any colour or opacity (a run of
// nothing changes no pixel and is left out), sorted by pixel and distance. stats as render_reference's.
std::vector<Fragment> trace_fragments(const RayIntegrator& integrator, const Camera& camera, int width, int height,
                                      ReferenceStats& stats);

// Sorts `fragments` by pixel, then by distance along the ray (t_in, then t_out, then colour: a total order, so the
// result does not depend on the order they came in), and composites each pixel's front to back in double, rounded to
// float once. Pixels first_pixel .. first_pixel + image size - 1 of the frame land in `image` (a band of rows).
void composite_fragments(std::vector<Fragment>& fragments, Image& image, uint64_t first_pixel = 0);

// The order composite_fragments sorts by.
bool fragment_before(const Fragment& a, const Fragment& b);

}  // namespace uvr
