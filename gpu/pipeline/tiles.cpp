#include "gpu/pipeline/tiles.h"

#include <algorithm>
#include <cmath>

namespace uvr::gpu {

ScreenTiles::ScreenTiles(int width, int height)
    : width_(width),
      height_(height),
      tiles_x_((width + kTile - 1) / kTile),
      tiles_y_((height + kTile - 1) / kTile),
      bins_(std::size_t(tiles_x_) * std::size_t(tiles_y_))
{
}

ScreenTiles::Range ScreenTiles::range(const std::vector<WindowCoord>& win, const uint32_t* idx, int n) const
{
    float x0 = win[idx[0]].x, x1 = x0, y0 = win[idx[0]].y, y1 = y0;
    for (int j = 1; j < n; ++j) {
        x0 = std::min(x0, win[idx[j]].x);
        x1 = std::max(x1, win[idx[j]].x);
        y0 = std::min(y0, win[idx[j]].y);
        y1 = std::max(y1, win[idx[j]].y);
    }
    Range r;
    if (!(x1 >= 0.0f && y1 >= 0.0f && x0 <= float(width_) && y0 <= float(height_))) return r;
    r.x0 = std::clamp(int(std::floor(x0)) / kTile, 0, tiles_x_ - 1);
    r.x1 = std::clamp(int(std::floor(x1)) / kTile, 0, tiles_x_ - 1);
    r.y0 = std::clamp(int(std::floor(y0)) / kTile, 0, tiles_y_ - 1);
    r.y1 = std::clamp(int(std::floor(y1)) / kTile, 0, tiles_y_ - 1);
    return r;
}

void ScreenTiles::add(uint32_t item, const Range& r)
{
    for (int ty = r.y0; ty <= r.y1; ++ty)
        for (int tx = r.x0; tx <= r.x1; ++tx)
            bins_[std::size_t(ty) * std::size_t(tiles_x_) + std::size_t(tx)].push_back(item);
}

TileRect ScreenTiles::tile(std::size_t b) const
{
    const int tx = int(b % std::size_t(tiles_x_)), ty = int(b / std::size_t(tiles_x_));
    const int px0 = tx * kTile, py0 = ty * kTile;
    return {px0, std::min(width_, px0 + kTile) - 1, py0, std::min(height_, py0 + kTile) - 1};
}

}  // namespace uvr::gpu
