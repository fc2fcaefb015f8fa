// The vertex stage's position in float32, unfused: uvr's program (clip_position: each row ((m0 x + m1 y) + m2 z) + m3)
// or the paper's ARB program (dp4_position: DP4 as llvmpipe sums it, ((m3 + m2 z) + m1 y) + m0 x, on state.matrix.mvp,
// the driver's float product driver_matrix_product). Input: a matrix and a vertex-buffer position (relative to the
// setup's origin). Output: the clip (or eye) coordinates. vertex_position / eye_position pick by ViewSetup::program.
// Twins: shaders/clip_position.vert (compiled in front of havs_vertex.vert and vicp.vert). Docs: docs/rasterizer.md,
// "The vertex stage"; docs/havs-arb.md, "The published vertex program".
#pragma once

#include <array>

#include <glm/vec3.hpp>

#include "gpu/pipeline/view_setup.h"

namespace uvr::gpu {

std::array<float, 4> clip_position(const Mat4f& mvp, const glm::vec3& p);
std::array<float, 4> dp4_position(const Mat4f& m, const glm::vec3& p);
// a * b as Mesa's matmul4 (src/mesa/math/m_matrix.c) computes state.matrix.mvp: ((a0 b0 + a1 b1) + a2 b2) + a3 b3.
Mat4f driver_matrix_product(const Mat4f& a, const Mat4f& b);

// The clip position and the eye-space position of ViewSetup's vertex program.
std::array<float, 4> vertex_position(const ViewSetup& vs, const glm::vec3& p);
glm::vec3 eye_position(const ViewSetup& vs, const glm::vec3& p);

}  // namespace uvr::gpu
