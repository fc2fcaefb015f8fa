// Texture lookups in the eight lanes of AVX2 registers, each lane computing what texture_sampling.h computes for one
// lookup (the same IEEE and integer operations in the same order, so the same bits): llvmpipe's 8-bit AoS filter
// (taps, texels, integer lerps) and its float SoA filter of RGBA32F textures (taps, texels, lerps, fused or not).
// For callers compiled for the target "avx2,fma" (every function here is always inlined into its caller, which must
// carry that target) on a host where host_has_avx2() holds. Used by the ray caster's packet march
// (gpu/raycast/raycast_packet.h).
#pragma once

#if defined(__x86_64__)

#include <immintrin.h>

#include "gpu/pipeline/texture_sampling.h"

namespace uvr::gpu::simd {

// Every helper carries the target: GCC inlines a function compiled for AVX2 only into one that is. The loops over the
// four channels are unrolled (#pragma): left as loops, GCC keeps the channels in memory (1.2 x the frame's time).
#define UVR_AVX2 __attribute__((target("avx2,fma"), always_inline)) inline

using V = __m256;
using I = __m256i;

UVR_AVX2 I splat(int32_t v)
{
    return _mm256_set1_epi32(v);
}
UVR_AVX2 V splat(float v)
{
    return _mm256_set1_ps(v);
}

// wrap_linear_aos (texture_sampling.h) in eight lanes: cvtps2dq rounds as cvtss2si does (MXCSR, to nearest), the
// subtraction wraps as the scalar's unsigned one, >> is arithmetic in both.
struct Taps8 {
    I i0, i1, weight;
};
UVR_AVX2 Taps8 wrap_aos(V coord, int size)
{
    const V c = _mm256_mul_ps(coord, splat(static_cast<float>(size << 8)));
    const I v = _mm256_sub_epi32(_mm256_cvtps_epi32(c), splat(128));
    const I i = _mm256_srai_epi32(v, 8);
    const I lmask = _mm256_cmpgt_epi32(i, splat(-1));        // i >= 0
    const I umask = _mm256_cmpgt_epi32(splat(size - 1), i);  // i < size - 1
    Taps8 t;
    t.weight = _mm256_and_si256(v, splat(0xff));
    t.i0 = _mm256_blendv_epi8(splat(size - 1), _mm256_and_si256(i, lmask), umask);
    t.i1 = _mm256_sub_epi32(t.i0, _mm256_and_si256(lmask, umask));  // + 1 where both masks hold (-1 each)
    return t;
}

// lerp_unorm8 in 32-bit lanes: the same integer products, shifts and masks.
template <bool kRounds>
UVR_AVX2 I lerp8(I w, I v0, I v1)
{
    const I delta = _mm256_sub_epi32(v1, v0);
    I res;
    if constexpr (kRounds) {
        const I prod = _mm256_add_epi32(_mm256_mullo_epi32(w, _mm256_slli_epi32(delta, 7)), splat(0x4000));
        res = _mm256_and_si256(_mm256_srai_epi32(prod, 15), splat(0xff));
    } else {
        const I prod = _mm256_and_si256(_mm256_mullo_epi32(w, _mm256_and_si256(delta, splat(0xffff))), splat(0xffff));
        res = _mm256_srli_epi32(prod, 8);
    }
    return _mm256_and_si256(_mm256_add_epi32(v0, res), splat(0xff));
}

// The texel at byte index i of an 8-bit texture: the low byte of the 32-bit word gathered there (little-endian),
// which reads up to 3 bytes of the storage's padding past the last texel.
UVR_AVX2 I texel8(const int* texels, I index)
{
    return _mm256_and_si256(_mm256_i32gather_epi32(texels, index, 1), splat(0xff));
}

// The four texels of slice q (q, q + dx, q + dy, q + dy + dx) filtered as sample_linear_r8_3d's slice.
template <bool kRounds>
UVR_AVX2 I slice8(const int* texels, I q, I dx, I dy, const Taps8& tx, const Taps8& ty)
{
    const I r0 = lerp8<kRounds>(tx.weight, texel8(texels, q), texel8(texels, _mm256_add_epi32(q, dx)));
    const I qy = _mm256_add_epi32(q, dy);
    const I r1 = lerp8<kRounds>(tx.weight, texel8(texels, qy), texel8(texels, _mm256_add_epi32(qy, dx)));
    return lerp8<kRounds>(ty.weight, r0, r1);
}

// sample_linear_r8_3d (texture_sampling.cpp) in eight lanes.
template <bool kRounds>
UVR_AVX2 V sample_volume(const TextureView& tex, V x, V y, V z)
{
    const Taps8 tx = wrap_aos(x, tex.width), ty = wrap_aos(y, tex.height), tz = wrap_aos(z, tex.depth);
    const I w = splat(tex.width), wh = splat(tex.width * tex.height);
    const I base =
        _mm256_add_epi32(_mm256_add_epi32(tx.i0, _mm256_mullo_epi32(ty.i0, w)), _mm256_mullo_epi32(tz.i0, wh));
    const I dx = _mm256_sub_epi32(tx.i1, tx.i0);
    const I dy = _mm256_mullo_epi32(_mm256_sub_epi32(ty.i1, ty.i0), w);
    const I dz = _mm256_mullo_epi32(_mm256_sub_epi32(tz.i1, tz.i0), wh);
    const int* texels = static_cast<const int*>(tex.texels);
    const I u8 = lerp8<kRounds>(tz.weight, slice8<kRounds>(texels, base, dx, dy, tx, ty),
                                slice8<kRounds>(texels, _mm256_add_epi32(base, dz), dx, dy, tx, ty));
    constexpr float kScale = static_cast<float>(1.0 / 255.0);  // unorm8_to_float's
    return _mm256_mul_ps(_mm256_cvtepi32_ps(u8), splat(kScale));
}

// lerp_f32: fused (one rounding) or a product and a sum.
template <bool kFma>
UVR_AVX2 V lerp_f(V w, V v0, V v1)
{
    const V delta = _mm256_sub_ps(v1, v0);
    if constexpr (kFma) return _mm256_fmadd_ps(w, delta, v0);
    return _mm256_add_ps(_mm256_mul_ps(w, delta), v0);
}

struct Rgba {
    V c[4];
};

// Eight RGBA32F texels (channel 0 of lane l at float index at[l]), one a lane: rows of four floats transposed to four
// registers of eight lanes (r, g, b, a). Loads and shuffles: each value moves unchanged.
UVR_AVX2 V texel_pair(const float* texels, const int32_t* at, int l)
{
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(texels + at[l])), _mm_loadu_ps(texels + at[l + 4]),
                                1);
}
UVR_AVX2 Rgba texels8(const float* texels, const int32_t* at)
{
    const V a = texel_pair(texels, at, 0), b = texel_pair(texels, at, 1);  // lanes l | l + 4
    const V c = texel_pair(texels, at, 2), d = texel_pair(texels, at, 3);
    const V ab_lo = _mm256_unpacklo_ps(a, b), ab_hi = _mm256_unpackhi_ps(a, b);  // r0 r1 g0 g1 | b0 b1 a0 a1
    const V cd_lo = _mm256_unpacklo_ps(c, d), cd_hi = _mm256_unpackhi_ps(c, d);
    Rgba out;
    out.c[0] = _mm256_shuffle_ps(ab_lo, cd_lo, 0x44);
    out.c[1] = _mm256_shuffle_ps(ab_lo, cd_lo, 0xee);
    out.c[2] = _mm256_shuffle_ps(ab_hi, cd_hi, 0x44);
    out.c[3] = _mm256_shuffle_ps(ab_hi, cd_hi, 0xee);
    return out;
}

