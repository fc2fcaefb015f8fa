// The GL side of HAVS's fragment stage (shaders/havs_fragment.frag): how the stage's inputs are laid out for the
// shader. The per-face constants go to a shader storage buffer as GlHavsFace records (std430, scalar arrays only, so
// the layout is the C++ struct's), the per-frame constants to uniforms.
#pragma once

#include <cstddef>
#include <cstdint>

#include "gpu/gl_context.h"
#include "gpu/havs_fragment.h"
#include "gpu/preintegration_table.h"

namespace uvr::gpu {

// `struct HavsFace` of havs_fragment.frag, byte for byte under std430.
struct GlHavsFace {
    double q[9];      // eye-space positions, x y z per vertex
    double v[6];      // window coordinates, x y per vertex
    double inv_w[3];
    double s[3];
    int32_t fx[3], fy[3];
    float side;
    float pad;
};
static_assert(sizeof(GlHavsFace) == 200 && offsetof(GlHavsFace, v) == 72 && offsetof(GlHavsFace, inv_w) == 120 &&
                  offsetof(GlHavsFace, s) == 144 && offsetof(GlHavsFace, fx) == 168 &&
                  offsetof(GlHavsFace, fy) == 180 && offsetof(GlHavsFace, side) == 192,
              "GlHavsFace must match the std430 layout of HavsFace in shaders/havs_fragment.frag");

GlHavsFace pack_havs_face(const HavsFace& f);

// Uploads `table` as the 3D texture preintegration_table.frag samples (texture unit 4; GL_RGBA32F, GL_RGBA16 or GL_RGBA8 after its
// format, data() as it is), with `filter` for magnification and minification and CLAMP_TO_EDGE. Creates `texture`
// when it is 0. Leaves texture unit 4 active.
void upload_preintegration_table(const GlContext& ctx, const PreintegrationTable& table, TextureFilter filter,
                                 GLuint& texture);

// Sets the havs_* uniforms of a program built from havs_fragment.frag (the program must be in use).
void set_havs_frame_uniforms(const GlContext& ctx, const GlProgram& program, const HavsFrameConstants& fc);

}  // namespace uvr::gpu
