#include "reference/fragments.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "reference/segment_integral.h"

namespace uvr {

std::vector<Fragment> trace_fragments(const RayIntegrator& integrator, const Camera& camera, int width, int height,
                                      ReferenceStats& stats)
{
    const auto t0 = std::chrono::steady_clock::now();
    // 16x16 tiles, as render_reference: neighbouring rays walk the same cells. Each tile keeps its own fragments.
    // Only the pixels whose rays can meet the part's bounds are traced: the others have no runs.
    const PixelRect rect = pixels_covering(camera, width, height, integrator.bounds());
    constexpr int kTile = 16;
    const int tiles_x = (rect.x1 - rect.x0 + kTile - 1) / kTile, tiles_y = (rect.y1 - rect.y0 + kTile - 1) / kTile;
    std::vector<std::vector<Fragment>> per_tile(std::size_t(tiles_x) * std::size_t(tiles_y));
    std::atomic<uint64_t> segments{0}, entries{0}, failures{0};
    const CameraRays rays(camera, width, height);
    tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1), [&](const tbb::blocked_range2d<int>& r) {
        RayStats rs;
        std::vector<RayRun> runs;
        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
            for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
                std::vector<Fragment>& out = per_tile[std::size_t(ty) * std::size_t(tiles_x) + std::size_t(tx)];
                for (int j = rect.y0 + ty * kTile; j < std::min(rect.y1, rect.y0 + (ty + 1) * kTile); ++j)
                    for (int i = rect.x0 + tx * kTile; i < std::min(rect.x1, rect.x0 + (tx + 1) * kTile); ++i) {
                        runs.clear();
                        integrator.runs(rays(i, j), rs, runs);
                        const uint32_t pixel = uint32_t(j) * uint32_t(width) + uint32_t(i);
                        for (const RayRun& run : runs)
                            if (run.rgba != glm::dvec4(0.0)) out.push_back({pixel, run});
                    }
            }
        segments += rs.segments;
        entries += rs.entries;
        failures += rs.failures;
    });
    std::size_t total = 0;
    for (const auto& t : per_tile) total += t.size();
    std::vector<Fragment> fragments;
    fragments.reserve(total);
    for (auto& t : per_tile) fragments.insert(fragments.end(), t.begin(), t.end());
    tbb::parallel_sort(fragments.begin(), fragments.end(), fragment_before);
    finish_reference_stats(stats, width, height, RayStats{segments, entries, failures}, t0);
    return fragments;
}

bool fragment_before(const Fragment& a, const Fragment& b)
{
    if (a.pixel != b.pixel) return a.pixel < b.pixel;
    if (a.run.t_in != b.run.t_in) return a.run.t_in < b.run.t_in;
    if (a.run.t_out != b.run.t_out) return a.run.t_out < b.run.t_out;
    for (int c = 0; c < 4; ++c)
        if (a.run.rgba[c] != b.run.rgba[c]) return a.run.rgba[c] < b.run.rgba[c];
    return false;
}

void composite_fragments(std::vector<Fragment>& fragments, Image& image, uint64_t first_pixel)
{
    tbb::parallel_sort(fragments.begin(), fragments.end(), fragment_before);
    const uint64_t pixels = uint64_t(image.width) * uint64_t(image.height);
    std::size_t f = 0;
    while (f < fragments.size()) {
        const uint32_t pixel = fragments[f].pixel;
        glm::dvec4 acc(0.0);
        for (; f < fragments.size() && fragments[f].pixel == pixel; ++f)
            acc = composite_over(acc, fragments[f].run.rgba);
        const uint64_t local = uint64_t(pixel) - first_pixel;
        if (pixel < first_pixel || local >= pixels)
            throw std::logic_error("composite_fragments: a fragment of pixel " + std::to_string(pixel) +
                                   " outside the band of " + std::to_string(pixels) + " pixels from " +
                                   std::to_string(first_pixel));
        for (int c = 0; c < 4; ++c) image.rgba[local * 4 + std::size_t(c)] = float(acc[c]);
    }
}

}  // namespace uvr
