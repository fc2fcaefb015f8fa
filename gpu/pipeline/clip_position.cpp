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

std::array<float, 4> dp4_position(const Mat4f& m, const glm::vec3& p)
{
    // ARB's DP4 becomes NIR's fdot4, which llvmpipe (lower_fdot: no fused multiply-add on this driver) turns into
    // products summed from the last component down (nir_lower_alu_width.c, lower_reduction). The position's w is the
    // attribute's default 1, so its product is the matrix entry itself.
    std::array<float, 4> out{};
    for (int r = 0; r < 4; ++r) {
        float acc = m[3][r];
        acc = acc + m[2][r] * p.z;
        acc = acc + m[1][r] * p.y;
        acc = acc + m[0][r] * p.x;
        out[std::size_t(r)] = acc;
    }
    return out;
}

Mat4f driver_matrix_product(const Mat4f& a, const Mat4f& b)
{
    // P(i,j) = A(i,0) B(0,j) + A(i,1) B(1,j) + A(i,2) B(2,j) + A(i,3) B(3,j), left to right in float (Mesa's C, built
    // for x86-64 without FMA, so nothing is fused). Column-major: A(i,k) = a[k][i].
    Mat4f out{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            float acc = a[0][i] * b[j][0];
            acc = acc + a[1][i] * b[j][1];
            acc = acc + a[2][i] * b[j][2];
            acc = acc + a[3][i] * b[j][3];
            out[std::size_t(j)][std::size_t(i)] = acc;
        }
    return out;
}

std::array<float, 4> vertex_position(const ViewSetup& vs, const glm::vec3& p)
{
    return vs.program == VertexProgram::published ? dp4_position(vs.driver_mvp, p) : clip_position(vs.mvp, p);
}

glm::vec3 eye_position(const ViewSetup& vs, const glm::vec3& p)
{
    const auto e = vs.program == VertexProgram::published ? dp4_position(vs.view, p) : clip_position(vs.view, p);
    return glm::vec3(e[0], e[1], e[2]);
}

}  // namespace uvr::gpu
