// VICP on a real GL context (issue 6): the GL twin of the emulated driver gpu/vicp.cpp. The CPU stage is the same
// code (vicp_setup: the cell order, ProjectTet's stream, the snapped points, the frame's constants); the GPU runs
// shaders/vicp.vert (the vertex program: each cell's constants, flat) on 12 vertices a cell, rasterizes with back
// faces culled, and runs shaders/vicp.frag (the fragment program: the segment, compositing front to back through
// GL_EXT_shader_framebuffer_fetch) on every fragment. docs/vicp.md.
//
// Resident on the GPU (uploaded once): double positions and normalized scalars per point, and the table. Per frame:
// ProjectTet's stream (VicpCell, 20 bytes a cell), the snapped points (24 bytes a point), the vertex buffer (float
// positions relative to the eye, 12 bytes a point, with the clip stage's vertices) and the clip stage's fans, in
// storage buffers; one glMultiDrawArrays per chunk of the stream (as many cells as GL_MAX_SHADER_STORAGE_BLOCK_SIZE
// holds): runs of whole cells, and the fans of the cells the view cuts in their places (shaders/vicp.vert).
#pragma once

#include <memory>

#include "gpu/gl_context.h"
#include "gpu/vicp.h"

namespace uvr::gpu {

class GlVicpRenderer {
public:
    // Builds the CPU stage and the GL objects on `ctx` (current on this thread). Throws InputError when the context
    // lacks what VICP needs (GL_EXT_shader_framebuffer_fetch, storage buffers in the vertex stage), when the mesh's
    // points exceed one storage block, or with --segment exact (a GPU samples the table).
    GlVicpRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                   const TransferFunction& tf, const VicpOptions& options);
    ~GlVicpRenderer();
    GlVicpRenderer(const GlVicpRenderer&) = delete;
    GlVicpRenderer& operator=(const GlVicpRenderer&) = delete;

    // Renders one frame and reads it back (float32 RGBA, SPEC §2 rows, with the per-pixel diagnostics). Stats:
    // sort_ms and project_ms are CPU time, setup_ms the vertex positions, snapping and uploads,
    // raster_fragment_ms the draws up to glFinish, readback_ms the glReadPixels.
    VicpFrame render(const Camera& camera, int width, int height);

    // Cells drawn per draw call: as many as GL_MAX_SHADER_STORAGE_BLOCK_SIZE bytes of the stream hold, or `n` when
    // set (tests; 0 goes back to the limit).
    std::size_t cells_per_draw() const;
    void set_cells_per_draw(std::size_t n) { cells_per_draw_ = n; }

    const VicpMesh& cpu_stage() const { return mesh_; }

private:
    struct Objects;
    GlContext& ctx_;
    VicpMesh mesh_;
    std::size_t cells_per_draw_ = 0;
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
