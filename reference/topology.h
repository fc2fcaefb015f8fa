// What is derived from a mesh's connectivity: its unique faces, which tetrahedra share them, and the boundary.
//
// Face f of tetrahedron t is the face opposite its vertex f (it uses the other three). A unique face records the tets
// on either side; boundary faces have tet[1] = -1 and their vertices ordered so that (v1-v0)x(v2-v0) points out of the
// mesh.
//
// Two things make the face graph of real meshes differ from their index graph. Points with bit-identical coordinates
// are one point for adjacency (a file may repeat a point; a curvilinear grid collapses cells on purpose), so faces are
// matched by canonical point (the smallest index at that position). And flat tetrahedra kept from collapsed grid cells
// (DegenerateCells::keep) cover no volume, so they are left out of the face graph: their tet_faces and neighbors are
// all -1, and the real tetrahedra on either side of them meet directly. The ray walker (ground truth) steps through `neighbor`, HAVS sorts `faces`, the convexity flag tells the GPU
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
    std::vector<uint32_t> canonical;              // per point: the smallest index of a point at the same position
    std::vector<Face> faces;  // sorted by their canonical vertex triple, tet[0] < tet[1] where shared: deterministic
    std::vector<std::array<int32_t, 4>> tet_faces;  // face index of the face opposite each vertex
    std::vector<std::array<int32_t, 4>> neighbor;   // tet across the face opposite each vertex, -1 on the boundary
    std::size_t boundary_faces = 0;
    std::size_t internal_faces = 0;
    std::size_t flat_tets = 0;                    // degenerate tetrahedra left out of the face graph
};

// Per point: the smallest index of a point with bit-identical coordinates (MeshTopology::canonical).
std::vector<uint32_t> canonical_points(const std::vector<glm::dvec3>& points);

// Throws InputError naming mesh.source and the face (its three points and the tetrahedra) when a face is shared by more
// than two tetrahedra, or when the two tetrahedra of a face lie on the same side of it (overlapping cells).
MeshTopology build_topology(const TetMesh& mesh);

// The face of tet `t` opposite its vertex `i`, ordered so its normal points out of t.
std::array<uint32_t, 3> tet_face(const Tet& t, int i);

// Per point: 1 when a coincident point exists that the internal faces do not connect it to (through the corresponding
// points of shared faces): the point lies on a seam between cells the face graph did not match, such as the periodic
// seam of an O-grid. Coincident points that the internal faces connect are one point written several times (a file
// that repeats points per cell) and are not seam points.
std::vector<uint8_t> seam_points(const TetMesh& mesh, const MeshTopology& topo);

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

// A closed, consistently oriented boundary traverses every edge (between canonical points) as often in one direction
// as in the other. Returns the number of edges where the two counts differ (0 for a valid mesh). Usually each edge
// has exactly two faces; a non-conforming interface, such as the periodic seam of an O-grid split into tetrahedra by
// alternating parity with an odd number of cells around, is geometrically closed but gives its edges four boundary
// faces, balanced two and two.
std::size_t boundary_open_edges(const MeshTopology& topo);

// Boundary edges with other than two faces (counted once per edge).
std::size_t boundary_nonmanifold_edges(const MeshTopology& topo);

}  // namespace uvr