// wrap_linear_soa (texture_sampling.h) in eight lanes: minps and maxps select as its comparisons do (c < size ? c :
// size, then c > 0 ? c : 0), c is then in [0, size - 0.5], so truncation is floor.
struct TapsF {
    I i0, i1;
    V weight;
};
UVR_AVX2 TapsF wrap_soa(V coord, int size)
{
    const V size_f = splat(static_cast<float>(size));
    V c = _mm256_min_ps(_mm256_mul_ps(coord, size_f), size_f);
    c = _mm256_max_ps(_mm256_sub_ps(c, splat(0.5f)), _mm256_setzero_ps());
    TapsF t;
    t.i0 = _mm256_cvttps_epi32(c);
    t.weight = _mm256_sub_ps(c, _mm256_cvtepi32_ps(t.i0));
    t.i1 = _mm256_min_epi32(_mm256_add_epi32(t.i0, splat(1)), splat(size - 1));
    return t;
}

// The lerp along x of texels (x0, row) and (x1, row) of an RGBA32F texture, `row` being each lane's texel index of
// x = 0: each channel's lerp.
template <bool kFma>
UVR_AVX2 Rgba lerp_x(const TextureView& tex, I row, const TapsF& tx)
{
    const float* texels = static_cast<const float*>(tex.texels);
    alignas(32) int32_t i0[8], i1[8];  // float index of channel 0: 4 (row + x)
    _mm256_store_si256(reinterpret_cast<I*>(i0), _mm256_slli_epi32(_mm256_add_epi32(row, tx.i0), 2));
    _mm256_store_si256(reinterpret_cast<I*>(i1), _mm256_slli_epi32(_mm256_add_epi32(row, tx.i1), 2));
    const Rgba v0 = texels8(texels, i0), v1 = texels8(texels, i1);
    Rgba r;
#pragma GCC unroll 4
    for (int ch = 0; ch < 4; ++ch) r.c[ch] = lerp_f<kFma>(tx.weight, v0.c[ch], v1.c[ch]);
    return r;
}

