#include "gpu/pipeline/face_sort.h"

#include <array>
#include <cstring>

namespace uvr::gpu {

void face_sort_keys(const std::vector<glm::vec3>& points, const std::vector<uint32_t>& faces, const glm::vec3& eye,
                    std::vector<float>& keys)
{
    const std::size_t n = faces.size() / 3;
    keys.resize(n);
    const float third = 1.0f / 3.0f;
    for (std::size_t f = 0; f < n; ++f) {
        const glm::vec3 &a = points[faces[3 * f]], &b = points[faces[3 * f + 1]], &c = points[faces[3 * f + 2]];
        const glm::vec3 d = (a + b + c) * third - eye;
        keys[f] = d.x * d.x + d.y * d.y + d.z * d.z;
    }
}

void radix_sort_faces(const std::vector<float>& keys, std::vector<uint32_t>& order, std::vector<uint32_t>& scratch)
{
    const std::size_t n = keys.size();
    std::vector<uint32_t> bits(n);
    for (std::size_t i = 0; i < n; ++i) {
        uint32_t b;
        std::memcpy(&b, &keys[i], sizeof b);
        bits[i] = b & 0x7FFFFFFFu;  // -0.0 sorts as +0.0
    }
    order.resize(n);
    scratch.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = uint32_t(i);
    for (int pass = 0; pass < 4; ++pass) {
        const int shift = 8 * pass;
        std::array<std::size_t, 257> count{};
        for (std::size_t i = 0; i < n; ++i) ++count[((bits[order[i]] >> shift) & 0xFFu) + 1];
        for (int d = 0; d < 256; ++d) count[std::size_t(d) + 1] += count[std::size_t(d)];
        // Scattering in the current order keeps equal digits in order: each pass is stable, so the sort is.
        for (std::size_t i = 0; i < n; ++i) scratch[count[(bits[order[i]] >> shift) & 0xFFu]++] = order[i];
        order.swap(scratch);
    }
}

}  // namespace uvr::gpu
