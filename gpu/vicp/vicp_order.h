// VICP's cell visibility orders: the tetrahedra front to back, computed on the CPU every frame. centroid:
// each cell's centroid depth, radix-sorted as HAVS's faces are (gpu/pipeline/face_sort.h); approximate. mpvonc: MPVO
// with XMPVO's relations along the rays for non-convex meshes, topologically sorted; exact along every pixel centre's
// ray unless the relations have a cycle, whose breaks are counted. Input: the mesh, its topology, the frame
// (CellOrderFrame). Output: the order, front to back, and CellOrderStats.
// Twins: none (CPU stage).
// Derivation: docs/vicp.md, "The two orders".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "gpu/pipeline/rasterize.h"
#include "gpu/vicp/vicp_clip.h"
#include "gpu/vicp/vicp_fragment.h"
#include "reference/camera.h"
#include "reference/mesh.h"
#include "reference/topology.h"
#include "reference/choice.h"

namespace uvr::gpu {

enum class CellOrder { centroid, mpvonc };
inline constexpr Choices<CellOrder, 2> kCellOrders{
    {{CellOrder::centroid, "centroid", "cells by the depth of their centroids"},
     {CellOrder::mpvonc, "mpvonc", "MPVO with XMPVO's relations: exact along each pixel's ray but for cycles"}}};
const char* cell_order_name(CellOrder o);             // "centroid", "mpvonc"
CellOrder parse_cell_order(const std::string& name);  // throws InputError for anything else

struct CellOrderStats {
    uint64_t face_dependencies = 0;  // internal faces that order their two cells
    uint64_t ray_dependencies = 0;   // distinct exit-to-entry relations found along the pixels' rays (XMPVO)
    uint64_t cycle_breaks = 0;       // cells drawn out of the dependency order because the sort stalled on a cycle
};

// The cells sorted by centroid depth along `view_dir`, front to back. `points` relative to any origin, `eye` in the
// same frame.
void centroid_cell_order(const std::vector<glm::vec3>& points, const std::vector<Tet>& tets, const glm::vec3& eye,
                         const glm::vec3& view_dir, std::vector<uint32_t>& order);

// Everything MPVONC needs of the frame: the camera, the pixels' rays (fc) and where the rasterizer puts every point
// (`win`, the vertex stage's output), so that the boundary faces are projected exactly as the cells' faces are.
struct CellOrderFrame {
    const Camera* camera = nullptr;
    glm::dvec3 origin{0.0};  // the frame the rays of fc are in (the mesh's centre)
    const VicpFrameConstants* fc = nullptr;
    const std::vector<WindowCoord>* win = nullptr;
    // Where the fragment program has the interior faces (the snapped points, relative to origin; vicp_fragment.h,
    // "Snapping"): each internal face orders its cells by the side of that plane the eye is on, so that the order
    // agrees with the segments drawn. Null: the mesh's own points.
    const std::vector<glm::dvec3>* snapped = nullptr;
    // The frame's clip stage: a boundary face with a point outside its planes is projected as the fan of its clipped
    // polygon, as the cells' faces are drawn (gpu/vicp/vicp_clip.h). Null: every face is projected whole.
    const VicpClipper* clipper = nullptr;
    int width = 0, height = 0;
};

// MPVONC, front to back. `centroid` is the centroid order of the same frame (the cycle breaker's priority).
void mpvonc_cell_order(const TetMesh& mesh, const MeshTopology& topo, const CellOrderFrame& frame,
                       const std::vector<uint32_t>& centroid, std::vector<uint32_t>& order, CellOrderStats& stats);

// Two boundary crossings of one pixel's ray closer than this fraction of their distance are one place: an exit face
// and an entry face that coincide (the two sides of an O-grid's seam, whose points are bit-identical) differ only by
// the rounding of two plane intersections, ~1e-15 relative; distinct surfaces that close are below anything a
// float32 image resolves.
inline constexpr double kCoincidentCrossing = 1e-9;

}  // namespace uvr::gpu
