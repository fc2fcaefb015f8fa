// What is derived from a mesh's connectivity: its unique faces, which tetrahedra share them, and the boundary.
//
// Face f of tetrahedron t is the face opposite its vertex f (it uses the other three). A unique face records the tets
// on either side; boundary faces have tet[1] = -1 and their vertices ordered so that (v1-v0)x(v2-v0) points out of the
// mesh. The ray walker (ground truth) steps through `neighbor`, HAVS sorts `faces`, the convexity flag tells the GPU
// algorithms whether gaps can occur.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "reference/mesh.h"

namespace uvr {

struct Face {
    std::array<uint32_t, 3> v;   // boundary: outward orientation; internal: as seen from tet[0] (normal out of tet[0])
    std::array<int32_t, 2> tet;  // tet[1] == -1 on the boundary
    bool boundary() const { return tet[1] < 0; }
};

struct MeshTopology {
    std::vector<Face> faces;                      // sorted by their smallest vertex triple: deterministic
    std::vector<std::array<int32_t, 4>> tet_faces;  // face index of the face opposite each vertex
    std::vector<std::array<int32_t, 4>> neighbor;   // tet across the face opposite each vertex, -1 on the boundary
    std::size_t boundary_faces = 0;
    std::size_t internal_faces = 0;
};

// Throws InputError naming mesh.source and the face (its three points and the tetrahedra) when a face is shared by more
// than two tetrahedra, or when the two tetrahedra of a face lie on the same side of it (overlapping cells).
MeshTopology build_topology(const TetMesh& mesh);

// The face of tet `t` opposite its vertex `i`, ordered so its normal points out of t.
std::array<uint32_t, 3> tet_face(const Tet& t, int i);

// Whether the boundary encloses a convex region: it is one connected closed surface and no boundary edge is reflex
// (the dihedral angle inside the mesh is at most 180 degrees, up to kConvexityTolerance). For a closed connected
// surface, local convexity at every edge implies global convexity (Tietze-Nakajima).
bool boundary_is_convex(const TetMesh& mesh, const MeshTopology& topo);

// A reflex edge is one where a neighbouring face's far vertex lies outside the plane of the other face by more than
// this fraction of the bounding box diagonal. Coplanar faces on a flat side of a box sit at rounding level (~1e-16 of
// the diagonal for coordinates of that scale); a fin or a tunnel is many orders of magnitude above 1e-9.
inline constexpr double kConvexityTolerance = 1e-9;

// Signed volume enclosed by the boundary faces (divergence theorem), and the sum of the tetrahedra's volumes. For a
// closed, outward-oriented boundary the two agree to rounding.
double boundary_enclosed_volume(const TetMesh& mesh, const MeshTopology& topo);
double total_tet_volume(const TetMesh& mesh);

// Every boundary edge is shared by exactly two boundary faces that traverse it in opposite directions (a closed,
// consistently oriented surface). Returns the number of edges that violate this (0 for a valid mesh).
std::size_t boundary_open_edges(const MeshTopology& topo);

}  // namespace uvr
