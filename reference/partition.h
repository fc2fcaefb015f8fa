// Splitting a tetrahedral mesh into parts, as data-parallel renderers split their data over processes
// (docs/distributed.md).
#pragma once

#include <cstdint>
#include <vector>

#include "reference/camera.h"
#include "reference/choice.h"
#include "reference/mesh.h"
#include "reference/ray_integrator.h"
#include "reference/topology.h"

namespace uvr {

// How a mesh is split: `uvr partition --method`.
enum class PartitionMethod { rcb, metis };
inline constexpr Choices<PartitionMethod, 2> kPartitionMethods{{
    {PartitionMethod::rcb, "rcb", "recursive coordinate bisection of the cells' centroids: parts in boxes"},
    {PartitionMethod::metis, "metis",
     "METIS's k-way partition of the cell graph: balanced, fewest cut faces, not convex"},
}};

// What the parts balance: `uvr partition --balance`.
enum class PartitionBalance { cells, view };
inline constexpr Choices<PartitionBalance, 2> kPartitionBalances{{
    {PartitionBalance::cells, "cells", "equal numbers of tetrahedra"},
    {PartitionBalance::view, "view",
     "equal work for one view (--camera or --view, --size): the steps the reference's rays take through each part "
     "(rcb: steps plus a share per cell; metis: both the cells and the steps)"},
}};

// Per tetrahedron, its part in [0, parts), by `method` (the functions below). With `view_steps` (one per tetrahedron,
// view_steps()) the parts balance a view's work: rcb weighs each tetrahedron by its steps plus kCellWorkInSteps,
// METIS balances the cells and the steps together.
std::vector<uint32_t> partition_mesh(const TetMesh& mesh, uint32_t parts, PartitionMethod method,
                                     const std::vector<uint64_t>* view_steps = nullptr);

// Per tetrahedron, its part in [0, parts): recursive coordinate bisection of the tetrahedra's centroids. Each step
// splits a set of cells at the plane normal to the longest side of its centroids' bounding box (the lowest axis on a
// tie), into two sets sized in proportion to the parts each receives (floor(n/2) and ceil(n/2) of n), ordering equal
// coordinates by cell index. Parts differ in size by at most one cell per level, and the result is the same on every
// run and machine. With `weights`, the two sets' shares are of the summed weights instead of the counts (the cut
// nearest the share, each set keeping at least one cell per part it receives). Throws InputError naming mesh.source
// unless 1 <= parts <= number of tetrahedra.
std::vector<uint32_t> partition_rcb(const TetMesh& mesh, uint32_t parts,
                                    const std::vector<uint64_t>* weights = nullptr);

// Per tetrahedron, its part in [0, parts): METIS_PartGraphKway (Debian's libmetis) on the graph whose vertices are the
// tetrahedra and whose edges are the internal faces (build_topology's, coincident points welded), with METIS's
// default load imbalance (kMetisImbalance) and a fixed seed, so the result is the same on every run. With `steps`, a
// second constraint (METIS's multi-constraint partitioning): each part also within the bound of the average steps.
// The parts are balanced and cut few faces, but are not boxes. Same refusals as partition_rcb.
std::vector<uint32_t> partition_metis(const TetMesh& mesh, uint32_t parts,
                                      const std::vector<uint64_t>* steps = nullptr);

// rcb's weight of a tetrahedron for a view is its steps plus this: what else a tetrahedron costs its rank, in steps of
// the walk. The ranks read, build and trace without waiting for each other (docs/distributed.md), so a part's work is
// its read, build and trace together: on Blunt Fin's 2 rcb parts for (-40, 70) at 512^2, on this project's 2-core test
// machine, reading and building cost about 0.65 us a tetrahedron and a step about 0.05 us (a ratio of 13), and the part
// of more, smaller cells walks slower (its cells fill more of the caches); of 17, 20 and 24, 17 and 20 balanced the
// ranks' read-to-image time best (docs/distributed.md, "Balanced for a view").
inline constexpr uint64_t kCellWorkInSteps = 20;

// Per tetrahedron, the steps the rays of a width x height image of `camera` take through it: its ray work in that view
// (RayIntegrator::integrate_counting, one ray per pixel, as the reference renders).
std::vector<uint64_t> view_steps(const RayIntegrator& integrator, std::size_t tetrahedra, const Camera& camera,
                                 int width, int height);

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
