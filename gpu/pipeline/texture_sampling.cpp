// llvmpipe's texture sampling, step by step. The Mesa functions named in the comments are those of
// src/gallium/auxiliary/gallivm/ (lp_bld_sample_soa.c, lp_bld_sample_aos.c, lp_bld_arit.c, lp_bld_conv.c,
// lp_bld_format_soa.c); docs/tables.md lists what was checked against OSMesa and what stays open.
#include "gpu/pipeline/texture_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "gpu/pipeline/llvmpipe_cpu.h"

namespace uvr::gpu {

namespace {

constexpr int32_t kIntegerIndefinite = std::numeric_limits<int32_t>::min();  // what x86 float->int gives on overflow

// Round to nearest, ties to even: exact, and independent of the floating-point environment (the JIT code runs in
// the default MXCSR mode, which is nearest-even). For |x| < 2^31 only (the callers check): in integers, with no
// library call. The upload's float -> unorm8 conversion, and x86_cvt_rne where there is no x86 instruction for it.
float round_half_even(float x)
{
    // floor(x): truncation, one down for a negative non-integer. Exact: below 2^23 the floor has at most 24 bits, and
    // from 2^23 on every float is an integer.
    int64_t f = static_cast<int64_t>(x);
    if (static_cast<float>(f) > x) f -= 1;
    // x - floor(x) is a multiple of ulp(x) below 1, hence exact, except for x in (-0.5, 0), where it may round (up to
    // 0.5 at worst); the answer there is 0 either way.
    const float frac = x - static_cast<float>(f);
    if (frac > 0.5f || (frac == 0.5f && (f & 1) != 0)) f += 1;
    return static_cast<float>(f);
}

// The channel value llvmpipe's SoA fetch produces (lp_build_fetch_rgba_soa -> lp_build_extract_soa_chan): floats
// are bit casts, unorm channels go through lp_build_unsigned_norm_to_float. Missing channels of a 1-channel format
// read as 0 (green, blue) and 1 (alpha), the format swizzle (r, 0, 0, 1).
inline float fetch_channel(const TextureView& tex, std::size_t texel, int c)
{
    if (c >= tex.channels) return c == 3 ? 1.0f : 0.0f;
    const std::size_t i = texel * std::size_t(tex.channels) + std::size_t(c);
    switch (tex.format) {
    case TexelFormat::f32: return static_cast<const float*>(tex.texels)[i];
    case TexelFormat::u16: return unorm16_to_float(static_cast<const uint16_t*>(tex.texels)[i]);
    case TexelFormat::u8: return unorm8_to_float(static_cast<const uint8_t*>(tex.texels)[i]);
    }
    return 0.0f;
}

// The byte the AoS path works on: lp_build_fetch_rgba_aos expands a 1-channel R8 texel to (r, 0, 0, 255).
uint8_t fetch_byte(const TextureView& tex, std::size_t texel, int c)
{
    if (c >= tex.channels) return c == 3 ? 255 : 0;
    return static_cast<const uint8_t*>(tex.texels)[texel * std::size_t(tex.channels) + std::size_t(c)];
}

// The texels v_yx of slice z0 and (3D) z1 of a linear filter's taps (LinearTaps or LinearTaps8), computed once for
// every channel: texel[s][2 * y + x].
struct SliceTexels {
    template <class Taps>
    SliceTexels(const TextureView& tex, const Taps& tx, const Taps& ty, const Taps& tz, int dims)
    {
        for (int s = 0; s < (dims == 3 ? 2 : 1); ++s) {
            const int z = s == 0 ? tz.i0 : tz.i1;
            at[s][0] = texel_index(tex, tx.i0, ty.i0, z);
            at[s][1] = texel_index(tex, tx.i1, ty.i0, z);
            at[s][2] = texel_index(tex, tx.i0, ty.i1, z);
            at[s][3] = texel_index(tex, tx.i1, ty.i1, z);
        }
    }
    const std::size_t* operator[](int s) const { return at[s]; }
    std::size_t at[2][4];
};

glm::vec4 sample_nearest(const TextureView& tex, const float* coord, int dims)
{
    // lp_build_sample_wrap_nearest (SoA) truncates coord * size and clamps; lp_build_sample_wrap_nearest_int (AoS)
    // floors coord * size and clamps. After the clamp to [0, size - 1] the two agree for every float input (they
    // differ only on (-1, 0), where both end at 0; NaN and |coord * size| >= 2^31 give 0x80000000, clamped to 0),
    // so both paths fetch the same texel and convert it to float the same way.
    const int size[3] = {tex.width, tex.height, tex.depth};
    int i[3] = {0, 0, 0};
    const bool aos = sample_path(tex.format) == SamplePath::aos_unorm8;
    for (int a = 0; a < dims; ++a)
        i[a] = aos ? wrap_nearest_aos(coord[a], size[a]) : wrap_nearest_soa(coord[a], size[a]);
    return texel_fetch(tex, i[0], i[1], i[2]);
}

// flatten: the taps, the lerps and the conversion inlined, as the loop runs them on every lookup of an 8-bit volume.
[[gnu::flatten]] glm::vec4 sample_linear_aos(const TextureView& tex, const float* coord, int dims,
                                             const LlvmpipeCpu& cpu)
{
    // lp_bld_sample_aos.c, lp_build_sample_image_linear + lp_build_sample_fetch_image_linear: the same lerp tree
    // as the SoA path (lp_build_reduce_filter_2d / _3d -> lp_build_lerp_2d / _3d, x first, then y, then z), but on
    // bytes with 8-bit weights (LP_BLD_LERP_PRESCALED_WEIGHTS), each intermediate result rounded back to a byte.
    // The filtered bytes become floats once, at the end (lp_build_rgba8_to_fi32_soa ->
    // lp_build_unsigned_norm_to_float(8)).
    const LinearTaps8 tx = wrap_linear_aos(coord[0], tex.width);
    const LinearTaps8 ty = wrap_linear_aos(coord[1], tex.height);
    const LinearTaps8 tz = dims == 3 ? wrap_linear_aos(coord[2], tex.depth) : LinearTaps8{0, 0, 0};
    const bool rounds = cpu.lerp8_rounds;
    const SliceTexels texel(tex, tx, ty, tz, dims);
    // A channel the format lacks is the same byte at every tap (fetch_byte: 0, alpha 255), and a lerp of two equal
    // bytes returns that byte (delta 0): its result is the constant, converted as the others.
    glm::vec4 out(unorm8_to_float(0), unorm8_to_float(0), unorm8_to_float(0), unorm8_to_float(255));
    for (int c = 0; c < tex.channels; ++c) {
        auto slice = [&](int s) {
            const uint8_t r0 =
                lerp_unorm8(tx.weight, fetch_byte(tex, texel[s][0], c), fetch_byte(tex, texel[s][1], c), rounds);
            const uint8_t r1 =
                lerp_unorm8(tx.weight, fetch_byte(tex, texel[s][2], c), fetch_byte(tex, texel[s][3], c), rounds);
            return lerp_unorm8(ty.weight, r0, r1, rounds);
        };
        const uint8_t c0 = slice(0);
        out[c] = unorm8_to_float(dims == 3 ? lerp_unorm8(tz.weight, c0, slice(1), rounds) : c0);
    }
    return out;
}

// sample_linear_aos on a one-channel 3D texture (the ray caster's 8-bit volume, every sample): the same taps, lerps
// and conversion, with the eight texels addressed from one base and three strides and the red channel alone.
template <bool kRounds>
float sample_linear_r8_3d(const TextureView& tex, const float* coord)
{
    const LinearTaps8 tx = wrap_linear_aos(coord[0], tex.width);
    const LinearTaps8 ty = wrap_linear_aos(coord[1], tex.height);
    const LinearTaps8 tz = wrap_linear_aos(coord[2], tex.depth);
    const std::size_t w = std::size_t(tex.width), wh = w * std::size_t(tex.height);
    const uint8_t* p = static_cast<const uint8_t*>(tex.texels) + texel_index(tex, tx.i0, ty.i0, tz.i0);
    const std::size_t dx = std::size_t(tx.i1 - tx.i0), dy = std::size_t(ty.i1 - ty.i0) * w,
                      dz = std::size_t(tz.i1 - tz.i0) * wh;
    const auto slice = [&](const uint8_t* q) {
        const uint8_t r0 = lerp_unorm8(tx.weight, q[0], q[dx], kRounds);
        const uint8_t r1 = lerp_unorm8(tx.weight, q[dy], q[dy + dx], kRounds);
        return lerp_unorm8(ty.weight, r0, r1, kRounds);
    };
    return unorm8_to_float(lerp_unorm8(tz.weight, slice(p), slice(p + dz), kRounds));
}

// The one-channel 8-bit volume's linear lookup as sample_3d returns it (green and blue 0, alpha 1).
glm::vec4 sample_r8(const TextureView& tex, const float* coord, const LlvmpipeCpu& cpu)
{
    const float r = cpu.lerp8_rounds ? sample_linear_r8_3d<true>(tex, coord) : sample_linear_r8_3d<false>(tex, coord);
    return {r, unorm8_to_float(0), unorm8_to_float(0), unorm8_to_float(255)};
}

glm::vec4 sample_any(const TextureView& tex, const float* coord, int dims, TextureFilter filter,
                     const LlvmpipeCpu& cpu)
{
    if (takes_linear_f32x4_fma(tex, filter, cpu)) return sample_linear_f32x4_fma(tex, coord, dims);
    if (filter == TextureFilter::nearest) return sample_nearest(tex, coord, dims);
    if (sample_path(tex.format) == SamplePath::aos_unorm8) return sample_linear_aos(tex, coord, dims, cpu);
    return sample_linear_soa(tex, coord, dims, cpu);
}

}  // namespace

bool takes_linear_f32x4_fma(const TextureView& tex, TextureFilter filter, const LlvmpipeCpu& cpu)
{
    static const bool fma = host_has_fma();
    return filter == TextureFilter::linear && tex.format == TexelFormat::f32 && tex.channels == 4 && cpu.fma && fma;
}

glm::vec4 sample_linear_soa(const TextureView& tex, const float* coord, int dims, const LlvmpipeCpu& cpu)
{
    // lp_build_sample_image_linear: the taps of each axis, the four texels of slice z0 filtered by
    // lp_build_reduce_filter_2d = lp_build_lerp_2d(s, t, v00, v01, v10, v11) = lerp(t, lerp(s, v00, v01),
    // lerp(s, v10, v11)) with v_yx, then (3D) the same for slice z1 and lerp(r, slice0, slice1). Every lerp is
    // lp_build_lerp_simple on floats: fmuladd(w, v1 - v0, v0).
    const LinearTaps tx = wrap_linear_soa(coord[0], tex.width);
    const LinearTaps ty = wrap_linear_soa(coord[1], tex.height);
    const LinearTaps tz = dims == 3 ? wrap_linear_soa(coord[2], tex.depth) : LinearTaps{0, 0, 0.0f};
    const SliceTexels texel(tex, tx, ty, tz, dims);
    glm::vec4 out;
    for (int c = 0; c < 4; ++c) {
        auto slice = [&](int s) {
            const float v00 = fetch_channel(tex, texel[s][0], c);
            const float v01 = fetch_channel(tex, texel[s][1], c);
            const float v10 = fetch_channel(tex, texel[s][2], c);
            const float v11 = fetch_channel(tex, texel[s][3], c);
            const float r0 = lerp_f32(tx.weight, v00, v01, cpu.fma);
            const float r1 = lerp_f32(tx.weight, v10, v11, cpu.fma);
            return lerp_f32(ty.weight, r0, r1, cpu.fma);
        };
        const float c0 = slice(0);
        out[c] = dims == 3 ? lerp_f32(tz.weight, c0, slice(1), cpu.fma) : c0;
    }
    return out;
}

const char* texel_format_name(TexelFormat f)
{
    switch (f) {
    case TexelFormat::f32: return "f32";
    case TexelFormat::u16: return "u16";
    case TexelFormat::u8: return "u8";
    }
    return "?";
}

int texel_channel_bytes(TexelFormat f)
{
    switch (f) {
    case TexelFormat::f32: return 4;
    case TexelFormat::u16: return 2;
    case TexelFormat::u8: return 1;
    }
    return 0;
}

LlvmpipeCpu host_llvmpipe_cpu()
{
    LlvmpipeCpu cpu;
    cpu.fma = llvmpipe_cpu_caps().fma;  // Mesa's decision (llvmpipe_cpu.h); other architectures: none, unverified
    cpu.lerp8_rounds = true;  // Mesa 22.3: pmulhrsw, on any x86 CPU with SSSE3 (2006 on)
    return cpu;
}

int32_t x86_cvtt(float x)
{
    // In range means -2^31 <= x < 2^31 (both bounds are exact floats); C++'s conversion truncates like cvttps2dq.
    if (!(x >= -2147483648.0f && x < 2147483648.0f)) return kIntegerIndefinite;
    return static_cast<int32_t>(x);
}

#if !UVR_X86_CVT_INSTRUCTION
int32_t x86_cvt_rne(float x)
{
    if (!(x >= -2147483648.0f && x < 2147483648.0f)) return kIntegerIndefinite;
    return static_cast<int32_t>(round_half_even(x));  // floats above 2^23 are integers: no rounding out of range
}
#endif

/*
 * unorm -> float. lp_build_unsigned_norm_to_float, branch "src_width <= mantissa + 1": the integer is converted
 * exactly (sitofp), then multiplied by lp_build_const_vec(1.0 / (2^n - 1)), a double constant rounded to float.
 * So the result is fl(i * fl(1/255)), one float rounding after an already rounded constant: 126 of the 256 8-bit
 * values (and 512 of the 65536 16-bit ones) differ by an ulp from i / 255.0f (i / 65535.0f); 255 maps to 1.0f.
 */
float unorm8_to_float(uint8_t v)
{
    constexpr float kScale = static_cast<float>(1.0 / 255.0);  // rounded to nearest, at compile time as at run time
    return static_cast<float>(v) * kScale;
}

float unorm16_to_float(uint16_t v)
{
    constexpr float kScale = static_cast<float>(1.0 / 65535.0);
    return static_cast<float>(v) * kScale;
}

/*
 * float -> unorm on upload. Mesa 22.3's texstore converts GL_FLOAT rows with the util_format pack functions
 * (u_format_pack.py): RGBA8 through float_to_ubyte, f * (255/256) + 32768.0f read back from the mantissa's low
 * byte, a round-to-nearest-even of f * 255 that agrees with _mesa_float_to_unorm's
 * _mesa_i64roundevenf(f * 255.0f) on every float in [0, 1] (enumerated); RGBA16 through
 * util_iround(CLAMP(f, 0, 1) * 65535.0f), ties away from zero. In both the product rounds once in float (x has 24
 * significant bits, the factor 8 or 16), and the ties that matter are products landing exactly on k + 1/2.
 */
uint8_t float_to_unorm8(float x)
{
    if (!(x > 0.0f)) return 0;  // also NaN (Mesa leaves it undefined)
    if (x > 1.0f) return 255;
    return static_cast<uint8_t>(round_half_even(x * 255.0f));
}

uint16_t float_to_unorm16(float x)
{
    if (!(x > 0.0f)) return 0;
    if (x > 1.0f) return 65535;
    const float p = x * 65535.0f;
    const float f = std::floor(p);
    return static_cast<uint16_t>(p - f >= 0.5f ? f + 1.0f : f);  // p - f is exact
}

/*
 * lp_build_lerp_simple, float types: delta = v1 - v0 (one rounding), then lp_build_mad(x, delta, v0), which is
 * lp_build_fmuladd -> llvm.fmuladd. LLVM fuses it into vfmadd (w * delta + v0, one rounding) when the target has
 * FMA3 and emits mulps + addps (two roundings) otherwise.
 */
float lerp_f32(float w, float v0, float v1, bool fma)
{
    const float delta = v1 - v0;
    if (fma) return std::fma(w, delta, v0);
    const float prod = w * delta;
    return prod + v0;
}

/*
 * lp_build_lerp on unorm8 vectors (type.norm): the bytes are unpacked to 16-bit lanes (zero-extended: 0..255) and
 * lp_build_lerp_simple runs with LP_BLD_LERP_WIDE_NORMALIZED | LP_BLD_LERP_PRESCALED_WEIGHTS on unsigned 16-bit
 * lanes, so the weight w8 needs no 255 -> 256 rescaling:
 *   delta = v1 - v0                    16-bit wrap-around; as a signed value in [-255, 255]
 *   rounding variant (pmulhrsw, SSSE3 lanes of 8 x i16 or AVX2 16 x i16):
 *     res = (w8 * (delta << 7) + 0x4000) >> 15   32-bit product, arithmetic shift, = floor((w8 * delta + 128) / 256)
 *     res &= 0xff
 *   truncating variant (plain 16-bit multiply):
 *     res = ((w8 * delta) mod 2^16) >> 8         logical shift: the high byte, = floor(w8 * delta / 256) mod 256
 *   result = (v0 + res) mod 256                  added as 8-bit lanes ("add with half wide type")
 * The wrap-around is harmless: |w8 * delta / 256| < |delta|, so the true sum v0 + res lies between v0 and v1.
 */
uint8_t lerp_unorm8(uint32_t w8, uint8_t v0, uint8_t v1, bool rounds)
{
    const int32_t delta = int32_t(v1) - int32_t(v0);
    uint32_t res;
    if (rounds) {
        const int32_t prod = int32_t(w8) * (delta * 128) + 0x4000;  // |.| < 2^23: no overflow
        res = uint32_t(prod >> 15) & 0xffu;                         // >> is arithmetic for negatives (C++20)
    } else {
        const uint32_t prod = (w8 * uint32_t(uint16_t(delta))) & 0xffffu;
        res = prod >> 8;
    }
    return static_cast<uint8_t>((uint32_t(v0) + res) & 0xffu);
}

/*
 * SoA nearest, CLAMP_TO_EDGE (lp_build_sample_wrap_nearest): coord * size in float (one rounding), lp_build_itrunc
 * (fptosi -> cvttps2dq, so NaN and huge values give 0x80000000), then lp_build_clamp(i, 0, size - 1) = max(min(i,
 * size - 1), 0) in 32-bit integers. Consequence: +inf and coordinates beyond 2^31 / size pick texel 0, not the last.
 */
int32_t wrap_nearest_soa(float coord, int size)
{
    const float c = coord * static_cast<float>(size);
    const int32_t i = x86_cvtt(c);
    return std::max(std::min(i, int32_t(size - 1)), int32_t(0));
}

/*
 * AoS nearest, CLAMP_TO_EDGE (lp_build_sample_image_nearest + lp_build_sample_wrap_nearest_int):
 * lp_build_unnormalized_coords multiplies by the float size (one rounding), lp_build_ifloor floors (roundps, mode
 * floor, then cvttps2dq), and the wrap clamps with max(i, 0) then min(i, size - 1).
 */
int32_t wrap_nearest_aos(float coord, int size)
{
    const float c = coord * static_cast<float>(size);
    const int32_t i = x86_cvtt(std::floor(c));
    return std::min(std::max(i, int32_t(0)), int32_t(size - 1));
}

SamplePath sample_path(TexelFormat f)
{
    // lp_build_sample_soa_code: use_aos = util_format_fits_8unorm(format) && plain texture op && no compare &&
    // no anisotropy && simple wrap modes (REPEAT, CLAMP_TO_EDGE) on every axis && not tiled && no seamless cube
    // filtering. Of our formats only RGBA8 / R8 fit 8unorm; RGBA16 does not, float never.
    return f == TexelFormat::u8 ? SamplePath::aos_unorm8 : SamplePath::soa_float;
}

glm::vec4 texel_fetch(const TextureView& tex, int x, int y, int z)
{
    const std::size_t i = texel_index(tex, x, y, z);
    return {fetch_channel(tex, i, 0), fetch_channel(tex, i, 1), fetch_channel(tex, i, 2), fetch_channel(tex, i, 3)};
}

glm::vec4 sample_2d(const TextureView& tex, float s, float t, TextureFilter filter, const LlvmpipeCpu& cpu)
{
    const float coord[3] = {s, t, 0.0f};
    return sample_any(tex, coord, 2, filter, cpu);
}

glm::vec4 sample_3d(const TextureView& tex, float s, float t, float r, TextureFilter filter, const LlvmpipeCpu& cpu)
{
    const float coord[3] = {s, t, r};
    if (tex.channels == 1 && tex.format == TexelFormat::u8 && filter == TextureFilter::linear)
        return sample_r8(tex, coord, cpu);
    return sample_any(tex, coord, 3, filter, cpu);
}

}  // namespace uvr::gpu
