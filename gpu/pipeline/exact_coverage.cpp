#include "gpu/pipeline/exact_coverage.h"

#include <utility>

namespace uvr::gpu {

namespace {

// The edge function of the directed edge a -> b at point q: positive when q lies to its left. Computed from the
// vertex with the smaller id, so that the triangle on the other side of a shared edge, which runs it the other way,
// gets exactly the negated value: the two never both cover, nor both miss, a point off the edge's line.
double edge_function(const glm::dvec2& a, uint32_t ia, const glm::dvec2& b, uint32_t ib, double qx, double qy)
{
    const auto orient = [&](const glm::dvec2& u, const glm::dvec2& v) {
        return (v.x - u.x) * (qy - u.y) - (v.y - u.y) * (qx - u.x);
    };
    return ia < ib ? orient(a, b) : -orient(b, a);
}

// The fill rule for a point exactly on an edge, the rasterizer's own (gpu/pipeline/rasterize.h: left and bottom edges
// in, GL y up): the point counts as moved by (e, e^2), e -> 0+, so the edge a -> b of a counter-clockwise triangle,
// whose interior lies to its left, keeps it when it runs downwards, or horizontally to the right. The neighbour runs
// the edge the other way, so exactly one of the two keeps it; at a vertex, exactly one triangle of a fan around it
// does.
bool keeps_points_on(const glm::dvec2& a, const glm::dvec2& b)
{
    const double dx = b.x - a.x, dy = b.y - a.y;
    return dy < 0.0 || (dy == 0.0 && dx > 0.0);
}

}  // namespace

ExactTriangle exact_triangle(const glm::dvec2 p[3], const uint32_t id[3])
{
    ExactTriangle t;
    for (int i = 0; i < 3; ++i) {
        t.p[i] = p[i];
        t.id[i] = id[i];
    }
    const double area2 = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
    if (!(area2 != 0.0) || !std::isfinite(area2)) return t;  // no area: no ray crosses it
    t.facing = area2 > 0.0 ? Facing::front : Facing::back;
    if (area2 < 0.0) {
        std::swap(t.p[1], t.p[2]);
        std::swap(t.id[1], t.id[2]);
    }
    t.x0 = std::min({p[0].x, p[1].x, p[2].x});
    t.x1 = std::max({p[0].x, p[1].x, p[2].x});
    t.y0 = std::min({p[0].y, p[1].y, p[2].y});
    t.y1 = std::max({p[0].y, p[1].y, p[2].y});
    return t;
}

bool exact_covers(const ExactTriangle& t, int px, int py)
{
    const double qx = double(px) + 0.5, qy = double(py) + 0.5;
    for (int e = 0; e < 3; ++e) {
        const int a = e, b = (e + 1) % 3;
        const double f = edge_function(t.p[a], t.id[a], t.p[b], t.id[b], qx, qy);
        if (f < 0.0 || (f == 0.0 && !keeps_points_on(t.p[a], t.p[b]))) return false;
    }
    return true;
}

}  // namespace uvr::gpu
