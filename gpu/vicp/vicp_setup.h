// VICP's CPU stage (Moreland's dissertation, VICP-ProjectTet), shared by the emulated driver (gpu/vicp/vicp.cpp) and
// the GL driver (gpu/vicp/gl_vicp.cpp), so that both draw the same cells in the same order: per mesh (VicpMesh) what
// the GPU keeps resident, view independent, and each cell's orientation; per frame (setup_vicp_frame) the cell order,
// ProjectTet's stream of oriented cells, the snapped points, the window coordinates, the frame's constants, the vertex
// buffer and the clip stage's fans (gpu/vicp/vicp_clip.h). Twins: none (CPU stage); gpu/vicp/gl_vicp.h uploads its
// outputs to the storage buffers shaders/vicp.vert reads. Derivation: docs/vicp.md, "ProjectTet" and "What is sent".
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "gpu/pipeline/drawn_mesh.h"
#include "gpu/pipeline/exact_coverage.h"
#include "gpu/pipeline/segment.h"
#include "gpu/vicp/vicp_clip.h"
#include "gpu/vicp/vicp_fragment.h"
#include "gpu/vicp/vicp_order.h"
#include "gpu/vicp/vicp_published_vertex.h"

namespace uvr::gpu {

// One cell as ProjectTet sends it: its points, positively oriented, and which of its faces (bit i: the face opposite
// point i) lie on the mesh's boundary.
struct VicpCell {
    Tet v;
    uint32_t boundary = 0;
};

struct VicpOptions {
    CellOrder order = CellOrder::mpvonc;
    SegmentMode segment = SegmentMode::table;
    float threshold = 1.0f;  // the opacity kill; VICP composites every cell by default (the published program has no kill)
    int table_size = 128;
    TexelFormat table_format = TexelFormat::f32;
    double table_max_length = 0.0;  // 0: the mesh's longest edge
    std::optional<Range> scalar_range;  // empty: the drawn field's own (as HavsOptions::scalar_range)
    TextureFilter filter = TextureFilter::linear;
    Coverage coverage = Coverage::gpu;  // --coverage exact: a cell covers the pixels whose rays cross it (emulation)
    // gpu: the published programs (docs/vicp.md "The published pipeline"; the cells a view cuts are drawn by the exact
    // variant); exact: the per-cell ray-plane variant.
    InterpolationMode interpolation = InterpolationMode::gpu;
};

class VicpMesh {
public:
    // Throws InputError when an option is out of range.
    VicpMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
             const VicpOptions& options);

    const TetMesh& mesh() const { return mesh_; }  // the mesh drawn (gpu/pipeline/drawn_mesh.h)
    const MeshTopology& topology() const { return topo_; }
    const VicpOptions& options() const { return options_; }  // table_max_length filled in
    const SegmentIntegrator& integrator() const { return integrator_; }
    const Range& range() const { return range_; }
    const glm::dvec3& origin() const { return origin_; }
    const std::vector<glm::dvec3>& points_d() const { return points_d_; }   // relative to origin(), double
    const std::vector<double>& scalars_n() const { return scalar_n_; }      // normalized to [0, 1]
    const PreintegrationTable* table() const { return table_.get(); }      // null with --segment exact
    double table_ms() const { return table_ms_; }
    std::size_t drawn_cells() const { return drawn_; }

    // Tetrahedron t as the vertex program receives it: its points positively oriented (det > 0 in
    // vicp_tet_constants), or false when it is not drawn (det == 0: a flat cell).
    bool oriented(uint32_t t, VicpCell& out) const;
    // The vertex program's constants of an oriented tetrahedron: its shape from the frame's snapped points, its field
    // from the mesh's.
    VicpTet constants(const VicpCell& cell, const std::vector<glm::dvec3>& snapped) const;
    // ProjectTet's 12 records of an oriented cell (--interpolation gpu), face f's vertex j at 3 f + j in kVicpCorner's
    // order: positions from the frame's vertex buffer (relative to the eye), planes and gradient from the mesh's
    // points in double, rounded once.
    void published_records(const VicpCell& cell, const std::vector<glm::vec3>& points_f,
                           VicpPublishedVertex out[12]) const;

private:
    DrawnMesh drawn_mesh_;
    const TetMesh& mesh_;
    const MeshTopology& topo_;
    VicpOptions options_;
    SegmentIntegrator integrator_;
    Range range_;
    glm::dvec3 origin_{0.0};
    std::vector<glm::dvec3> points_d_;
    std::vector<double> scalar_n_;
    std::vector<uint8_t> orientation_;  // per cell: 0 not drawn, 1 as it is, 2 vertices 2 and 3 swapped
    std::vector<uint8_t> boundary_;     // per cell: bit i, the face opposite point i is a boundary face
    std::size_t drawn_ = 0;
    std::shared_ptr<const PreintegrationTable> table_;
    double table_ms_ = 0.0;
};

