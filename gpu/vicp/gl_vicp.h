// VICP on a real GL context: the GL twin of the emulated driver gpu/vicp/vicp.cpp. The CPU stage is the same
// code (vicp_setup: the cell order, ProjectTet's stream, the snapped points, the frame's constants); the GPU runs
// shaders/vicp.vert (the vertex program: each cell's constants, flat) on 12 vertices a cell, rasterizes (no culling),
// and runs shaders/vicp.frag (the fragment program: the segment, compositing front to back through
// GL_EXT_shader_framebuffer_fetch, on front faces only: gl_FrontFacing) on every fragment. docs/vicp.md.
// Twins: emulated driver gpu/vicp/vicp.h; shaders/clip_position.vert, vicp_tet.glsl, vicp_vertex.vert, vicp.vert,
// preintegration_table.frag, vicp_fragment.frag, vicp.frag; GL uniforms gpu/vicp/gl_vicp_fragment.h; harness
// gpu/vicp/gl_vicp_harness.h.
// What is resident and what goes per frame: docs/vicp.md, "What is resident and what is sent per frame".
#pragma once

#include <memory>

#include "gpu/gl/gl_context.h"
#include "gpu/gl/gl_fragment_access.h"
#include "gpu/vicp/vicp.h"

namespace uvr::gpu {

class GlVicpRenderer {
public:
    // Builds the CPU stage and the GL objects on `ctx` (current on this thread). `access`: how the compositing reads
    // its pixel (gl_fragment_access.h). Throws InputError when the context lacks what VICP needs (framebuffer fetch or
    // the image route, storage buffers in the vertex stage), when the mesh's points exceed one storage block, or with
    // --segment exact (a GPU samples the table).
    GlVicpRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                   const TransferFunction& tf, const VicpOptions& options,
                   FramebufferAccess access = FramebufferAccess::automatic);
    ~GlVicpRenderer();

    // The exact and the published programs' sources for a route (what the constructor compiles; tests compile every
    // route's variant offline).
    struct VicpProgramSources {
        GlShaderSource exact_vertex, exact_fragment, published_vertex, published_fragment;
    };
    static VicpProgramSources program_sources(const FragmentAccessPath& path);
    GlVicpRenderer(const GlVicpRenderer&) = delete;
    GlVicpRenderer& operator=(const GlVicpRenderer&) = delete;

    // Renders one frame and reads it back (float32 RGBA, docs/spec.md §2 rows, with the per-pixel diagnostics). Stats:
    // sort_ms and project_ms are CPU time, setup_ms the vertex positions, snapping and uploads,
    // raster_fragment_ms the draws up to glFinish, readback_ms the glReadPixels.
    VicpFrame render(const Camera& camera, int width, int height);

    // Cells drawn per draw call: as many as GL_MAX_SHADER_STORAGE_BLOCK_SIZE bytes of the stream hold, or `n` when
    // set (tests; 0 goes back to the limit).
    std::size_t cells_per_draw() const;
    void set_cells_per_draw(std::size_t n) { cells_per_draw_ = n; }

    const VicpMesh& cpu_stage() const { return mesh_; }

    // --send (--interpolation gpu): the faces that make fragments (covered, the default) or all four of every cell, as
    // ProjectTet as published sends them (vicp_sent_faces). The frame's bits are the same.
    void set_submission(TriangleSubmission s) { submission_ = s; }

    // Cells a published draw sends (--interpolation gpu): 16,384 cells are 8.6 MB of records (528 bytes a cell), which
    // the GPU holds whatever the mesh's size.
    static constexpr std::size_t kPublishedCellsPerDraw = 16384;

private:
    struct Objects;
    // The frame's stages (render): the buffers, state and uniforms; the draws; the read-back.
    void prepare_frame(const VicpFrameSetup& fs, const Camera& cam, int width, int height);
    void draw_cells(const VicpFrameSetup& fs, VicpStats& st);
    void read_frame(int width, int height, VicpFrame& out);
    void draw_exact(const VicpFrameSetup& fs, std::size_t begin, std::size_t end, VicpStats& st);
    void draw_published(const VicpFrameSetup& fs, std::size_t begin, std::size_t end, VicpStats& st);
    GlContext& ctx_;
    VicpMesh mesh_;
    std::size_t cells_per_draw_ = 0;
    TriangleSubmission submission_ = TriangleSubmission::covered;
    FragmentAccessPath access_;  // framebuffer fetch, or the image route (gl_fragment_access.h)
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
