// VICP's use of the clip stage (gpu/pipeline/clip.h): the cells a view cuts (a camera inside the mesh or on its
// boundary, a view closer than the mesh's size) drawn so that the GPU clips nothing, as HAVS's faces are
// (gpu/havs/havs_setup.cpp). Input: the frame's ViewSetup and, per mesh point, its snapped position relative to the
// eye and its outcode. Output: a cut cell's four faces clipped to the view (clip_triangle) and its near-plane section
// turned to face the eye (near_face), polygons the CPU stage draws as fans.
// Twins: none (CPU stage); the fans are drawn by shaders/vicp.vert (the vertices from vicp_whole_vertices on).
// Derivation: docs/vicp.md, "The cells a view cuts".
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "gpu/pipeline/clip.h"
#include "gpu/pipeline/rasterize.h"

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
    // The triangle of mesh points v[0..2] clipped to the view (gpu/pipeline/clip.h clip_polygon), in the same orientation.
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
