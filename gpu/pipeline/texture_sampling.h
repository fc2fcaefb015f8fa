// How llvmpipe (Mesa 22.3, gallivm) samples 2D and 3D textures, emulated bit for bit on the CPU: normalized float
// coordinates, CLAMP_TO_EDGE, no mipmaps, GL_NEAREST or GL_LINEAR, formats f32, u16 and u8 (RGBA or one channel).
// Input: a TextureView, the coordinates, the filter and the CPU's features (LlvmpipeCpu: FMA3 changes the result).
// Output: what the shader's texture() returns. The FMA3 fast path is in texture_sampling_fma.cpp.
// Twins: the texture() calls of shaders/preintegration_table.frag, shaders/classification_table.frag and
// shaders/raycast_fragment.frag (the volume); the GL counterpart is llvmpipe's own sampler.
// Derivation (scope, the AoS and SoA paths, float32 kept in float32): docs/tables.md, "Scope and the two paths".
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#if defined(__x86_64__) || defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <glm/vec4.hpp>
#include "reference/choice.h"

namespace uvr::gpu {

// Storage formats of a texture: RGBA32F (or R32F), RGBA16 unorm (R16), RGBA8 unorm (R8).
enum class TexelFormat { f32, u16, u8 };
inline constexpr Choices<TexelFormat, 3> kTexelFormats{{{TexelFormat::f32, "f32", "32-bit float"},
                                                        {TexelFormat::u16, "u16", "16-bit unorm"},
                                                        {TexelFormat::u8, "u8", "8-bit unorm"}}};
const char* texel_format_name(TexelFormat f);  // "f32", "u16", "u8"
int texel_channel_bytes(TexelFormat f);         // 4, 2, 1

enum class TextureFilter { nearest, linear };

// A texture as llvmpipe holds it: `channels` (1 or 4) interleaved values per texel, x fastest, then y, then z, the
// layout glTexImage3D takes from memory (unpack alignment 1). A 2D texture has depth 1. Does not own the data.
struct TextureView {
    TexelFormat format = TexelFormat::f32;
    int channels = 4;
    int width = 1, height = 1, depth = 1;
    const void* texels = nullptr;
};

// The CPU features llvmpipe's generated sampling code depends on.
struct LlvmpipeCpu {
    // llvm.fmuladd is fused into a single-rounding FMA when Mesa's caps have FMA (llvmpipe_cpu.h: the CPU's FMA3,
    // unless the environment takes it away). Without it the float lerp rounds twice (multiply, then add).
    bool fma = true;
    // The 8-bit lerp of the AoS path. Mesa 22.3 uses pmulhrsw on SSSE3 / AVX2 lanes, which rounds w * delta / 256
    // to nearest (checked bit for bit against OSMesa 22.3.6, docs/tables.md); older Mesa truncated (floored).
    bool lerp8_rounds = true;
};
// The features of the machine this runs on: FMA as Mesa decides it (llvmpipe_cpu.h); lerp8_rounds as Mesa 22.3 does it.
LlvmpipeCpu host_llvmpipe_cpu();

// ---- Building blocks (exposed for the tests and for the other emulated stages) ----

// x86 cvttps2dq: truncation toward zero; NaN and values outside [-2^31, 2^31) give the "integer indefinite"
// 0x80000000. LLVM's fptosi on a <N x float> vector compiles to this instruction on x86.
int32_t x86_cvtt(float x);
// x86 cvtps2dq in the default MXCSR mode: round to nearest, ties to even; NaN and out of range give 0x80000000.
// On x86 it is the scalar instruction itself (cvtss2si), in the rounding mode uvr never changes (its float arithmetic,
// like the JIT code it emulates, assumes round to nearest); elsewhere the same rule in integers (texture_sampling.cpp).
#if defined(__x86_64__) || defined(__SSE__)
#define UVR_X86_CVT_INSTRUCTION 1
inline int32_t x86_cvt_rne(float x)
{
    return _mm_cvtss_si32(_mm_set_ss(x));
}
#else
#define UVR_X86_CVT_INSTRUCTION 0
int32_t x86_cvt_rne(float x);
#endif

// The unorm -> float conversion llvmpipe generates (lp_build_unsigned_norm_to_float for widths <= 24 bits):
// sitofp, then one float multiply by the float nearest 1/(2^n - 1). Not always the float nearest i / (2^n - 1).
float unorm8_to_float(uint8_t v);
float unorm16_to_float(uint16_t v);
// Mesa 22.3's float -> unorm conversion when glTexImage uploads GL_FLOAT data into RGBA8 / RGBA16 (checked against
// OSMesa 22.3.6 on every float in [0, 1] where the candidate formulas differ): 0 below 0 (and NaN), the maximum
// above 1, otherwise the float product x * (2^n - 1) rounded to an integer, ties to even for 8 bits
// (float_to_ubyte, which equals _mesa_float_to_unorm there) and ties away from zero for RGBA16 (util_iround in the
// generated util_format pack function). One-channel R16 rounds ties to even instead; see docs/tables.md.
uint8_t float_to_unorm8(float x);
uint16_t float_to_unorm16(float x);

// The float lerp of lp_build_lerp_simple: v0 + w * (v1 - v0), fused (one rounding) when `fma`.
float lerp_f32(float w, float v0, float v1, bool fma);
// The 8-bit lerp of the AoS path with a prescaled weight w8 in [0, 255] (meaning w8 / 256): v0 plus w8 * (v1 - v0)
// / 256, rounded to nearest (halves up) when `rounds`, floored otherwise; exact integer arithmetic.
uint8_t lerp_unorm8(uint32_t w8, uint8_t v0, uint8_t v1, bool rounds);

// Wrap CLAMP_TO_EDGE of one coordinate, in both paths.
struct LinearTaps {   // SoA float path
    int32_t i0, i1;   // the two texels
    float weight;     // of i1, in [0, 1)
};
struct LinearTaps8 {  // AoS 8-bit path
    int32_t i0, i1;
    uint32_t weight;  // of i1, in 1/256 steps, [0, 255]
};
int32_t wrap_nearest_soa(float coord, int size);
int32_t wrap_nearest_aos(float coord, int size);

/*
 * AoS linear, CLAMP_TO_EDGE (lp_build_sample_image_linear + lp_build_sample_wrap_linear_int, block length 1):
 *   c = coord * float(size << 8)            the size pre-scaled by 256 as an integer, converted exactly; one rounding
 *   v = iround(c)                           lp_build_iround -> cvtps2dq: nearest-even, 0x80000000 on NaN / overflow
 *   v = v - 128                             "subtract 0.5" in 24.8 fixed point; 32-bit wrap-around
 *   i = v >> 8 (arithmetic), w8 = v & 255   floor and 8-bit fraction
 *   lmask = i >= 0, umask = i < size - 1
 *   i0 = lmask ? i : 0;  i0 = umask ? i0 : size - 1
 *   i1 = i0 + (lmask && umask ? 1 : 0)      the second texel's offset adds the stride only inside the texture
 * The weight is not clamped: outside, both taps are the same texel, so any weight returns it. NaN or |c| >= 2^31
 * gives v = 0x7fffff80 after the wrap, i.e. the last texel, also for huge negative coordinates.
 */
inline LinearTaps8 wrap_linear_aos(float coord, int size)
{
    const float c = coord * static_cast<float>(size << 8);
    const int32_t v = static_cast<int32_t>(static_cast<uint32_t>(x86_cvt_rne(c)) - 128u);
    const int32_t i = v >> 8;
    const bool lmask = i >= 0;
    const bool umask = i < size - 1;
    LinearTaps8 taps;
    taps.weight = static_cast<uint32_t>(v) & 0xffu;
    taps.i0 = lmask ? i : 0;
    taps.i0 = umask ? taps.i0 : size - 1;
    taps.i1 = taps.i0 + (lmask && umask ? 1 : 0);
    return taps;
}

/*
 * SoA linear, CLAMP_TO_EDGE (lp_build_sample_wrap_linear, not gather):
 *   c = coord * size                        float multiply, one rounding
 *   c = min(c, size)                        lp_build_min_ext(.., GALLIVM_NAN_RETURN_OTHER_SECOND_NONNAN): NaN -> size
 *   c = c - 0.5                             float subtract: exact for c < 2^23 (results below 0 are clamped next)
 *   c = max(c, 0)                           so c is in [0, size - 0.5]: no NaN, no infinity left
 *   i0 = (int) floor(c), w = c - floor(c)   lp_build_ifloor_fract with roundps floor; the subtraction is exact
 *   i1 = min(i0 + 1, size - 1)              i0 itself never exceeds size - 1 (c <= size - 0.5)
 * Below the first texel centre c clamps to 0 (weight 0), beyond the last one i0 = i1 = size - 1.
 */
inline LinearTaps wrap_linear_soa(float coord, int size)
{
    const float size_f = static_cast<float>(size);
    float c = coord * size_f;
    c = c < size_f ? c : size_f;
    c = c - 0.5f;
    c = c > 0.0f ? c : 0.0f;
    // c is now finite and in [0, size - 0.5] (a NaN took the first select's false side, size; the second clamps below),
    // so truncation is floor, exactly: the same bits as std::floor without its library call (15 % of an emulated HAVS
    // frame's time went to this function). Inline, in the header: it is on every emulated texture lookup.
    const int32_t i0 = static_cast<int32_t>(c);
    const float fl = static_cast<float>(i0);
    LinearTaps taps;
    taps.weight = c - fl;
    taps.i0 = i0;
    taps.i1 = std::min(taps.i0 + 1, int32_t(size - 1));
    return taps;
}

// Which path llvmpipe takes for a format (CLAMP_TO_EDGE, no mipmaps, equal filters): AoS for u8, SoA otherwise.
enum class SamplePath { soa_float, aos_unorm8 };
SamplePath sample_path(TexelFormat f);

// The index of texel (x, y, z) in the layout above (x fastest, then y, then z).
inline std::size_t texel_index(const TextureView& tex, int x, int y, int z)
{
    return (std::size_t(z) * std::size_t(tex.height) + std::size_t(y)) * std::size_t(tex.width) + std::size_t(x);
}

// One texel converted to float as llvmpipe's fetch does (1-channel textures read as (r, 0, 0, 1)).
glm::vec4 texel_fetch(const TextureView& tex, int x, int y, int z = 0);

// The SoA linear filter (f32 and u16 formats), the plain path: channel by channel, as the Mesa comments trace it.
// `coord` holds `dims` (2 or 3) coordinates.
glm::vec4 sample_linear_soa(const TextureView& tex, const float* coord, int dims, const LlvmpipeCpu& cpu);
// Its fast path (texture_sampling_fma.cpp) for 4-channel f32 textures when both the emulated llvmpipe and this host
// fuse (cpu.fma and host_has_fma()): the same bits, four channels at once. sample_2d and sample_3d take it where it
// applies; the test calls both paths.
bool host_has_fma();
// Whether this host runs AVX2 and FMA3 (gpu/pipeline/texture_lanes.h: lookups eight at a time).
bool host_has_avx2();
glm::vec4 sample_linear_f32x4_fma(const TextureView& tex, const float* coord, int dims);
// Whether sample_2d and sample_3d take that fast path for `tex` with `filter` (a caller that samples one texture
// many times may then call it directly: the same bits, without the dispatch per sample).
bool takes_linear_f32x4_fma(const TextureView& tex, TextureFilter filter, const LlvmpipeCpu& cpu);

// texture(sampler2D, vec2(s, t)) and texture(sampler3D, vec3(s, t, r)) with the given filter on both min and mag.
glm::vec4 sample_2d(const TextureView& tex, float s, float t, TextureFilter filter, const LlvmpipeCpu& cpu);
glm::vec4 sample_3d(const TextureView& tex, float s, float t, float r, TextureFilter filter, const LlvmpipeCpu& cpu);

}  // namespace uvr::gpu