struct VicpFrameSetup {
    Camera camera;
    int width = 0, height = 0;
    ViewSetup view;
    VicpFrameConstants constants;
    // The frame's vertex buffer: the mesh's points, then the vertices the clip stage made, relative to the eye in
    // float (gl_Position), and what the rasterizer receives of each.
    std::vector<glm::vec3> points_f;
    std::vector<WindowCoord> win;
    // Per mesh point, relative to the mesh's centre in double: where snapping put it (the window position the
    // rasterizer snapped it to, at its own depth; vicp_fragment.h, "Snapping"), or the point itself where the GPU's
    // frustum test would clip it (it is never rasterized).
    std::vector<glm::dvec3> snapped;
    std::vector<uint32_t> order;   // every cell, front to back
    std::vector<VicpCell> stream;  // ProjectTet's output: the drawn cells, oriented, in order
    // The cells of the stream the view cuts (by slot), drawn as fans instead of their four faces
    // (gpu/vicp/vicp_clip.h), and the fans' triangles: four values each, its three vertices (indices into points_f) and
    // its cell's slot.
    std::vector<VicpCut> cuts;
    std::vector<uint32_t> fans;
    CellOrderStats order_stats;
    // The clip stage's counts: cells drawn through it, cells outside the view, near-plane sections drawn, and drawn
    // triangles with a vertex the GPU's frustum test would clip (0 unless the clip stage's margins failed).
    uint64_t clipped_cells = 0, culled_cells = 0, near_sections = 0, gpu_clipped = 0;
    double sort_ms = 0.0, project_ms = 0.0, vertex_ms = 0.0;

    std::size_t fan_triangles() const { return fans.size() / 4; }
};

// The faces of a stream cell ProjectTet sends under --interpolation gpu (bit f: face f, kVicpCorner's order): with
// covered, those llvmpipe's setup finds front-facing (its fixed-point area, the emulation's Facing) that cover a pixel,
// the only ones that make fragments; with all, the four, as the published ProjectTet does (the fragment program drops
// back faces on gl_FrontFacing). All four too when the GPU would clip a vertex of the frame (fs.gpu_clipped), as HAVS
// does.
unsigned vicp_sent_faces(const VicpFrameSetup& fs, const VicpCell& cell, TriangleSubmission submission);

// The view the published vertex program takes (--interpolation gpu): the camera's projection and viewing direction.
VicpPublishedView vicp_published_view(const Camera& camera);

// The frame's CPU stage. A view that cuts the mesh goes through the clip stage (gpu/vicp/vicp_clip.h).
VicpFrameSetup setup_vicp_frame(const VicpMesh& vm, const Camera& camera, int width, int height);

// What the GPU holds per cell: resident (positions in double and scalars, per point; amortized over cells) and sent
// per frame: with --interpolation exact ProjectTet's stream, 20 bytes a cell, the snapped points in double, 24 bytes a
// point, and the vertex buffer, 12 bytes a point; with gpu the published records, 132 bytes a sent face (`sent_faces`
// of the frame: vicp_sent_faces). The cells a view cuts (their fans, and with gpu the exact program's per-frame
// buffers) are not counted.
inline constexpr std::size_t kPublishedBytesSentPerFace = 33 * sizeof(float);
inline constexpr std::size_t kPublishedBytesSentPerCell =
    4 * kPublishedBytesSentPerFace;  // Moreland's dissertation's count, 528
double vicp_sent_bytes_per_cell(const VicpMesh& vm, uint64_t sent_faces);
double vicp_resident_bytes_per_cell(const VicpMesh& vm);

}  // namespace uvr::gpu
