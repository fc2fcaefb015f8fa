#include "gpu/pipeline/clip.h"

#include <utility>

#include "gpu/pipeline/clip_position.h"

namespace uvr::gpu {

ClipPlanes inner_clip_planes(int width, int height)
{
    // NDC spans 2 over `width` pixels: kClipMarginPixels pixels are 2 * kClipMarginPixels / width of it.
    return {1.0 - 2.0 * kClipMarginPixels / double(width), 1.0 - 2.0 * kClipMarginPixels / double(height),
            1.0 - kNearMargin};
}

ClipVertex clip_vertex(const ViewSetup& vs, const glm::dvec3& p, double s)
{
    ClipVertex v;
    v.p = p;
    v.s = s;
    const auto& m = vs.mvp_d;
    for (int r = 0; r < 4; ++r) v.c[r] = ((m[0][r] * p.x + m[1][r] * p.y) + m[2][r] * p.z) + m[3][r];
    return v;
}

double plane_value(const ClipPlanes& pl, int plane, const glm::dvec4& c)
{
    switch (plane) {
    case kClipNear: return c.z + pl.az * c.w;
    case kClipLeft: return c.x + pl.ax * c.w;
    case kClipRight: return pl.ax * c.w - c.x;
    case kClipBottom: return c.y + pl.ay * c.w;
    default: return pl.ay * c.w - c.y;  // kClipTop
    }
}

unsigned outcode(const ClipPlanes& planes, const glm::dvec4& c)
{
    unsigned code = 0;
    for (int p = 0; p < kClipPlaneCount; ++p)
        if (plane_value(planes, p, c) < 0.0) code |= 1u << p;
    return code;
}

namespace {
bool lexicographically_less(const glm::dvec3& a, const glm::dvec3& b)
{
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}
}  // namespace

ClipVertex crossing(const ViewSetup& vs, const ClipPlanes& planes, int plane, const ClipVertex& a0,
                    const ClipVertex& b0)
{
    const bool swap = lexicographically_less(b0.p, a0.p);
    const ClipVertex& a = swap ? b0 : a0;
    const ClipVertex& b = swap ? a0 : b0;
    const double la = plane_value(planes, plane, a.c), lb = plane_value(planes, plane, b.c);
    // An end on the plane is the crossing itself (a + 1 * (b - a) need not round to b).
    if (la == 0.0) return a;
    if (lb == 0.0) return b;
    const double t = la / (la - lb);
    return clip_vertex(vs, a.p + t * (b.p - a.p), a.s + t * (b.s - a.s));
}

void clip_polygon(const ViewSetup& vs, const ClipPlanes& planes, std::vector<ClipVertex>& poly,
                  std::vector<ClipVertex>& out, int first)
{
    for (int plane = first; plane < kClipPlaneCount && !poly.empty(); ++plane) {
        bool any_out = false;
        for (const ClipVertex& v : poly) any_out = any_out || plane_value(planes, plane, v.c) < 0.0;
        if (!any_out) continue;
        out.clear();
        const std::size_t n = poly.size();
        for (std::size_t i = 0; i < n; ++i) {
            const ClipVertex& cur = poly[i];
            const ClipVertex& next = poly[(i + 1) % n];
            const bool cur_in = plane_value(planes, plane, cur.c) >= 0.0;
            const bool next_in = plane_value(planes, plane, next.c) >= 0.0;
            if (cur_in) out.push_back(cur);
            if (cur_in != next_in) out.push_back(crossing(vs, planes, plane, cur, next));
        }
        std::swap(poly, out);
        if (poly.size() < 3) poly.clear();
    }
}

uint32_t ClipVertexBuffer::append(const ClipVertex& v)
{
    const uint32_t id = uint32_t(points_f_.size());
    points_f_.push_back(glm::vec3(v.p));
    const auto clip = vertex_position(view_, points_f_.back());
    win_.push_back(viewport_transform(clip.data(), fbuf_));
    new_outside_.push_back(outside_gpu_frustum(clip) ? 1 : 0);
    return id;
}

bool outside_gpu_frustum(const std::array<float, 4>& c)
{
    const float w = c[3];
    return !(c[0] >= -w && c[0] <= w && c[1] >= -w && c[1] <= w && c[2] >= -w && c[2] <= w);
}

void near_section(const ViewSetup& vs, const ClipPlanes& planes, const ClipVertex v[4], std::vector<ClipVertex>& poly)
{
    poly.clear();
    int front[4], back[4], nf = 0, nb = 0;  // front: strictly before the near plane (clipped away)
    for (int i = 0; i < 4; ++i) {
        if (plane_value(planes, kClipNear, v[i].c) < 0.0)
            front[nf++] = i;
        else
            back[nb++] = i;
    }
    if (nf == 0 || nb == 0) return;
    auto cut = [&](int a, int b) { poly.push_back(crossing(vs, planes, kClipNear, v[a], v[b])); };
    if (nf == 1) {
        for (int j = 0; j < 3; ++j) cut(front[0], back[j]);
    } else if (nb == 1) {
        for (int j = 0; j < 3; ++j) cut(front[j], back[0]);
    } else {
        // Two and two: front a, b and back c, d cut edges ac, ad, bd, bc, in that cyclic order (consecutive cuts share a
        // face of the tetrahedron: acd, abd, bcd, abc).
        cut(front[0], back[0]);
        cut(front[0], back[1]);
        cut(front[1], back[1]);
        cut(front[1], back[0]);
    }
}

}  // namespace uvr::gpu
