// VICP-ProjectTet's per-vertex record and VICP-VertexProg as Moreland's dissertation gives them (--interpolation gpu).
// ProjectTet sends each face's three vertices with 11 floats each (VicpPublishedVertex): the position, the
// scalar, the scalar's gradient, the plane of the face opposite the vertex in Weiler, Kraus and Ertl's three components
// (n with n . (x - v) = 1 on that plane), and the vertex's index in its face. The vertex program intersects the view
// ray through the vertex with that plane (IntersectBackFace: t = 1 / (n . r), the scalar s + t (g . r)) and puts the
// distance and the scalar into the entry of its index; the other two entries are 0 and the vertex's own scalar.
// float32, unfused. Input: VicpPublishedVertex, the view (perspective: r = v / |v|; orthographic: the view direction).
// Output: VicpPublishedVaryings (gpu/vicp/vicp_published_fragment.h), which the rasterizer interpolates `smooth`.
// Twins: shaders/vicp_published_vertex.vert; harness gpu/vicp/gl_vicp_harness.h (run_published_vertex). Derivation:
// docs/vicp.md, "The published pipeline".
#pragma once

#include <glm/vec3.hpp>

#include "gpu/vicp/vicp_published_fragment.h"

namespace uvr::gpu {

struct VicpPublishedVertex {
    glm::vec3 position{0.0f};  // relative to the eye (the vertex buffer's convention, docs/rasterizer.md)
    float s = 0.0f;            // normalized scalar
    glm::vec3 gradient{0.0f};  // of the normalized scalar, per world unit
    glm::vec3 plane{0.0f};     // n: n . (x - position) = 1 on the face opposite the vertex
    float index = 0.0f;        // 0, 1 or 2: the vertex's place in the face, the varyings' entry it fills
};
static_assert(sizeof(VicpPublishedVertex) == 11 * sizeof(float),
              "ProjectTet sends 11 floats a vertex (Moreland's dissertation)");

// The view the vertex program needs: perspective rays from the eye (the origin of the positions), or orthographic
// rays along `direction` (unit, world axes).
struct VicpPublishedView {
    int orthographic = 0;
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
};

VicpPublishedVaryings vicp_published_vertex_program(const VicpPublishedView& view, const VicpPublishedVertex& in);

// a . b as both twins write it: ((a.z b.z + a.y b.y) + a.x b.x), each product and sum rounded.
float vicp_published_dot3(const glm::vec3& a, const glm::vec3& b);
// Not the published: uvr's ordering-error diagnostic needs each fragment's distance from the eye, which the published
// varyings do not hold. The draw interpolates the vertex position (`smooth`, linear across the face, so the
// interpolated point is the ray's entry up to rounding) and takes its distance along the view ray: |entry| (sqrt of
// the dot product) under perspective, entry . direction when orthographic. Twin: shaders/vicp_published.glsl.
float vicp_published_entry_distance(const VicpPublishedView& view, const glm::vec3& entry);

// The plane of the face opposite vertex `v` of the tetrahedron (v, a, b, c) in the record's three components, in
// double: N = (b - a) x (c - a), n = N / (N . (a - v)). The tetrahedron must not be flat.
glm::dvec3 vicp_published_plane(const glm::dvec3& v, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);
// The gradient of the linear field with values s[i] at p[i], in double (0 for a flat cell).
glm::dvec3 vicp_published_gradient(const glm::dvec3 p[4], const double s[4]);

}  // namespace uvr::gpu
