// Screen tiles for the emulated drivers (havs.cpp, vicp.cpp): primitives are binned by the window-space bounding box
// of their points, in submission order, and the tiles are then processed in parallel, each applying its primitives in
// that order to its own pixels, exactly as a GPU orders the fragments of one pixel. So the result does not depend on
// the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/rasterize.h"

namespace uvr::gpu {

class ScreenTiles {
public:
    static constexpr int kTile = 64;  // pixels along a tile's side

    ScreenTiles(int width, int height);

    // The tiles the bounding box of win[idx[0]] .. win[idx[n - 1]] touches: columns x0..x1, rows y0..y1, inclusive
    // (none when the box lies off the framebuffer). Reads only: drivers compute many in parallel and add them in
    // submission order.
    struct Range {
        int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
    };
    Range range(const std::vector<WindowCoord>& win, const uint32_t* idx, int n) const;
    // Appends `item` to every tile of `r`.
    void add(uint32_t item, const Range& r);
    // Both: appends `item` to every tile the bounding box touches.
    void add(uint32_t item, const std::vector<WindowCoord>& win, const uint32_t* idx, int n)
    {
        add(item, range(win, idx, n));
    }

    std::size_t count() const { return bins_.size(); }
    const std::vector<uint32_t>& items(std::size_t b) const { return bins_[b]; }
    // Tile b's pixels, inclusive.
    void pixels(std::size_t b, int& px0, int& px1, int& py0, int& py1) const;

private:
    int width_, height_, tiles_x_, tiles_y_;
    std::vector<std::vector<uint32_t>> bins_;
};

}  // namespace uvr::gpu
