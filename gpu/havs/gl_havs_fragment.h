// The GL side of HAVS's fragment stage (shaders/havs_fragment.frag): how the stage's inputs are laid out for the
// shader. The per-face constants go to a buffer texture of RGBA32UI texels as GlHavsFace records (kHavsFaceTexels
// texels a face, read with texelFetch: the bits as uploaded), the per-frame constants to uniforms. Why a buffer
// texture and not a storage buffer: havs_fragment.frag, at havs_face_records.
// Twins: shaders/havs_fragment.frag (havs_face, the havs_* uniforms); emulated stage gpu/havs/havs_fragment.h;
// harness gpu/havs/gl_havs_harness.h.
#pragma once

#include <cstddef>
#include <cstdint>

#include "gpu/gl/gl_context.h"
#include "gpu/havs/havs_fragment.h"

namespace uvr::gpu {

// One face record, as havs_face() of havs_fragment.frag reads its words: doubles low word first (little-endian, as
// x86 and every GL driver this runs on store them).
struct GlHavsFace {
    double v[6];      // window coordinates, x y per vertex
    float q[9];       // eye-space positions, x y z per vertex
    float inv_w[3];
    float s[3];
    int32_t fx[3], fy[3];
    float side;
    float pad[2];     // to a whole texel
};
inline constexpr int kHavsFaceTexels = 9;  // havs_face_texels of havs_fragment.frag
inline constexpr int kHavsFaceUnit = 5;    // the texture unit of the records (binding = 5 there)
// The word offsets havs_face() uses: v 0, q 12, inv_w 21, s 24, fx 27, fy 30, side 33.
static_assert(sizeof(GlHavsFace) == 16 * kHavsFaceTexels && offsetof(GlHavsFace, q) == 4 * 12 &&
                  offsetof(GlHavsFace, inv_w) == 4 * 21 && offsetof(GlHavsFace, s) == 4 * 24 &&
                  offsetof(GlHavsFace, fx) == 4 * 27 && offsetof(GlHavsFace, fy) == 4 * 30 &&
                  offsetof(GlHavsFace, side) == 4 * 33,
              "GlHavsFace must match the words havs_face() reads in shaders/havs_fragment.frag");

GlHavsFace pack_havs_face(const HavsFace& f);

// Points the buffer texture `texture` (on texture unit kHavsFaceUnit) at `buffer`'s records as RGBA32UI texels.
// Leaves that unit active.
void bind_havs_face_records(const GlContext& ctx, GLuint texture, GLuint buffer);

// Sets the havs_* uniforms of a program built from havs_fragment.frag (the program must be in use).
void set_havs_frame_uniforms(const GlContext& ctx, const GlProgram& program, const HavsFrameConstants& fc);

}  // namespace uvr::gpu
