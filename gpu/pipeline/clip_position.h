// The vertex stage's position: clip = mvp * vec4(p, 1) in float32, each row as ((m0 * x + m1 * y) + m2 * z) + m3,
// unfused, for HAVS's and VICP's vertex programs. Input: the setup's float matrix and a vertex-buffer position (relative
// to the setup's origin). Output: the clip coordinates the rasterizer receives.
// Twins: shaders/clip_position.vert (compiled in front of havs_vertex.vert and vicp.vert). Docs: docs/rasterizer.md.
#pragma once

#include <array>

#include <glm/vec3.hpp>

#include "gpu/pipeline/view_setup.h"

namespace uvr::gpu {

std::array<float, 4> clip_position(const Mat4f& mvp, const glm::vec3& p);

}  // namespace uvr::gpu
