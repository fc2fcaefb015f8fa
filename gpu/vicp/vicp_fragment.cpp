#include "gpu/vicp/vicp_fragment.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace uvr::gpu {

namespace {
// The four barycentric coordinates along the ray q + t d (q relative to the tetrahedron's vertex 0), lambda_i(t) =
// a[i] + t b[i], from the gradients m of lambda_1..3; lambda_0 = 1 - the others.
void barycentrics_along(const glm::dvec3 m[3], double qx, double qy, double qz, double dx, double dy, double dz,
                        double a[4], double b[4])
{
    for (int i = 0; i < 3; ++i) {
        a[i + 1] = (m[i].x * qx + m[i].y * qy) + m[i].z * qz;
        b[i + 1] = (m[i].x * dx + m[i].y * dy) + m[i].z * dz;
    }
    a[0] = 1.0 - ((a[1] + a[2]) + a[3]);
    b[0] = 0.0 - ((b[1] + b[2]) + b[3]);
}
// The rule for a ray that lies in the plane of faces of the cell (bit i of `in_plane`: face i), the rasterizer's fill
// rule and the exact coverage's (gpu/pipeline/exact_coverage.h; docs/spec.md §7): the ray counts as inside when the
// ray through the pixel centre moved by (e, e^2) in window coordinates (y up), e -> 0+, is inside each such face. Moving the pixel by
// one in window x changes lambda_i by gx = m_i . (ray_ox + t ray_dx) times 2 / width (y: ray_oy, ray_dy), at any t
// past the eye (one of the two terms is zero: orthographic rays share d, perspective ones o). The cell on the other
// side of the face has the opposite gradient, so exactly one of the two takes the ray.
bool inside_moved_ray(const VicpFrameConstants& fc, const VicpTet& tet, unsigned in_plane, double t_in, double t_out)
{
    const double t = t_out < kVicpNoExit ? 0.5 * (t_in + t_out) : t_in + 1.0;
    const glm::dvec3 wx = fc.ray_ox + t * fc.ray_dx, wy = fc.ray_oy + t * fc.ray_dy;
    for (int i = 0; i < 4; ++i) {
        if (!(in_plane & (1u << i))) continue;
        const glm::dvec3* m = (tet.boundary & (1u << i)) ? tet.me : tet.m;
        const glm::dvec3 grad = i == 0 ? -((m[0] + m[1]) + m[2]) : m[i - 1];
        const double gx = glm::dot(grad, wx) * fc.two_over_width, gy = glm::dot(grad, wy) * fc.two_over_height;
        // gx is zero up to rounding where the face's trace on the screen is horizontal (kParallelFace's reasoning).
        const bool horizontal = !(std::fabs(gx) > kParallelFace * (std::fabs(gx) + std::fabs(gy)));
        if (!(horizontal ? gy > 0.0 : gx > 0.0)) return false;
    }
    return true;
}

}  // namespace

VicpSegment vicp_fragment_values(const VicpFrameConstants& fc, const VicpTet& tet, int pix_x, int pix_y)
{
    const double ndc_x = (double(pix_x) + 0.5) * fc.two_over_width - 1.0;
    const double ndc_y = (double(pix_y) + 0.5) * fc.two_over_height - 1.0;
    // The ray, relative to vertex 0.
    const double qx = ((fc.eye.x + ndc_x * fc.ray_ox.x) + ndc_y * fc.ray_oy.x) - tet.p0.x;
    const double qy = ((fc.eye.y + ndc_x * fc.ray_ox.y) + ndc_y * fc.ray_oy.y) - tet.p0.y;
    const double qz = ((fc.eye.z + ndc_x * fc.ray_ox.z) + ndc_y * fc.ray_oy.z) - tet.p0.z;
    const double dx = (fc.ray_d0.x + ndc_x * fc.ray_dx.x) + ndc_y * fc.ray_dy.x;
    const double dy = (fc.ray_d0.y + ndc_x * fc.ray_dx.y) + ndc_y * fc.ray_dy.y;
    const double dz = (fc.ray_d0.z + ndc_x * fc.ray_dx.z) + ndc_y * fc.ray_dy.z;
    // lambda_i(t) = a[i] + t * b[i], from the snapped shape's gradients; the boundary faces' from the exact cell's (the
    // ray relative to its vertex 0: o - base = q + (p0 - base)).
    double a[4], b[4];
    barycentrics_along(tet.m, qx, qy, qz, dx, dy, dz, a, b);
    const double bx = qx + (tet.p0.x - tet.base.x), by = qy + (tet.p0.y - tet.base.y), bz = qz + (tet.p0.z - tet.base.z);
    if (tet.boundary) {
        double ae[4], be[4];
        barycentrics_along(tet.me, bx, by, bz, dx, dy, dz, ae, be);
        for (int i = 0; i < 4; ++i)
            if (tet.boundary & (1u << i)) a[i] = ae[i], b[i] = be[i];
    }
    // Entry: the last face whose lambda rises through zero (not before the ray's origin); exit: the first whose lambda
    // falls to zero. Some b is negative: the four sum to zero and d is not zero.
    // A face the ray runs along (|b| at rounding level: the ray lies in its plane, which the rasterizer's fill rule
    // decided) bounds nothing: its crossing -a / b would be rounding noise (kParallelFace).
    const double parallel = kParallelFace * ((std::fabs(b[0]) + std::fabs(b[1])) + (std::fabs(b[2]) + std::fabs(b[3])));
    const double outside = kParallelOutside * ((std::fabs(a[0]) + std::fabs(a[1])) + (std::fabs(a[2]) + std::fabs(a[3])));
    double t_in = 0.0, t_out = kVicpNoExit;
    int exit_face = -1;
    bool misses = false;
    unsigned in_plane = 0;  // bit i: the ray lies in face i's plane
    for (int i = 0; i < 4; ++i) {
        if (!(std::fabs(b[i]) > parallel)) {
            misses = misses || a[i] < -outside;
            if (!(a[i] < -outside) && !(a[i] > outside)) in_plane |= 1u << i;
            continue;
        }
        const double t = -a[i] / b[i];
        if (b[i] > 0.0 && t > t_in) t_in = t;
        if (b[i] < 0.0 && t < t_out) t_out = t, exit_face = i;
    }
    if (in_plane && !misses) misses = !inside_moved_ray(fc, tet, in_plane, t_in, t_out);
    const double scale = std::sqrt((dx * dx + dy * dy) + dz * dz);
    // The scalar along the ray, from the exact cell's field: s(t) = s0 + (g . (o - base) + t g . d).
    const double ga = (tet.g.x * bx + tet.g.y * by) + tet.g.z * bz;
    const double gb = (tet.g.x * dx + tet.g.y * dy) + tet.g.z * dz;
    auto scalar = [&](double t) {
        const double s = tet.s0 + (ga + t * gb);
        return s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    };
    VicpSegment out;
    out.s_front = scalar(t_in);
    out.s_back = scalar(t_out);
    out.t_in = t_in * scale;
    out.t_out = t_out * scale;
    out.length = (t_out - t_in) * scale;
    out.exit_face = exit_face;
    out.misses = misses;
    return out;
}

}  // namespace uvr::gpu
