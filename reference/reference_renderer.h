// Rendering a whole image with the ground truth: one ray per pixel (docs/spec.md §2), tiles in parallel.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "reference/camera.h"
#include "reference/image.h"
#include "reference/ray_integrator.h"
#include "reference/volume_integrator.h"

namespace uvr {

struct ReferenceStats {
    uint64_t rays = 0;
    uint64_t segments = 0;
    uint64_t entries = 0;
    uint64_t failures = 0;  // rays abandoned by the walk's guards: must be 0
    double seconds = 0.0;
};

// `stats` of width x height rays that did `rays` together, started at t0 (what every image of rays reports).
void finish_reference_stats(ReferenceStats& stats, int width, int height, const RayStats& rays,
                            std::chrono::steady_clock::time_point t0);

// Every pixel is computed independently in double and rounded to float once, so the image does not depend on the
// number of threads. `progress` (may be empty) is called with the fraction done, from one thread at a time.
Image render_reference(const RayIntegrator& integrator, const Camera& camera, int width, int height,
                       ReferenceStats& stats, const std::function<void(double)>& progress = {});
// The same for a regular grid (stats.failures stays 0: the grid walk has no guard to trip).
Image render_reference(const VolumeIntegrator& integrator, const Camera& camera, int width, int height,
                       ReferenceStats& stats, const std::function<void(double)>& progress = {});

}  // namespace uvr
