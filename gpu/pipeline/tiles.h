// Screen tiles for the emulated drivers (gpu/havs/havs.cpp, gpu/vicp/vicp.cpp): primitives are binned by the
// window-space bounding box of their points, in submission order, and the tiles are then processed in parallel, each
// applying its primitives in that order to its own pixels, exactly as a GPU orders the fragments of one pixel. So the
// result does not depend on the number of threads.
// Twins: none (emulation only; llvmpipe's own binning is docs/rasterizer.md, section 5).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/rasterize.h"

namespace uvr::gpu {

// A tile's pixels, inclusive, in GL rows (from the bottom).
struct TileRect {
    int px0 = 0, px1 = -1, py0 = 0, py1 = -1;
};

class ScreenTiles {
public:
    static constexpr int kTile = 64;  // pixels along a tile's side
    // Primitives whose tile ranges are computed at once while binning: their scratch (16 B each) stays at 4 MiB.
    static constexpr std::size_t kBinChunk = std::size_t(1) << 18;

    ScreenTiles(int width, int height);

    // The tiles the bounding box of win[idx[0]] .. win[idx[n - 1]] touches: columns x0..x1, rows y0..y1, inclusive
    // (none when the box lies off the framebuffer).
    struct Range {
        int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
        bool empty() const { return x1 < x0 || y1 < y0; }
        // The smallest range holding both (a primitive drawn as several pieces).
        Range hull(const Range& o) const
        {
            if (empty()) return o;
            if (o.empty()) return *this;
            return {std::min(x0, o.x0), std::max(x1, o.x1), std::min(y0, o.y0), std::max(y1, o.y1)};
        }
    };
    Range range(const std::vector<WindowCoord>& win, const uint32_t* idx, int n) const;

    // Bins primitives 0 .. count - 1 in drawing order: `range_of(i)` (a Range) is computed in parallel, a kBinChunk
    // of primitives at a time (on a large mesh most of the time goes to its scattered reads of window positions),
    // and the primitives are appended to their tiles in order on one thread, so every tile lists its primitives in
    // drawing order whatever the thread count.
    template <class RangeOf>
    void bin(std::size_t count, RangeOf&& range_of)
    {
        std::vector<Range> ranges(std::min(kBinChunk, count));
        for (std::size_t c0 = 0; c0 < count; c0 += kBinChunk) {
            const std::size_t n = std::min(kBinChunk, count - c0);
            tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { ranges[i] = range_of(c0 + i); });
            for (std::size_t i = 0; i < n; ++i) add(uint32_t(c0 + i), ranges[i]);
        }
    }

    // Runs `visit(tile, items)` on every tile, tiles in parallel, each on one thread with llvmpipe's rounding mode
    // (denormals flushed, gpu/pipeline/denormals.h); `items` are the tile's primitives in drawing order, so each
    // pixel sees its fragments in the order a GPU does.
    template <class Visit>
    void visit(Visit&& visit) const
    {
        tbb::parallel_for(std::size_t(0), bins_.size(), [&](std::size_t b) {
            const FlushDenormals llvmpipe_mxcsr;
            visit(tile(b), bins_[b]);
        });
    }

    std::size_t count() const { return bins_.size(); }

private:
    int width_, height_, tiles_x_, tiles_y_;
    std::vector<std::vector<uint32_t>> bins_;

    void add(uint32_t item, const Range& r);
    TileRect tile(std::size_t b) const;
};

// The covered spans of triangle `ts` in `tile`, row by row from the bottom: `span(py, first, last)` for the columns
// first..last of GL window row py (never empty).
template <class Span>
void for_each_span_in_tile(const TriangleSetup& ts, const TileRect& tile, Span&& span)
{
    const int ya = std::max(ts.y0, tile.py0), yb = std::min(ts.y1, tile.py1);
    for (int py = ya; py <= yb; ++py) {
        int first = 0, last = -1;
        row_span(ts, py, first, last);
        first = std::max(first, tile.px0);
        last = std::min(last, tile.px1);
        if (first <= last) span(py, first, last);
    }
}

// The fragments of triangle `ts` that lie in `tile`, row by row from the bottom and left to right in each row (the
// rasterizer's coverage, rasterize.h): `fragment(px, py)` in GL window pixels.
template <class Fragment>
void for_each_fragment_in_tile(const TriangleSetup& ts, const TileRect& tile, Fragment&& fragment)
{
    for_each_span_in_tile(ts, tile, [&](int py, int first, int last) {
        for (int px = first; px <= last; ++px) fragment(px, py);
    });
}

}  // namespace uvr::gpu
