#include "gpu/vicp/vicp_clip.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "gpu/pipeline/clip_position.h"

namespace uvr::gpu {

ClipVertex VicpClipper::vertex(uint32_t point) const
{
    ClipVertex v = clip_vertex(view_, moved_[point], 0.0);  // VICP takes its scalars from the cell's constants
    v.id = point;
    return v;
}

void VicpClipper::clip_triangle(const uint32_t v[3], std::vector<ClipVertex>& poly,
                                std::vector<ClipVertex>& scratch) const
{
    poly.assign({vertex(v[0]), vertex(v[1]), vertex(v[2])});
    clip_polygon(view_, planes_, poly, scratch);
}

void VicpClipper::near_face(const uint32_t v[4], std::vector<ClipVertex>& poly, std::vector<ClipVertex>& scratch) const
{
    const ClipVertex c[4] = {vertex(v[0]), vertex(v[1]), vertex(v[2]), vertex(v[3])};
    near_section(view_, planes_, c, poly);
    clip_polygon(view_, planes_, poly, scratch, kClipLeft);
    if (poly.size() < 3) return;
    // Facing the eye, that is counter-clockwise on screen: the polygon's normal (the sum of its fan's, robust for a
    // thin one) must point back at the eye. Away from the eye is the gradient of the clip z row, which grows with the
    // depth under either projection (gpu/pipeline/view_setup.cpp); the near plane is perpendicular to it.
    glm::dvec3 n(0.0);
    for (std::size_t i = 1; i + 1 < poly.size(); ++i)
        n += glm::cross(poly[i].p - poly[0].p, poly[i + 1].p - poly[0].p);
    const auto& m = view_.mvp_d;
    const glm::dvec3 forward(m[0][2], m[1][2], m[2][2]);
    if (glm::dot(n, forward) > 0.0) std::reverse(poly.begin(), poly.end());
}

WindowCoord frame_window_coord(const ViewSetup& view, const Framebuffer& fbuf, const glm::vec3& p)
{
    const auto clip = clip_position(view.mvp, p);
    return viewport_transform(clip.data(), fbuf);
}

}  // namespace uvr::gpu
