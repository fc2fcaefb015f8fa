// VICP's vertex stage (Moreland's dissertation, VICP-VertexProg), emulated operation by operation in double:
// vicp_tet_constants (a tetrahedron's snapped shape, its exact points and normalized scalars, its boundary mask ->
// VicpTet, the flat constants every vertex of the cell passes: the barycentric coordinate functions and the scalar's
// gradient). Twins: shaders/vicp_vertex.vert (VicpTet in shaders/vicp_tet.glsl; the draw's main is shaders/vicp.vert);
// harness gpu/vicp/gl_vicp_harness.h. Derivation: docs/vicp.md, "The flat constants".
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec3.hpp>

namespace uvr::gpu {

// What the vertex program passes to the fragment program (flat).
struct VicpTet {
    // The cell's shape, as the rasterizer drew it (from the snapped points, gpu/vicp/vicp_fragment.h "Snapping").
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
