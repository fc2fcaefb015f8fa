// Splitting a tetrahedral mesh into parts, as data-parallel renderers split their data over processes
// (docs/distributed.md).
#pragma once

#include <cstdint>
#include <vector>

#include "reference/mesh.h"
#include "reference/topology.h"

namespace uvr {

// Per tetrahedron, its part in [0, parts): recursive coordinate bisection of the tetrahedra's centroids. Each step
// splits a set of cells at the plane normal to the longest side of its centroids' bounding box (the lowest axis on a
// tie), into two sets sized in proportion to the parts each receives (floor(n/2) and ceil(n/2) of n), ordering equal
// coordinates by cell index. Parts differ in size by at most one cell per level, and the result is the same on every
// run and machine. Throws InputError naming mesh.source unless 1 <= parts <= number of tetrahedra.
std::vector<uint32_t> partition_rcb(const TetMesh& mesh, uint32_t parts);

// The tetrahedra of `part` (in the mesh's order), the points they use (in the mesh's order, so coincident points stay
// distinct and per-cell vertex data survives) and every field's values there, unchanged.
TetMesh extract_part(const TetMesh& mesh, const std::vector<uint32_t>& part_of, uint32_t part);

// What a part holds: its tetrahedra, its faces on the mesh's boundary, and its cut faces (internal faces of the mesh
// whose other tetrahedron lies in another part: where the part's own boundary runs through the mesh).
struct PartCounts {
    std::size_t tetrahedra = 0, boundary_faces = 0, cut_faces = 0;
};
std::vector<PartCounts> count_parts(const MeshTopology& topo, const std::vector<uint32_t>& part_of);

}  // namespace uvr
