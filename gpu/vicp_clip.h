// VICP's use of the clip stage (gpu/clip.h): the cells a view cuts (a camera inside the mesh or on its boundary, a
// view closer than the mesh's size) drawn so that the GPU clips nothing, as HAVS's faces are (havs_setup.cpp).
//
// ProjectTet draws a whole cell as its four faces, 12 vertices (shaders/vicp.vert), and the rasterizer culls the faces
// seen from inside the cell, so each pixel the cell covers gets one fragment. A cell with a point outside one of the
// clip stage's planes cannot be drawn so: a point behind the eye has no window position, and the draw module would
// clip the faces its own way (docs/rasterizer.md "Not emulated" 1). Such a cell is drawn as the front faces of the
// cell clipped to the view instead:
//   - each of its four faces clipped by clip_polygon (orientation kept) and drawn as a fan, the rasterizer again
//     culling those seen from inside;
//   - when the near plane cuts it, its near-plane section (near_section, clipped to the sides), turned to face the
//     eye: it is the face of the clipped cell nearest the eye.
// These tile the clipped cell's projection as the four faces tile a whole cell's. The fragment program is unchanged:
// it intersects the pixel's ray with the cell from the cell's constants whatever was rasterized, from max(0, entry)
// on, so the cell around the eye gives its segment from the eye on. A cell wholly outside one plane is not drawn.
//
// Clipping runs on the points where snapping put them (vicp_fragment.h "Snapping"; a point the GPU's frustum test
// would clip is not drawn and keeps its own position), relative to the eye in double: a crossing then lies on the
// edge of the cell the fragment program intersects, and its rounding to window coordinates is the only difference
// between the rasterized edge and the cell's (at most 1/512 pixel, at the image's border or on the near plane).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "gpu/clip.h"
#include "gpu/rasterize.h"

namespace uvr::gpu {

// The cut cell at stream slot `slot` is drawn as the fan triangles [first, first + count) of the frame.
struct VicpCut {
    uint32_t slot = 0, first = 0, count = 0;
};

// The clip stage's view of one frame: its planes, and per mesh point where clipping takes it from (relative to the
// eye) and the planes it lies outside of (outcode).
class VicpClipper {
public:
    VicpClipper(const ViewSetup& view, int width, int height, const std::vector<glm::dvec3>& moved,
                const std::vector<uint8_t>& codes)
        : view_(view), planes_(inner_clip_planes(width, height)), moved_(moved), codes_(codes)
    {
    }

    const ViewSetup& view() const { return view_; }
    const ClipPlanes& planes() const { return planes_; }
    unsigned code(uint32_t point) const { return codes_[point]; }
    // Mesh point `point` as a polygon's vertex (id = point).
    ClipVertex vertex(uint32_t point) const;
    // The triangle of mesh points v[0..2] clipped to the view (gpu/clip.h clip_polygon), in the same orientation.
    void clip_triangle(const uint32_t v[3], std::vector<ClipVertex>& poly, std::vector<ClipVertex>& scratch) const;
    // The near plane's section of the tetrahedron of mesh points v[0..3], clipped to the sides and ordered
    // counter-clockwise as the eye sees it (front-facing); empty when the near plane does not cut it.
    void near_face(const uint32_t v[4], std::vector<ClipVertex>& poly, std::vector<ClipVertex>& scratch) const;

private:
    const ViewSetup& view_;
    ClipPlanes planes_;
    const std::vector<glm::dvec3>& moved_;
    const std::vector<uint8_t>& codes_;
};

// The window coordinates the vertex stage gives a vertex of the frame's vertex buffer (float, relative to the eye).
WindowCoord frame_window_coord(const ViewSetup& view, const Framebuffer& fbuf, const glm::vec3& p);

}  // namespace uvr::gpu
