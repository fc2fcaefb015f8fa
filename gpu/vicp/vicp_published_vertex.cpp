#include "gpu/vicp/vicp_published_vertex.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace uvr::gpu {

// The order llvmpipe lowers dot() in (from the last component, docs/havs-arb.md "Compilation"); the twin spells it out.
float vicp_published_dot3(const glm::vec3& a, const glm::vec3& b)
{
    const float zz = a.z * b.z, yy = a.y * b.y, xx = a.x * b.x;
    const float zy = zz + yy;
    return zy + xx;
}

float vicp_published_entry_distance(const VicpPublishedView& view, const glm::vec3& entry)
{
    if (view.orthographic != 0) return vicp_published_dot3(entry, view.direction);
    return std::sqrt(vicp_published_dot3(entry, entry));  // GLSL sqrt: correctly rounded on llvmpipe (LLVM's sqrt)
}

VicpPublishedVaryings vicp_published_vertex_program(const VicpPublishedView& view, const VicpPublishedVertex& in)
{
    // The view ray's direction at the vertex: v / |v| by DP3, RSQ (1 / sqrt: two roundings), MUL, or the view's.
    glm::vec3 r = view.direction;
    if (view.orthographic == 0) {
        const float vv = vicp_published_dot3(in.position, in.position);
        const float rsq = 1.0f / std::sqrt(vv);
        r = glm::vec3(in.position.x * rsq, in.position.y * rsq, in.position.z * rsq);
    }
    // IntersectBackFace: position + t r on the plane n . (x - position) = 1, so t = 1 / (n . r) (an IEEE division:
    // llvmpipe sets no lower_fdiv); the scalar there s + t (g . r).
    const float nr = vicp_published_dot3(in.plane, r);
    const float t = 1.0f / nr;
    const float gr = vicp_published_dot3(in.gradient, r);
    const float tg = t * gr;
    const float s_exit = in.s + tg;
    VicpPublishedVaryings out;
    out.scalar = glm::vec3(in.s);
    out.s = in.s;
    // The entry of the vertex's index; float(0), float(1), float(2) compared exactly.
    const int i = in.index == 0.0f ? 0 : in.index == 1.0f ? 1 : 2;
    out.distance[i] = t;
    out.scalar[i] = s_exit;
    return out;
}

glm::dvec3 vicp_published_plane(const glm::dvec3& v, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const glm::dvec3 n = glm::cross(b - a, c - a);
    return n / glm::dot(n, a - v);
}

glm::dvec3 vicp_published_gradient(const glm::dvec3 p[4], const double s[4])
{
    const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
    const double det = glm::dot(e1, glm::cross(e2, e3));
    if (det == 0.0) return glm::dvec3(0.0);
    return (glm::cross(e2, e3) * (s[1] - s[0]) + glm::cross(e3, e1) * (s[2] - s[0]) +
            glm::cross(e1, e2) * (s[3] - s[0])) /
           det;
}

}  // namespace uvr::gpu
