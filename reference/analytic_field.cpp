#include "reference/analytic_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "reference/segment_integral.h"

namespace uvr {

namespace {

// The deepest halving: a piece 2^-40 of the ray is far below any tolerance's need on a smooth field; it ends the
// recursion where the field is not smooth enough for the estimate.
constexpr int kMaxHalvings = 40;
// The shallowest accepted: 16 pieces a ray, so that a whole ray whose halves agree by symmetry is not taken as done.
constexpr int kMinHalvings = 4;

struct Piece {
    const AnalyticField& field;
    const SegmentIntegrator& segment;
    const Ray& ray;
    double tolerance_per_length;
};

// `whole`: the piece [a, b] integrated in one (the caller computed it as one of its halves).
glm::dvec4 integrate_piece(const Piece& p, double a, double b, double sa, double sb, const glm::dvec4& whole, int depth)
{
    const double m = 0.5 * (a + b);
    const double sm = p.field(p.ray.origin + m * p.ray.dir);
    const glm::dvec4 front = p.segment.integrate(sa, sm, m - a), back = p.segment.integrate(sm, sb, b - m);
    const glm::dvec4 halves = composite_over(front, back);
    const glm::dvec4 d = glm::abs(halves - whole);
    if (depth >= kMaxHalvings ||
        (depth >= kMinHalvings && std::max(std::max(d.x, d.y), std::max(d.z, d.w)) <= p.tolerance_per_length * (b - a)))
        return halves;
    return composite_over(integrate_piece(p, a, m, sa, sm, front, depth + 1),
                          integrate_piece(p, m, b, sm, sb, back, depth + 1));
}

}  // namespace

glm::dvec4 integrate_analytic(const AnalyticField& field, const Bounds& box, const SegmentIntegrator& segment,
                              const Ray& ray, double tolerance)
{
    // The slab test: the ray's interval inside the box.
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const double inv = 1.0 / ray.dir[k];
        double ta = (box.lo[k] - ray.origin[k]) * inv, tb = (box.hi[k] - ray.origin[k]) * inv;
        if (ta > tb) std::swap(ta, tb);
        if (std::isnan(ta) || std::isnan(tb)) {  // parallel to the slab: inside it or not
            if (ray.origin[k] < box.lo[k] || ray.origin[k] > box.hi[k]) return glm::dvec4(0.0);
            continue;
        }
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t1 > t0)) return glm::dvec4(0.0);
    const Piece p{field, segment, ray, tolerance / (t1 - t0)};
    const double s0 = field(ray.origin + t0 * ray.dir), s1 = field(ray.origin + t1 * ray.dir);
    return integrate_piece(p, t0, t1, s0, s1, segment.integrate(s0, s1, t1 - t0), 0);
}

Image render_analytic(const AnalyticField& field, const Bounds& box, const TransferFunction& tf, const Camera& camera,
                      int width, int height, double tolerance)
{
    Image img(width, height);
    const SegmentIntegrator segment(tf);
    const CameraRays rays(camera, width, height);
    tbb::parallel_for(tbb::blocked_range2d<int>(0, height, 16, 0, width, 16), [&](const tbb::blocked_range2d<int>& r) {
        for (int j = r.rows().begin(); j < r.rows().end(); ++j)
            for (int i = r.cols().begin(); i < r.cols().end(); ++i) {
                const glm::dvec4 c = integrate_analytic(field, box, segment, rays(i, j), tolerance);
                float* px = img.pixel(i, j);
                for (int k = 0; k < 4; ++k) px[k] = float(c[k]);
            }
    });
    return img;
}

}  // namespace uvr
