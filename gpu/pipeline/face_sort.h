// HAVS's CPU stage: the mesh's unique faces sorted every frame, front to back, by the squared distance from the eye to
// each face's centroid (docs/spec.md §6), with a least-significant-digit radix sort on the float bits, as the original
// does. Twins: none (CPU stage). Callers: gpu/havs/havs_setup.cpp, and VICP's centroid order (gpu/vicp/vicp_order.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace uvr::gpu {

// Squared eye-to-centroid distance of each face, in float32 as a CPU stage feeding a GPU computes it: the centroid
// is (a + b + c) * (1/3) from the float vertex positions, then the squared length of (centroid - eye) summed x, y, z
// in that order. `faces` holds three vertex indices per face.
void face_sort_keys(const std::vector<glm::vec3>& points, const std::vector<uint32_t>& faces, const glm::vec3& eye,
                    std::vector<float>& keys);

// Face indices ordered by ascending key, stable (equal keys keep their index order). Four passes of 8 bits over the
// key's bit pattern: a non-negative float orders as its bits read as an unsigned integer, and a squared distance is
// never negative (a -0.0 is read as +0.0). `order` and `scratch` are resized as needed, so a caller that keeps them
// across frames allocates once.
void radix_sort_faces(const std::vector<float>& keys, std::vector<uint32_t>& order, std::vector<uint32_t>& scratch);

}  // namespace uvr::gpu
