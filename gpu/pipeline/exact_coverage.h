// --coverage exact (docs/spec.md §7), the emulation's stand-in for the rasterizer's coverage: a pixel is covered by a
// triangle when the ray through its centre crosses it, tested in double on the triangle's window coordinates without
// snapping. A pixel centre on an edge or a vertex goes to exactly one of the triangles that share it (a fill rule on
// edge functions computed the same way from either side), so a ray crosses a sheet of faces once, as the reference's
// walk does. Input: the window coordinates in double and the frame-vertex ids of a triangle; output: its covered
// pixels. Twins: none (the GPU snaps; this is the variant that removes snapping). Docs: docs/rasterizer.md, "Exact
// coverage".
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/vec2.hpp>

#include "gpu/pipeline/rasterize.h"
#include "gpu/pipeline/tiles.h"
#include "reference/choice.h"

namespace uvr::gpu {

enum class Coverage { gpu, exact };
inline constexpr Choices<Coverage, 2> kCoverages{
    {{Coverage::gpu, "gpu", "the rasterizer's snapped coverage"},
     {Coverage::exact, "exact", "the ray through the pixel centre crosses the primitive, in double; emulation only"}}};

struct ExactTriangle {
    glm::dvec2 p[3];       // counter-clockwise in window coordinates (y up)
    uint32_t id[3] = {0, 0, 0};
    Facing facing = Facing::none;  // of the triangle as given (before the reordering); none: zero area
    double x0 = 0, x1 = -1, y0 = 0, y1 = -1;  // bounding box
    bool empty() const { return facing == Facing::none; }
};

// The triangle with window coordinates p[i] (double) of frame vertices id[i]. Facing as GL's default: front when
// counter-clockwise in window coordinates.
ExactTriangle exact_triangle(const glm::dvec2 p[3], const uint32_t id[3]);

// Whether the ray through pixel (px, py)'s centre crosses the triangle.
bool exact_covers(const ExactTriangle& t, int px, int py);

// The covered pixels of `t` in `tile`, row by row from the bottom, left to right: fragment(px, py).
template <class Fragment>
void for_each_exact_fragment_in_tile(const ExactTriangle& t, const TileRect& tile, Fragment&& fragment)
{
    if (t.empty()) return;
    // Pixel centres px + 0.5 within the box: px from ceil(x0 - 0.5) to floor(x1 - 0.5).
    const int ya = std::max(tile.py0, int(std::ceil(t.y0 - 0.5))), yb = std::min(tile.py1, int(std::floor(t.y1 - 0.5)));
    const int xa = std::max(tile.px0, int(std::ceil(t.x0 - 0.5))), xb = std::min(tile.px1, int(std::floor(t.x1 - 0.5)));
    for (int py = ya; py <= yb; ++py)
        for (int px = xa; px <= xb; ++px)
            if (exact_covers(t, px, py)) fragment(px, py);
}

}  // namespace uvr::gpu
