// The pre-integrated table's upload: the 3D texture shaders/preintegration_table.frag samples (texture unit 4),
// shared by the GL drivers of HAVS, VICP and the ray caster. Emulated lookup: gpu/pipeline/preintegration_table.h.
// Twins: shaders/preintegration_table.frag reads this texture; the HAVS and VICP stage harnesses upload through it too.
#pragma once

#include "gpu/gl/gl_context.h"
#include "gpu/pipeline/preintegration_table.h"

namespace uvr::gpu {

// Uploads `table` as the 3D texture preintegration_table.frag samples (texture unit 4; GL_RGBA32F, GL_RGBA16 or GL_RGBA8 after its
// format, data() as it is), with `filter` for magnification and minification and CLAMP_TO_EDGE. Creates `texture`
// when it is 0. Leaves texture unit 4 active.
void upload_preintegration_table(const GlContext& ctx, const PreintegrationTable& table, TextureFilter filter,
                                 GLuint& texture);

}  // namespace uvr::gpu
