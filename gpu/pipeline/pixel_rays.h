// The rays of a frame's pixels as the fragment programs that compute them in double (VICP's, the ray caster's) receive
// them: pixel (px, py) of GL window coordinates (row from the bottom) has ndc = (p + 0.5) * (2 / size) - 1 and the ray
// o = eye + ndc_x * ray_ox + ndc_y * ray_oy, d = ray_d0 + ndc_x * ray_dx + ndc_y * ray_dy (docs/spec.md §2; d is not
// normalized), in a frame centred on `origin`. Twins: none (CPU stage: it fills the uniforms);
// shaders/vicp_fragment.frag and shaders/raycast_fragment.frag apply the formula.
#pragma once

#include <glm/vec3.hpp>

#include "reference/camera.h"

namespace uvr::gpu {

struct PixelRays {
    double two_over_width = 0.0, two_over_height = 0.0;
    glm::dvec3 eye{0.0};                  // relative to the origin
    glm::dvec3 ray_ox{0.0}, ray_oy{0.0};  // orthographic: the image plane's half extents; perspective: 0
    glm::dvec3 ray_d0{0.0};               // the view direction (unit)
    glm::dvec3 ray_dx{0.0}, ray_dy{0.0};  // perspective: the image plane at distance 1; orthographic: 0
};

PixelRays pixel_rays(const Camera& cam, int width, int height, const glm::dvec3& origin);

}  // namespace uvr::gpu
