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

    // Appends `item` to every tile that the bounding box of win[idx[0]] .. win[idx[n - 1]] touches (none when the box
    // lies off the framebuffer).
    void add(uint32_t item, const std::vector<WindowCoord>& win, const uint32_t* idx, int n);

    std::size_t count() const { return bins_.size(); }
    const std::vector<uint32_t>& items(std::size_t b) const { return bins_[b]; }
    // Tile b's pixels, inclusive.
    void pixels(std::size_t b, int& px0, int& px1, int& py0, int& py1) const;

private:
    int width_, height_, tiles_x_, tiles_y_;
    std::vector<std::vector<uint32_t>> bins_;
};

}  // namespace uvr::gpu
