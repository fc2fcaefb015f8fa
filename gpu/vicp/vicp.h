// View-Independent Cell Projection (Weiler, Kraus, Ertl 2003; Moreland's dissertation) emulated on the CPU as a GPU
// runs it: the cells ordered on the CPU (vicp_order), ProjectTet's stream (vicp_setup) with the cells the view cuts
// clipped (vicp_clip), each cell's four faces through the vertex stage (vicp_vertex), rasterized with llvmpipe's rules
// and back faces culled (rasterize), each fragment through the fragment program (vicp_fragment). docs/vicp.md. Twins:
// shaders/vicp.vert and shaders/vicp.frag (the draw's mains); GL driver gpu/vicp/gl_vicp.h; GL uniforms
// gpu/vicp/gl_vicp_fragment.h; harness gpu/vicp/gl_vicp_harness.h.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/pipeline/tiles.h"
#include "gpu/vicp/vicp_setup.h"
#include "reference/image.h"

namespace uvr::gpu {

struct VicpStats {
    uint64_t cells = 0, drawn_cells = 0;
    uint64_t fragments = 0, ordering_errors = 0;
    uint32_t max_fragments = 0;  // most fragments on one pixel
    CellOrderStats order;
    double table_ms = 0, sort_ms = 0, project_ms = 0, setup_ms = 0, raster_fragment_ms = 0, readback_ms = 0;
    uint32_t draws = 0;  // the GL backend's draw calls
    // The clip stage (gpu/vicp/vicp_clip.h): cells drawn through it, cells outside the view, near-plane sections, fan
    // triangles, and triangles with a vertex the GPU's frustum test would clip (0 unless its margins failed).
    uint64_t clipped_cells = 0, culled_cells = 0, near_sections = 0, fan_triangles = 0, gpu_clipped = 0;
    // --interpolation gpu (emulation): fragments whose smallest positive distance picked another face than the exact
    // crossing's exit (the published wrong exits, docs/vicp.md "The published pipeline").
    uint64_t wrong_exits = 0;
    // --interpolation gpu: the faces ProjectTet sends (vicp_sent_faces; the emulation counts the GL driver's default,
    // covered).
    uint64_t sent_faces = 0;
    double max_length_error = 0.0;  // the largest |interpolated - exact| segment length of a fragment (world units)
};

struct VicpFrame {
    Image image;
    // Per pixel, docs/spec.md §2 order (row 0 at the top): fragments, ordering errors; with the published interpolation
    // (emulation), wrong exits and the largest |interpolated - exact| segment length of the pixel's fragments.
    std::vector<uint32_t> fragments, ordering_errors, wrong_exits;
    std::vector<float> length_error;
    VicpStats stats;
};

// The end of a frame, for both backends: colour and diagnostics (GL rows, from the bottom) into `out` (image rows (row
// 0 on top)).
void store_vicp_frame(const std::vector<glm::vec4>& colour, const std::vector<VicpDiagnostics>& diagnostics, int width,
                      int height, VicpFrame& out);

// The CPU stage's statistics of the frame `fs` of `vm` (cells, order, times, the clip stage's counts) into `st`, for
// both backends.
void store_setup_stats(const VicpMesh& vm, const VicpFrameSetup& fs, VicpStats& st);

class VicpRenderer {
public:
    // `diagnostics`: the per-pixel counts (fragments, ordering errors) and, with the published interpolation, the
    // wrong exits and length errors against the exact segment, which cost a frame about half its time more; the image
    // is the same without them (uvr bench times frames without, as the GL driver is timed).
    VicpRenderer(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                 const VicpOptions& options, bool diagnostics = true);
    VicpFrame render(const Camera& camera, int width, int height) const;
    const VicpMesh& cpu_stage() const { return mesh_; }

private:
    VicpMesh mesh_;
    bool diagnostics_ = true;

    template <class Shade>  // SegmentShader, or the table's TableSegmentShader
    void composite_published(const VicpFrameConstants& fc, const VicpFrameSetup& fs, uint32_t slot,
                             const VicpPublishedView& view, const std::vector<SetupVertex>& setup, const TileRect& tile,
                             ViewportArithmetic arith, const Shade& shade, int width, std::vector<glm::vec4>& fb,
                             std::vector<VicpDiagnostics>& diag, std::vector<uint32_t>& wrong_exits,
                             std::vector<float>& length_error) const;
    void composite_exact_coverage(const VicpFrameConstants& fc, const VicpFrameSetup& fs, uint32_t slot, bool cut,
                                  const TileRect& tile, const SegmentShader& shade, int width, std::vector<glm::vec4>& fb,
                                  std::vector<VicpDiagnostics>& diag) const;
};

}  // namespace uvr::gpu
