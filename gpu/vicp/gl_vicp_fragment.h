// The GL side of VICP's fragment stage (shaders/vicp_fragment.frag): the per-frame constants as uniforms. The
// per-tetrahedron constants reach it as flat varyings from the vertex program (shaders/vicp.vert) in the renderer,
// from a storage buffer in the stage harness (gpu/vicp/gl_vicp_harness.h).
// Twins: shaders/vicp_fragment.frag; emulated stage gpu/vicp/vicp_fragment.h; harness gpu/vicp/gl_vicp_harness.h.
#pragma once

#include "gpu/gl/gl_context.h"
#include "gpu/vicp/vicp_fragment.h"

namespace uvr::gpu {

// Sets the vicp_* uniforms of a program built from vicp_fragment.frag (the program must be in use).
void set_vicp_frame_uniforms(const GlContext& ctx, const GlProgram& program, const VicpFrameConstants& fc);

}  // namespace uvr::gpu
