// VICP's vertex stage (seed 003, VICP-VertexProg), emulated operation by operation in double, and its GLSL twin
// shaders/vicp_vertex.vert.
//
// The seed's vertex program intersects the view ray through its vertex with the tetrahedron's faces and lets the
// rasterizer interpolate the distances and scalars across the projected face. Interpolators cannot be mirrored bit for
// bit (docs/vicp.md), so here the vertex program computes what the interpolation would be built from, once per
// tetrahedron and identically at each of its vertices, and passes it `flat` (a flat varying is the provoking vertex's
// value, copied without arithmetic): the barycentric coordinate functions of the tetrahedron, lambda_i(x) =
// m_i . (x - p0) for i = 1, 2, 3 and lambda_0 = 1 - lambda_1 - lambda_2 - lambda_3. lambda_i is 0 on the face
// opposite vertex i (the seed's "opposite faces") and 1 at vertex i, so the fragment program finds where its ray
// crosses each face (a plane intersection per face, VICP-FragmentProg) and the scalar there (the barycentric mean of
// the scalar's gradient) from these constants alone. They depend on the view only through the rasterizer's snapping
// (vicp_fragment.h): nothing else of the view reaches the vertex program, the independence the algorithm is named
// after.
//
// m_i is the face normal n_i = e_j x e_k of the face opposite vertex i divided by det = e1 . (e2 x e3), with e_i =
// p_i - p0 in double (positions relative to the mesh's centre, VICP's vertex buffer). Each operation is written out
// in a fixed order; the shader marks them `precise`.
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec3.hpp>

namespace uvr::gpu {

// What the vertex program passes to the fragment program (flat).
struct VicpTet {
    // The cell's shape, as the rasterizer drew it (from the snapped points, gpu/vicp_fragment.h "Snapping").
    glm::dvec3 p0{0.0};         // vertex 0, relative to the mesh's centre
    glm::dvec3 m[3];            // gradients of lambda_1, lambda_2, lambda_3
    double det = 0.0;           // e1 . (e2 x e3): six times the signed volume (the CPU's orientation check)
    // The cell as the mesh has it: its boundary faces bound the rays (vicp_fragment.h), and its scalar field is
    // s(x) = s0 + g . (x - base).
    glm::dvec3 base{0.0};       // vertex 0
    glm::dvec3 me[3];           // gradients of lambda_1..3 of the exact cell
    uint32_t boundary = 0;      // bit i: the face opposite vertex i lies on the mesh's boundary
    glm::dvec3 g{0.0};          // the normalized scalar's gradient
    double s0 = 0.0;            // normalized scalar at vertex 0, in [0, 1]
};

// The constants of the tetrahedron whose shape has vertices shape[0..3] and whose field has the normalized scalars
// s[0..3] at the points exact[0..3] (all relative to the mesh's centre).
VicpTet vicp_tet_constants(const glm::dvec3 shape[4], const glm::dvec3 exact[4], const double s[4],
                           uint32_t boundary);

// The four faces of a positively oriented tetrahedron (det > 0), as the vertex program emits them: face f opposite
// vertex f, corners counter-clockwise seen from outside (reference/topology.cpp's tet_face), so that a face the eye
// sees from outside is front-facing and the rasterizer culls the others. 12 vertices a tetrahedron, in this order.
inline constexpr int kVicpCorner[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
inline constexpr int kVicpVerticesPerTet = 12;

}  // namespace uvr::gpu
