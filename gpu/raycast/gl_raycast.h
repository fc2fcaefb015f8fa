// The ray caster on GL (Krüger and Westermann): the volume as a one-channel 3D texture, the classification (or
// pre-integrated) table; the published three passes (--interpolation gpu: the box's front and back faces into RGBA32F
// targets, then the box again with the march) or one full-screen triangle (exact); colour and samples per pixel in a
// float framebuffer. The CPU stages (RaycastVolume, raycast_box_frame) and the frame's constants are the
// emulation's, so both march the same texels with the same uniforms. docs/raycast.md.
// Twins: emulated driver gpu/raycast/raycast.h; shaders/raycast_box.{vert,frag}, fullscreen.vert,
// classification_table.frag, preintegration_table.frag, raycast_fragment.frag, raycast.frag; GL uniforms here
// (set_raycast_frame_uniforms); harness gpu/raycast/gl_raycast_harness.h.
#pragma once

#include <memory>

#include "gpu/gl/gl_context.h"
#include "gpu/raycast/raycast.h"

namespace uvr::gpu {

// The fragment program's uniforms (RaycastFrameConstants) on `program`, which must be in use.
void set_raycast_frame_uniforms(const GlContext& ctx, const GlProgram& program, const RaycastFrameConstants& fc);

// The textures of RaycastVolume: the volume at unit 0 (R8 / R16 / R32F, GL_LINEAR, CLAMP_TO_EDGE) and the
// classification table at unit 1 or the pre-integrated table at unit 4. `textures` holds the names made.
void upload_raycast_textures(const GlContext& ctx, const RaycastVolume& rv, GLuint textures[3]);

class GlRaycastRenderer {
public:
    // Throws InputError when the context cannot hold the volume texture or --segment exact is asked for.
    GlRaycastRenderer(GlContext& ctx, const Volume& volume, const TransferFunction& tf, const RaycastOptions& options);
    ~GlRaycastRenderer();

    // The march's program (after the published box passes, or on a full-screen triangle) and the box passes' program,
    // with the light or without (what the constructor compiles; tests compile them offline).
    struct RaycastProgramSources {
        GlShaderSource march_vertex, march_fragment, box_vertex, box_fragment;
    };
    static RaycastProgramSources program_sources(bool published, bool light);
    GlRaycastRenderer(const GlRaycastRenderer&) = delete;
    GlRaycastRenderer& operator=(const GlRaycastRenderer&) = delete;

    RaycastFrame render(const Camera& camera, int width, int height);
    const RaycastVolume& cpu_stage() const { return volume_; }

private:
    void draw_box_passes(const RaycastBoxFrame& bf, int width, int height);  // the published first two passes

    GlContext& ctx_;
    RaycastVolume volume_;
    struct Objects;
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
