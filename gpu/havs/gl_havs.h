// HAVS on a real GL context: the GL twin of the emulated driver gpu/havs/havs.cpp. The CPU stage is the same
// code (havs_setup: the sorted faces, the vertex stage's double geometry, the per-face constants); the GPU runs
// shaders/havs_vertex.vert, rasterizes, and runs shaders/havs_fragment.frag + shaders/havs.frag on every fragment, the
// k-buffer living in RGBA32F colour attachments read and written with GL_EXT_shader_framebuffer_fetch; then the flush
// (k runs of the program a pixel, in one full-screen pass). docs/gl-backend.md.
// Per frame: the faces go in sorted order, in consecutive chunks, one draw each: a chunk's vertex indices to an element
// buffer and its constants (GlHavsFace, in the same order) to a buffer texture indexed by gl_PrimitiveID, just
// before glDrawElements draws it. GL keeps primitive order across draws.
// Twins: emulated driver gpu/havs/havs.h; shaders/clip_position.vert, havs_vertex.vert, havs_fragment.frag, havs.frag;
// GL uniforms gpu/havs/gl_havs_fragment.h; harness gpu/havs/gl_havs_harness.h.
#pragma once

#include <memory>

#include "gpu/gl/gl_context.h"
#include "gpu/gl/gl_fragment_access.h"
#include "gpu/havs/havs.h"

namespace uvr::gpu {

class GlHavsRenderer {
public:
    // Builds the CPU stage and the GL objects on `ctx` (current on this thread). With `diagnostics`, one more colour
    // attachment carries the per-pixel diagnostics (HavsFrame's fragments, max_held, ordering_errors); without, the
    // frame's diagnostic vectors stay empty and one more attachment is free for entries. Throws InputError when the
    // context lacks what HAVS needs (framebuffer fetch or the image route: gl_fragment_access.h), when k is outside
    // 1 .. max_k, or with --segment exact (a GPU samples the table; the exact integral is the emulation's).
    GlHavsRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                   const TransferFunction& tf, const HavsOptions& options, bool diagnostics = true,
                   FramebufferAccess access = FramebufferAccess::automatic);
    ~GlHavsRenderer();

    // The geometry and flush programs' sources for k, the diagnostics, the entries' encoding, the interpolation and
    // the route (what the constructor compiles; tests compile every route's variant offline).
    struct HavsProgramSources {
        GlShaderSource geometry_vertex, geometry_fragment, flush_vertex, flush_fragment;
    };
    static HavsProgramSources program_sources(int k, bool diagnostics, bool paper_entries, bool published,
                                              const FragmentAccessPath& path);
    GlHavsRenderer(const GlHavsRenderer&) = delete;
    GlHavsRenderer& operator=(const GlHavsRenderer&) = delete;

    // Renders one frame and reads it back (float32 RGBA, docs/spec.md §2 rows). Stats: sort_ms and setup_ms are CPU
    // time (setup includes building and uploading the per-face constants), raster_fragment_ms the geometry pass and
    // flush_ms the flush passes, each up to glFinish, readback_ms the glReadPixels.
    HavsFrame render(const Camera& camera, int width, int height);

    // The largest k the context's draw buffers allow: one attachment for the colour, one for the diagnostics when
    // asked for, two entries in each of the others.
    static int max_k(const GlInfo& info, bool diagnostics);

    // Faces drawn per draw call: as many as 16 MiB of face constants hold (116,508 faces; less where
    // GL_MAX_TEXTURE_BUFFER_SIZE texels hold fewer), or `n` when set (tests; 0 goes back to the limit).
    std::size_t faces_per_draw() const;
    void set_faces_per_draw(std::size_t n) { faces_per_draw_ = n; }
    // Which triangles are sent (havs_sent_triangles): by default those that cover a pixel.
    void set_submission(TriangleSubmission s) { submission_ = s; }

    const HavsMesh& cpu_stage() const { return mesh_; }
    const GlContext& context() const { return ctx_; }

private:
    struct Objects;
    // The frame's stages (render): the framebuffer cleared and the geometry program's uniforms; the geometry pass;
    // the flush pass; the read-back.
    void prepare_frame(const HavsFrameSetup& fs, int width, int height);
    void geometry_pass(const HavsFrameSetup& fs, HavsStats& st);
    void flush_pass(const HavsFrameSetup& fs, HavsStats& st);
    void read_frame(int width, int height, HavsFrame& out);
    void use_program(const GlProgram& p, const HavsFrameSetup& fs);
    GlContext& ctx_;
    HavsMesh mesh_;
    bool diagnostics_;
    bool images_ = false;  // the k-buffer through image load/store (gl_fragment_access.h)
    std::size_t faces_per_draw_ = 0;
    TriangleSubmission submission_ = TriangleSubmission::covered;
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