template <bool kFma>
UVR_AVX2 Rgba lerp(V w, const Rgba& a, const Rgba& b)
{
    Rgba out;
#pragma GCC unroll 4
    for (int ch = 0; ch < 4; ++ch) out.c[ch] = lerp_f<kFma>(w, a.c[ch], b.c[ch]);
    return out;
}

// Texel `index` of a one-channel float (R32F) or 16-bit (R16, as unorm16_to_float converts it) texture, as float. A
// 16-bit texel is the low half of the 32-bit word gathered at its address, which reads 2 bytes past the last texel.
template <TexelFormat kFormat>
UVR_AVX2 V texel_red(const void* texels, I index)
{
    static_assert(kFormat == TexelFormat::f32 || kFormat == TexelFormat::u16);
    if constexpr (kFormat == TexelFormat::f32) return _mm256_i32gather_ps(static_cast<const float*>(texels), index, 4);
    const I v = _mm256_and_si256(_mm256_i32gather_epi32(static_cast<const int*>(texels), index, 2), splat(0xffff));
    constexpr float kScale = static_cast<float>(1.0 / 65535.0);  // unorm16_to_float's
    return _mm256_mul_ps(_mm256_cvtepi32_ps(v), splat(kScale));
}

// The lerp along x of texels (x0, row) and (x1, row) of a one-channel texture, `row` the lanes' texel index of x = 0.
template <TexelFormat kFormat, bool kFma>
UVR_AVX2 V lerp_x_red(const void* texels, I row, const TapsF& tx)
{
    return lerp_f<kFma>(tx.weight, texel_red<kFormat>(texels, _mm256_add_epi32(row, tx.i0)),
                        texel_red<kFormat>(texels, _mm256_add_epi32(row, tx.i1)));
}

// Slice z filtered in x and y: lerp(t, lerp(s, v00, v01), lerp(s, v10, v11)).
template <TexelFormat kFormat, bool kFma>
UVR_AVX2 V slice_red(const TextureView& tex, I z, const TapsF& tx, const TapsF& ty)
{
    const I w = splat(tex.width), zh = _mm256_mullo_epi32(z, splat(tex.height));
    const V r0 = lerp_x_red<kFormat, kFma>(tex.texels, _mm256_mullo_epi32(_mm256_add_epi32(zh, ty.i0), w), tx);
    const V r1 = lerp_x_red<kFormat, kFma>(tex.texels, _mm256_mullo_epi32(_mm256_add_epi32(zh, ty.i1), w), tx);
    return lerp_f<kFma>(ty.weight, r0, r1);
}

// sample_linear_soa's red channel on a one-channel float or 16-bit 3D texture (the ray caster's volume), in eight
// lanes: the taps of x, y and z, then the lerp tree x, y, z.
template <TexelFormat kFormat, bool kFma>
UVR_AVX2 V sample_volume_soa(const TextureView& tex, V x, V y, V z)
{
    const TapsF tx = wrap_soa(x, tex.width), ty = wrap_soa(y, tex.height), tz = wrap_soa(z, tex.depth);
    return lerp_f<kFma>(tz.weight, slice_red<kFormat, kFma>(tex, tz.i0, tx, ty),
                        slice_red<kFormat, kFma>(tex, tz.i1, tx, ty));
}

// Slice z of the 3D table filtered in x and y, fused.
UVR_AVX2 Rgba table_slice(const TextureView& table, I z, const TapsF& tx, const TapsF& ty)
{
    const I w = splat(table.width), zh = _mm256_mullo_epi32(z, splat(table.height));
    const Rgba r0 = lerp_x<true>(table, _mm256_mullo_epi32(_mm256_add_epi32(zh, ty.i0), w), tx);
    const Rgba r1 = lerp_x<true>(table, _mm256_mullo_epi32(_mm256_add_epi32(zh, ty.i1), w), tx);
    return lerp<true>(ty.weight, r0, r1);
}

// texture(table, vec3(u_front, u_back, t_z)) on the 3D RGBA32F pre-integrated table, fused (TableSegmentShader:
// sample_linear_f32x4_fma): x, then y, then z, as its lerp tree.
UVR_AVX2 Rgba segment_lookup(const TextureView& table, V u_front, V u_back, V t_z)
{
    const TapsF tx = wrap_soa(u_front, table.width), ty = wrap_soa(u_back, table.height);
    const TapsF tz = wrap_soa(t_z, table.depth);
    return lerp<true>(tz.weight, table_slice(table, tz.i0, tx, ty), table_slice(table, tz.i1, tx, ty));
}

}  // namespace uvr::gpu::simd

#endif
