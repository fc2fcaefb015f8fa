// Splitting a tetrahedral mesh into parts, as data-parallel renderers split their data over processes
// (docs/distributed.md).
#pragma once

#include <cstdint>
#include <vector>

#include "reference/choice.h"
#include "reference/mesh.h"
#include "reference/topology.h"

namespace uvr {

// How a mesh is split: `uvr partition --method`.
enum class PartitionMethod { rcb, metis };
inline constexpr Choices<PartitionMethod, 2> kPartitionMethods{{
    {PartitionMethod::rcb, "rcb", "recursive coordinate bisection of the cells' centroids: parts in boxes"},
    {PartitionMethod::metis, "metis",
     "METIS's k-way partition of the cell graph: balanced, fewest cut faces, not convex"},
}};

// Per tetrahedron, its part in [0, parts), by `method` (the functions below).
std::vector<uint32_t> partition_mesh(const TetMesh& mesh, uint32_t parts, PartitionMethod method);

// Per tetrahedron, its part in [0, parts): recursive coordinate bisection of the tetrahedra's centroids. Each step
// splits a set of cells at the plane normal to the longest side of its centroids' bounding box (the lowest axis on a
// tie), into two sets sized in proportion to the parts each receives (floor(n/2) and ceil(n/2) of n), ordering equal
// coordinates by cell index. Parts differ in size by at most one cell per level, and the result is the same on every
// run and machine. Throws InputError naming mesh.source unless 1 <= parts <= number of tetrahedra.
std::vector<uint32_t> partition_rcb(const TetMesh& mesh, uint32_t parts);

// Per tetrahedron, its part in [0, parts): METIS_PartGraphKway (Debian's libmetis) on the graph whose vertices are the
// tetrahedra and whose edges are the internal faces (build_topology's, coincident points welded), with METIS's
// default load imbalance (kMetisImbalance) and a fixed seed, so the result is the same on every run. The parts are
// balanced and cut few faces, but are not boxes. Same refusals as partition_rcb.
std::vector<uint32_t> partition_metis(const TetMesh& mesh, uint32_t parts);

// METIS's default bound on a part's size: at most 1.03 times the average (its ufactor of 30, in thousandths).
inline constexpr double kMetisImbalance = 1.03;

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
