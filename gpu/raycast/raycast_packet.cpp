#include "gpu/raycast/raycast_packet.h"

#include <algorithm>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace uvr::gpu {

#if defined(__x86_64__)

namespace {

bool host_has_avx2()
{
    static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return avx2;
}

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

// texture(table, vec2(u, 0.5)) on the N x 1 RGBA32F classification table (sample_linear_soa / its FMA path); t's taps
// are the same for every lane.
template <bool kFma>
UVR_AVX2 Rgba classify(const TextureView& table, const LinearTaps& ty, V u)
{
    const TapsF tx = wrap_soa(u, table.width);
    const Rgba r0 = lerp_x<kFma>(table, splat(ty.i0 * table.width), tx);
    // One row (the table's height is 1): the second row's lerps are the first's on the same texels, the same bits.
    const Rgba r1 = ty.i1 == ty.i0 ? r0 : lerp_x<kFma>(table, splat(ty.i1 * table.width), tx);
    return lerp<kFma>(splat(ty.weight), r0, r1);
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

// The packet's rays in lanes: their start, step, exit and sample count.
struct Lanes {
    V tex0[3], dtex[3], exit[3], last_length;
    I n;
    int longest = 0;
};
__attribute__((target("avx2,fma"))) Lanes load_lanes(const RaycastRay* rays, int count)
{
    alignas(32) float v[10][8] = {};
    alignas(32) int32_t n[8] = {};
    Lanes lanes;
    for (int l = 0; l < count; ++l) {
        for (int a = 0; a < 3; ++a) {
            v[a][l] = rays[l].tex0[a];
            v[3 + a][l] = rays[l].dtex[a];
            v[6 + a][l] = rays[l].tex_exit[a];
        }
        v[9][l] = rays[l].last_length;
        n[l] = rays[l].samples;
        lanes.longest = std::max(lanes.longest, rays[l].samples);
    }
    for (int a = 0; a < 3; ++a) {
        lanes.tex0[a] = _mm256_load_ps(v[a]);
        lanes.dtex[a] = _mm256_load_ps(v[3 + a]);
        lanes.exit[a] = _mm256_load_ps(v[6 + a]);
    }
    lanes.last_length = _mm256_load_ps(v[9]);
    lanes.n = _mm256_load_si256(reinterpret_cast<const I*>(n));
    return lanes;
}

// The march's scalar at sample k of every lane (raycast_march's position(k), then scalar(p)); where `at_exit`, at the
// lane's exit instead.
template <bool kRounds>
UVR_AVX2 V scalar_at(const RaycastFrameConstants& fc, const RaycastTextures& tex, const Lanes& lanes, int k,
                     V at_exit = _mm256_setzero_ps())
{
    const V kf = splat(static_cast<float>(k));
    V p[3];
    for (int a = 0; a < 3; ++a)
        p[a] = _mm256_blendv_ps(_mm256_add_ps(lanes.tex0[a], _mm256_mul_ps(kf, lanes.dtex[a])), lanes.exit[a], at_exit);
    const V u = sample_volume<kRounds>(tex.volume, p[0], p[1], p[2]);
    return _mm256_add_ps(_mm256_mul_ps(u, splat(fc.scalar_scale)), splat(fc.scalar_bias));
}

// raycast_composite on the lanes of `on` only.
UVR_AVX2 void composite(V* acc, const Rgba& c, I on)
{
    const V one_minus_a = _mm256_sub_ps(splat(1.0f), acc[3]);
#pragma GCC unroll 4
    for (int ch = 0; ch < 4; ++ch)
        acc[ch] = _mm256_blendv_ps(acc[ch], _mm256_add_ps(_mm256_mul_ps(c.c[ch], one_minus_a), acc[ch]),
                                   _mm256_castsi256_ps(on));
}

// The lanes whose opacity has passed the threshold (raycast_march's test: acc.a > threshold, false for NaN).
UVR_AVX2 I opaque(const V* acc, float threshold)
{
    return _mm256_castps_si256(_mm256_cmp_ps(acc[3], splat(threshold), _CMP_GT_OQ));
}

__attribute__((target("avx2,fma"))) void store_results(const V* acc, I taken, int count, RaycastResult* out)
{
    alignas(32) float rgba[4][8];
    alignas(32) int32_t samples[8];
#pragma GCC unroll 4
    for (int ch = 0; ch < 4; ++ch) _mm256_store_ps(rgba[ch], acc[ch]);
    _mm256_store_si256(reinterpret_cast<I*>(samples), taken);
    for (int l = 0; l < count; ++l) {
        out[l].colour = {rgba[0][l], rgba[1][l], rgba[2][l], rgba[3][l]};
        out[l].samples = uint32_t(samples[l]);
    }
}

// The post-classified march, every step in the lanes.
template <bool kRounds, bool kFma>
__attribute__((target("avx2,fma"))) void march_classified(const RaycastFrameConstants& fc, const RaycastRay* rays,
                                                          int count, const RaycastTextures& tex, RaycastResult* out)
{
    const Lanes lanes = load_lanes(rays, count);
    const TextureView table = tex.classification->view();
    const LinearTaps ty = wrap_linear_soa(0.5f, table.height);
    V acc[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    I taken = _mm256_setzero_si256();
    I alive = splat(-1);
    for (int k = 0; k < lanes.longest; ++k) {
        // A lane marches while k < its sample count and its opacity has not passed the threshold.
        const I active = _mm256_and_si256(alive, _mm256_cmpgt_epi32(lanes.n, splat(k)));
        if (_mm256_testz_si256(active, active)) break;
        composite(acc, classify<kFma>(table, ty, scalar_at<kRounds>(fc, tex, lanes, k)), active);
        taken = _mm256_sub_epi32(taken, active);  // + 1 on the active lanes (-1 each)
        alive = _mm256_andnot_si256(opaque(acc, fc.threshold), alive);
    }
    store_results(acc, taken, count, out);
}

// The pre-integrated march with the table's usual path (TableSegmentShader), every step in the lanes: raycast_march
// from sample 1 to n, the last sample at the exit with the last length, a segment composited where its length is
// positive.
template <bool kRounds>
__attribute__((target("avx2,fma"))) void march_table(const RaycastFrameConstants& fc, const RaycastRay* rays, int count,
                                                     const RaycastTextures& tex, const TextureView& table,
                                                     RaycastResult* out)
{
    const Lanes lanes = load_lanes(rays, count);
    V previous = scalar_at<kRounds>(fc, tex, lanes, 0);
    V acc[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    I alive = _mm256_cmpgt_epi32(lanes.n, _mm256_setzero_si256());  // a ray without samples takes none
    I taken = _mm256_and_si256(alive, splat(1));                    // the entry's sample
    for (int k = 1; k <= lanes.longest; ++k) {
        const I active = _mm256_and_si256(alive, _mm256_cmpgt_epi32(lanes.n, splat(k - 1)));  // k <= n
        if (_mm256_testz_si256(active, active)) break;
        const V last = _mm256_castsi256_ps(_mm256_cmpeq_epi32(lanes.n, splat(k)));
        const V x = scalar_at<kRounds>(fc, tex, lanes, k, last);
        const V length = _mm256_blendv_ps(splat(fc.step_f), lanes.last_length, last);
        const V t_z = _mm256_add_ps(_mm256_mul_ps(length, splat(fc.length_scale)), splat(fc.length_bias));
        const I lit = _mm256_castps_si256(_mm256_cmp_ps(length, _mm256_setzero_ps(), _CMP_GT_OQ));
        composite(acc, segment_lookup(table, previous, x, t_z), _mm256_and_si256(active, lit));
        taken = _mm256_sub_epi32(taken, active);
        previous = _mm256_blendv_ps(previous, x, _mm256_castsi256_ps(active));
        alive = _mm256_andnot_si256(opaque(acc, fc.threshold), alive);
    }
    store_results(acc, taken, count, out);
}

// The pre-integrated march with any other segment (--segment exact): the volume's samples in the lanes, each lane's
// segment and compositing on its own (raycast_march's, in its order: the samples of one ray never mix).
template <bool kRounds, class Segment>
__attribute__((target("avx2,fma"))) void march_preintegrated(const RaycastFrameConstants& fc, const RaycastRay* rays,
                                                             int count, const RaycastTextures& tex,
                                                             const Segment& segment, RaycastResult* out)
{
    const Lanes lanes = load_lanes(rays, count);
    alignas(32) float previous[8], x[8];
    _mm256_store_ps(previous, scalar_at<kRounds>(fc, tex, lanes, 0));
    bool alive[8] = {};
    for (int l = 0; l < count; ++l) {
        out[l] = RaycastResult{};
        alive[l] = rays[l].samples > 0;
        out[l].samples = alive[l] ? 1 : 0;
    }
    for (int k = 1; k <= lanes.longest; ++k) {
        bool any = false;
        for (int l = 0; l < count; ++l) any |= alive[l] && k <= rays[l].samples;
        if (!any) break;
        const V last = _mm256_castsi256_ps(_mm256_cmpeq_epi32(lanes.n, splat(k)));
        _mm256_store_ps(x, scalar_at<kRounds>(fc, tex, lanes, k, last));
        for (int l = 0; l < count; ++l) {
            if (!alive[l] || k > rays[l].samples) continue;
            const bool is_last = k == rays[l].samples;
            const float length = is_last ? rays[l].last_length : fc.step_f;
            ++out[l].samples;
            if (length > 0.0f) {
                const float t_z = length * fc.length_scale + fc.length_bias;
                raycast_composite(out[l].colour, segment(previous[l], x[l], t_z, length));
            }
            previous[l] = x[l];
            if (out[l].colour.a > fc.threshold) alive[l] = false;
        }
    }
}

template <bool kRounds>
void march(const RaycastFrameConstants& fc, const RaycastRay* rays, int count, const RaycastTextures& tex,
           RaycastResult* out)
{
    if (fc.preintegrate) {
        if (tex.table_segment) return march_table<kRounds>(fc, rays, count, tex, tex.table_segment->view, out);
        return march_preintegrated<kRounds>(fc, rays, count, tex, tex.segment, out);
    }
    if (tex.cpu.fma) return march_classified<kRounds, true>(fc, rays, count, tex, out);
    march_classified<kRounds, false>(fc, rays, count, tex, out);
}

}  // namespace

bool packet_march_applies(const RaycastFrameConstants& fc, const RaycastTextures& tex)
{
    // Every index a lane computes is a 32-bit integer: the volume's texels, the tables' floats.
    const auto fits = [](const TextureView& t, int64_t per_texel) {
        return int64_t(t.width) * t.height * t.depth * per_texel < (int64_t(1) << 31);
    };
    const TextureView& v = tex.volume;
    const bool table_fits = !fc.preintegrate || !tex.table_segment || fits(tex.table_segment->view, 4);
    return host_has_avx2() && !fc.shade && (fc.preintegrate || tex.classification) && v.format == TexelFormat::u8 &&
           v.channels == 1 && fits(v, 1) && table_fits;
}

void raycast_march_packet(const RaycastFrameConstants& fc, const RaycastRay* rays, int count,
                          const RaycastTextures& tex, RaycastResult* out)
{
    if (tex.cpu.lerp8_rounds) return march<true>(fc, rays, count, tex, out);
    march<false>(fc, rays, count, tex, out);
}

#else

bool packet_march_applies(const RaycastFrameConstants&, const RaycastTextures&)
{
    return false;
}

void raycast_march_packet(const RaycastFrameConstants& fc, const RaycastRay* rays, int count,
                          const RaycastTextures& tex, RaycastResult* out)
{
    for (int l = 0; l < count; ++l) out[l] = raycast_march(fc, rays[l], tex);
}

#endif

}  // namespace uvr::gpu
