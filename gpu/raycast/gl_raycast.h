// The ray caster on GL (issue 7): the volume as a one-channel 3D texture, the classification (or pre-integrated)
// table, one full-screen triangle whose fragment program is shaders/raycast_fragment.frag (+ raycast.frag), colour and
// samples per pixel in a float framebuffer. The CPU stage (RaycastVolume) and the frame's constants are the
// emulation's (gpu/raycast/raycast_setup.h), so both march the same texels with the same uniforms. docs/raycast.md.
// Twins: emulated driver gpu/raycast/raycast.h; shaders/fullscreen.vert, classification_table.frag,
// preintegration_table.frag, raycast_fragment.frag, raycast.frag; GL uniforms here (set_raycast_frame_uniforms);
// harness gpu/raycast/gl_raycast_harness.h.
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
    GlRaycastRenderer(const GlRaycastRenderer&) = delete;
    GlRaycastRenderer& operator=(const GlRaycastRenderer&) = delete;

    RaycastFrame render(const Camera& camera, int width, int height);
    const RaycastVolume& cpu_stage() const { return volume_; }

private:
    GlContext& ctx_;
    RaycastVolume volume_;
    struct Objects;
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
