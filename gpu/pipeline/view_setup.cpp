#include "gpu/pipeline/view_setup.h"

#include "gpu/pipeline/clip_position.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>


namespace uvr::gpu {

namespace {

using Mat4d = std::array<std::array<double, 4>, 4>;

Mat4d multiply(const Mat4d& a, const Mat4d& b)
{
    Mat4d m{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k) m[c][r] += a[k][r] * b[c][k];
    return m;
}

Mat4f to_float(const Mat4d& m)
{
    Mat4f f{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) f[c][r] = float(m[c][r]);
    return f;
}

// The view matrix of points given relative to `origin` (the model matrix's translation folded in): the eye's offset
// from the origin is formed in double before anything else, so no large coordinate meets a small one in float.
Mat4d view_matrix(const Camera& cam, const glm::dvec3& origin)
{
    const CameraFrame fr = camera_frame(cam);
    Mat4d v{};
    const glm::dvec3 rows[3] = {fr.r, fr.u, -fr.f};
    const glm::dvec3 eye = cam.eye - origin;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) v[c][r] = rows[r][c];
        v[3][r] = -glm::dot(rows[r], eye);
    }
    v[3][3] = 1.0;
    return v;
}

}  // namespace

glm::dvec3 eye_space(const CameraFrame& fr, const glm::dvec3& d)
{
    return {glm::dot(fr.r, d), glm::dot(fr.u, d), -glm::dot(fr.f, d)};
}


ViewSetup view_setup(const Camera& cam, int width, int height, const Bounds& b, const glm::dvec3& origin)
{
    // Depth range: the bounds' corners along the view direction, widened by 1 % of the bounds' size.
    const CameraFrame fr = camera_frame(cam);
    double zmin = INFINITY, zmax = -INFINITY;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
        const double z = glm::dot(fr.f, p - cam.eye);
        zmin = std::min(zmin, z);
        zmax = std::max(zmax, z);
    }
    const double margin = 0.01 * glm::length(b.extent()) + 1e-9;
    double n = zmin - margin, f = zmax + margin;
    bool near_cuts = false;
    const double floor = kNearPlane * glm::length(b.extent());
    if (!(n >= floor)) {
        n = floor;
        near_cuts = true;
        f = std::max(f, n + margin);
    }
    Mat4d p{};
    const double aspect = double(width) / double(height);
    if (cam.orthographic) {
        // z_ndc(depth d) = (2 d - f - n) / (f - n) is -1 + kNearMargin at d = the near distance for this n (< 0).
        if (near_cuts) n = (n - 0.5 * kNearMargin * f) / (1.0 - 0.5 * kNearMargin);
        const double h = 0.5 * cam.ortho_height, w = h * aspect;
        p[0][0] = 1.0 / w;
        p[1][1] = 1.0 / h;
        p[2][2] = -2.0 / (f - n);
        p[3][2] = -(f + n) / (f - n);
        p[3][3] = 1.0;
    } else {
        const double t = 1.0 / std::tan(0.5 * cam.fovy_deg * 3.14159265358979323846 / 180.0);
        p[0][0] = t / aspect;
        p[1][1] = t;
        p[2][2] = -(f + n) / (f - n);
        p[2][3] = -1.0;
        p[3][2] = -2.0 * f * n / (f - n);
    }
    const Mat4d v = view_matrix(cam, origin);
    const Mat4d mvp = multiply(p, v);
    ViewSetup vs;
    vs.view = to_float(v);
    vs.projection = to_float(p);
    vs.mvp = to_float(mvp);
    vs.driver_mvp = driver_matrix_product(vs.projection, vs.view);
    vs.mvp_d = mvp;
    vs.near_cuts = near_cuts;
    return vs;
}

void window_position_d(const ViewSetup& vs, const glm::dvec3& p, int width, int height, double& x, double& y,
                       double& inv_w)
{
    double c[4];
    for (int r = 0; r < 4; ++r) c[r] = vs.mvp_d[0][r] * p.x + vs.mvp_d[1][r] * p.y + vs.mvp_d[2][r] * p.z + vs.mvp_d[3][r];
    inv_w = 1.0 / c[3];
    x = (c[0] * inv_w + 1.0) * (0.5 * width);
    y = (c[1] * inv_w + 1.0) * (0.5 * height);
}

}  // namespace uvr::gpu
