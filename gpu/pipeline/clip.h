// The clip stage: what llvmpipe's draw module does to a triangle that leaves the view frustum (draw_pipe_clip.c),
// done instead on the CPU, in double, before the draw, so that the GPU never clips anything and the emulation and the
// GL backend rasterize the same triangles. Input: polygons of ClipVertex (positions relative to the eye, clip
// coordinates in double, scalars). Output: the polygons clipped against planes a little inside the GPU's frustum
// (ClipPlanes), near-plane sections of cells, and the frame's vertex buffer extended (ClipVertexBuffer).
// Twins: none (CPU stage; it replaces the draw module's clipping). Used by gpu/havs/havs_setup.cpp and
// gpu/vicp/vicp_clip.h.
// Derivation (the margins, watertight crossings): docs/rasterizer.md, "The clip stage's planes and crossings".
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/pipeline/view_setup.h"
#include "gpu/pipeline/rasterize.h"

namespace uvr::gpu {

// How far inside the viewport's sides the CPU clips, in pixels: below the half pixel between the viewport's edge and
// the nearest pixel centre, above the vertex stage's float rounding (see above).
inline constexpr double kClipMarginPixels = 0.25;
// How far inside the near plane the CPU clips: kNearMargin in normalized depth (view_setup.h).

enum ClipPlane : int { kClipNear = 0, kClipLeft, kClipRight, kClipBottom, kClipTop, kClipPlaneCount };

// The planes of the CPU's clipping: x >= -ax w, x <= ax w, y likewise with ay, z >= -az w. The far plane is never
// crossed (view_setup puts it behind the mesh's bounds).
struct ClipPlanes {
    double ax = 1.0, ay = 1.0, az = 1.0;
};
ClipPlanes inner_clip_planes(int width, int height);

// A vertex of a polygon being clipped: its position relative to the view's origin (the eye), its clip coordinates
// (mvp_d * p, in double) and its normalized scalar.
struct ClipVertex {
    glm::dvec3 p{0.0};
    glm::dvec4 c{0.0};
    double s = 0.0;
    uint32_t id = kNewVertex;  // the caller's index of the vertex, kept through clipping; kNewVertex for a crossing
    static constexpr uint32_t kNewVertex = 0xFFFFFFFFu;
};
ClipVertex clip_vertex(const ViewSetup& vs, const glm::dvec3& p, double s);

// The signed distance-like value of clip coordinates c to `plane` (>= 0: on the kept side).
double plane_value(const ClipPlanes& planes, int plane, const glm::dvec4& c);
// One bit per plane that c lies outside of (bit `plane` for plane_value < 0); 0 inside all.
unsigned outcode(const ClipPlanes& planes, const glm::dvec4& c);

// Where edge ab crosses `plane` (a and b on opposite sides of it): position and scalar interpolated in double from the
// lexicographically smaller end, so the result does not depend on which end is a; an end that lies on the plane is
// returned as it is.
ClipVertex crossing(const ViewSetup& vs, const ClipPlanes& planes, int plane, const ClipVertex& a, const ClipVertex& b);

// Clips the convex polygon `poly` (in order) against the planes from `first` on, near first (Sutherland–Hodgman,
// keeping plane_value >= 0); `poly` becomes the clipped polygon, in the same orientation, or empty when nothing is
// left. A near-plane section starts at kClipLeft: its vertices lie on the near plane, to the rounding.
void clip_polygon(const ViewSetup& vs, const ClipPlanes& planes, std::vector<ClipVertex>& poly,
                  std::vector<ClipVertex>& scratch, int first = kClipNear);

// Whether the draw module would clip a vertex of these float clip coordinates (x, y or z outside [-w, w]).
bool outside_gpu_frustum(const std::array<float, 4>& clip);

// The polygon where the near plane cuts the tetrahedron with vertices v[0..3]: empty unless some vertex lies strictly
// in front of the plane (plane_value < 0) and some not; otherwise 3 or 4 vertices, made by crossing() on the cut
// edges, in cyclic order. Adjacent tetrahedra make the same vertices on the edges they share.
void near_section(const ViewSetup& vs, const ClipPlanes& planes, const ClipVertex v[4], std::vector<ClipVertex>& poly);

// The frame's vertex buffer as the clip stage extends it (HAVS and VICP alike): the mesh's points, then the vertices
// clipping makes, each with its float position relative to the eye and its window coordinates, and whether the GPU's
// frustum test would clip it (the renderers count such triangles as gpu_clipped: 0 unless the margins above fail).
class ClipVertexBuffer {
public:
    // points_f and win hold the mesh's points (the vertex stage's output); points_outside says, per mesh point, whether
    // the GPU's frustum test would clip it.
    ClipVertexBuffer(const ViewSetup& view, int width, int height, std::vector<glm::vec3>& points_f,
                     std::vector<WindowCoord>& win, const std::vector<uint8_t>& points_outside)
        : view_(view), fbuf_{width, height, RenderTarget::fbo}, points_f_(points_f), win_(win),
          points_(uint32_t(points_outside.size())), points_outside_(points_outside)
    {
    }

    // The frame vertices of the polygon's vertices, in order, into `ids`: a mesh point keeps its index, a crossing is
    // appended, and on_new(vertex) is called for it (for a renderer's own per-vertex data).
    template <class OnNew>
    void add(const std::vector<ClipVertex>& poly, std::vector<uint32_t>& ids, OnNew&& on_new)
    {
        ids.clear();
        for (const ClipVertex& v : poly) {
            if (v.id != ClipVertex::kNewVertex) {
                ids.push_back(v.id);
                continue;
            }
            ids.push_back(append(v));
            on_new(v);
        }
    }

    // Whether the GPU's frustum test would clip a vertex of triangle v.
    bool gpu_clips(uint32_t v0, uint32_t v1, uint32_t v2) const { return outside(v0) || outside(v1) || outside(v2); }

private:
    uint32_t append(const ClipVertex& v);
    bool outside(uint32_t v) const { return v < points_ ? points_outside_[v] != 0 : new_outside_[v - points_] != 0; }

    const ViewSetup& view_;
    Framebuffer fbuf_;
    std::vector<glm::vec3>& points_f_;
    std::vector<WindowCoord>& win_;
    uint32_t points_;
    const std::vector<uint8_t>& points_outside_;
    std::vector<uint8_t> new_outside_;
};

}  // namespace uvr::gpu
