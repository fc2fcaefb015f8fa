#include "reference/reference_renderer.h"

#include <atomic>
#include <chrono>
#include <mutex>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

namespace uvr {

namespace {

// One ray per pixel through `integrator` (RayIntegrator or VolumeIntegrator: integrate(Ray, RayStats&)).
template <class Integrator>
Image render_rays(const Integrator& integrator, const Camera& camera, int width, int height, ReferenceStats& stats,
                  const std::function<void(double)>& progress)
{
    const auto t0 = std::chrono::steady_clock::now();
    Image img(width, height);
    std::atomic<uint64_t> segments{0}, entries{0}, failures{0}, done{0};
    std::mutex progress_mutex;
    const CameraRays rays(camera, width, height);
    // 16x16 tiles keep neighbouring rays (which walk the same cells) on one thread.
    tbb::parallel_for(tbb::blocked_range2d<int>(0, height, 16, 0, width, 16), [&](const tbb::blocked_range2d<int>& r) {
        RayStats rs;
        for (int j = r.rows().begin(); j < r.rows().end(); ++j)
            for (int i = r.cols().begin(); i < r.cols().end(); ++i) {
                const glm::dvec4 c = integrator.integrate(rays(i, j), rs);
                float* px = img.pixel(i, j);
                for (int k = 0; k < 4; ++k) px[k] = float(c[k]);
            }
        segments += rs.segments;
        entries += rs.entries;
        failures += rs.failures;
        const uint64_t n = done += uint64_t(r.rows().size()) * uint64_t(r.cols().size());
        if (progress) {
            std::lock_guard<std::mutex> lock(progress_mutex);
            progress(double(n) / (double(width) * double(height)));
        }
    });
    finish_reference_stats(stats, width, height, RayStats{segments, entries, failures}, t0);
    return img;
}

}  // namespace

void finish_reference_stats(ReferenceStats& stats, int width, int height, const RayStats& rays,
                            std::chrono::steady_clock::time_point t0)
{
    stats.rays = uint64_t(width) * uint64_t(height);
    stats.segments = rays.segments;
    stats.entries = rays.entries;
    stats.failures = rays.failures;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Image render_reference(const RayIntegrator& integrator, const Camera& camera, int width, int height,
                       ReferenceStats& stats, const std::function<void(double)>& progress)
{
    return render_rays(integrator, camera, width, height, stats, progress);
}

Image render_reference(const VolumeIntegrator& integrator, const Camera& camera, int width, int height,
                       ReferenceStats& stats, const std::function<void(double)>& progress)
{
    return render_rays(integrator, camera, width, height, stats, progress);
}

}  // namespace uvr
