#include "gpu/pipeline/pixel_rays.h"

#include <cmath>

namespace uvr::gpu {

PixelRays pixel_rays(const Camera& cam, int width, int height, const glm::dvec3& origin)
{
    PixelRays r;
    const CameraFrame cf = camera_frame(cam);
    r.two_over_width = 2.0 / double(width);
    r.two_over_height = 2.0 / double(height);
    r.eye = cam.eye - origin;
    r.ray_d0 = cf.f;
    const double aspect = double(width) / double(height);
    if (cam.orthographic) {
        const double h = 0.5 * cam.ortho_height;
        r.ray_ox = cf.r * (h * aspect);
        r.ray_oy = cf.u * h;
    } else {
        const double t = std::tan(0.5 * cam.fovy_deg * 3.14159265358979323846 / 180.0);
        r.ray_dx = cf.r * (t * aspect);
        r.ray_dy = cf.u * t;
    }
    return r;
}

}  // namespace uvr::gpu
