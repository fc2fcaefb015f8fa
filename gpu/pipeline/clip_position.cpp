#include "gpu/pipeline/clip_position.h"

namespace uvr::gpu {

std::array<float, 4> clip_position(const Mat4f& m, const glm::vec3& p)
{
    std::array<float, 4> out{};
    for (int r = 0; r < 4; ++r) {
        float acc = m[0][r] * p.x;
        acc = acc + m[1][r] * p.y;
        acc = acc + m[2][r] * p.z;
        acc = acc + m[3][r];
        out[std::size_t(r)] = acc;
    }
    return out;
}

}  // namespace uvr::gpu
