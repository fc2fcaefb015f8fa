#include "gpu/vicp/vicp_vertex.h"

namespace uvr::gpu {

namespace {
glm::dvec3 sub(const glm::dvec3& a, const glm::dvec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
glm::dvec3 cross(const glm::dvec3& a, const glm::dvec3& b)
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
}  // namespace

namespace {
// lambda_1..3's gradients n_i / det and det, from the points p[0..3].
double barycentric_gradients(const glm::dvec3 p[4], glm::dvec3 m[3])
{
    const glm::dvec3 e1 = sub(p[1], p[0]), e2 = sub(p[2], p[0]), e3 = sub(p[3], p[0]);
    const glm::dvec3 n1 = cross(e2, e3), n2 = cross(e3, e1), n3 = cross(e1, e2);
    const double det = (e1.x * n1.x + e1.y * n1.y) + e1.z * n1.z;
    const double inv = 1.0 / det;
    m[0] = {n1.x * inv, n1.y * inv, n1.z * inv};
    m[1] = {n2.x * inv, n2.y * inv, n2.z * inv};
    m[2] = {n3.x * inv, n3.y * inv, n3.z * inv};
    return det;
}
}  // namespace

VicpTet vicp_tet_constants(const glm::dvec3 shape[4], const glm::dvec3 exact[4], const double s[4],
                           uint32_t boundary)
{
    VicpTet t;
    t.p0 = shape[0];
    t.det = barycentric_gradients(shape, t.m);
    // The field: s = s0 + sum_i (s_i - s0) lambda_i over the exact cell, whose gradient is sum_i (s_i - s0) m_i.
    glm::dvec3* me = t.me;
    barycentric_gradients(exact, me);
    t.boundary = boundary;
    const double d1 = s[1] - s[0], d2 = s[2] - s[0], d3 = s[3] - s[0];
    t.g = {(d1 * me[0].x + d2 * me[1].x) + d3 * me[2].x, (d1 * me[0].y + d2 * me[1].y) + d3 * me[2].y,
           (d1 * me[0].z + d2 * me[1].z) + d3 * me[2].z};
    t.base = exact[0];
    t.s0 = s[0];
    return t;
}

}  // namespace uvr::gpu
