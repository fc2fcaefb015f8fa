#include "gpu/raycast/raycast_packet.h"

#include <algorithm>

#include "gpu/pipeline/texture_lanes.h"

namespace uvr::gpu {

#if defined(__x86_64__)

namespace {

using namespace simd;

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

// The volume's lookup, as sample_3d takes it for the volume's format: an 8-bit volume through the AoS path (its 8-bit
// lerp rounding or not), a 16-bit or float one through the SoA path (its lerps fused or not).
template <bool kRounds>
struct R8Volume {
    UVR_AVX2 static V sample(const TextureView& t, V x, V y, V z) { return sample_volume<kRounds>(t, x, y, z); }
};
template <TexelFormat kFormat, bool kFma>
struct SoaVolume {
    UVR_AVX2 static V sample(const TextureView& t, V x, V y, V z)
    {
        return sample_volume_soa<kFormat, kFma>(t, x, y, z);
    }
};

// The march's scalar at sample k of every lane (raycast_march's position(k), then scalar(p)); where `at_exit`, at the
// lane's exit instead.
template <class Volume>
UVR_AVX2 V scalar_at(const RaycastFrameConstants& fc, const RaycastTextures& tex, const Lanes& lanes, int k,
                     V at_exit = _mm256_setzero_ps())
{
    const V kf = splat(static_cast<float>(k));
    V p[3];
    for (int a = 0; a < 3; ++a)
        p[a] = _mm256_blendv_ps(_mm256_add_ps(lanes.tex0[a], _mm256_mul_ps(kf, lanes.dtex[a])), lanes.exit[a], at_exit);
    const V u = Volume::sample(tex.volume, p[0], p[1], p[2]);
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
template <class Volume, bool kFma>
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
        composite(acc, classify<kFma>(table, ty, scalar_at<Volume>(fc, tex, lanes, k)), active);
        taken = _mm256_sub_epi32(taken, active);  // + 1 on the active lanes (-1 each)
        alive = _mm256_andnot_si256(opaque(acc, fc.threshold), alive);
    }
    store_results(acc, taken, count, out);
}

// The pre-integrated march with the table's usual path (TableSegmentShader), every step in the lanes: raycast_march
// from sample 1 to n, the last sample at the exit with the last length, a segment composited where its length is
// positive.
template <class Volume>
__attribute__((target("avx2,fma"))) void march_table(const RaycastFrameConstants& fc, const RaycastRay* rays, int count,
                                                     const RaycastTextures& tex, const TextureView& table,
                                                     RaycastResult* out)
{
    const Lanes lanes = load_lanes(rays, count);
    V previous = scalar_at<Volume>(fc, tex, lanes, 0);
    V acc[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    I alive = _mm256_cmpgt_epi32(lanes.n, _mm256_setzero_si256());  // a ray without samples takes none
    I taken = _mm256_and_si256(alive, splat(1));                    // the entry's sample
    for (int k = 1; k <= lanes.longest; ++k) {
        const I active = _mm256_and_si256(alive, _mm256_cmpgt_epi32(lanes.n, splat(k - 1)));  // k <= n
        if (_mm256_testz_si256(active, active)) break;
        const V last = _mm256_castsi256_ps(_mm256_cmpeq_epi32(lanes.n, splat(k)));
        const V x = scalar_at<Volume>(fc, tex, lanes, k, last);
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
template <class Volume, class Segment>
__attribute__((target("avx2,fma"))) void march_preintegrated(const RaycastFrameConstants& fc, const RaycastRay* rays,
                                                             int count, const RaycastTextures& tex,
                                                             const Segment& segment, RaycastResult* out)
{
    const Lanes lanes = load_lanes(rays, count);
    alignas(32) float previous[8], x[8];
    _mm256_store_ps(previous, scalar_at<Volume>(fc, tex, lanes, 0));
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
        _mm256_store_ps(x, scalar_at<Volume>(fc, tex, lanes, k, last));
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

template <class Volume>
void march(const RaycastFrameConstants& fc, const RaycastRay* rays, int count, const RaycastTextures& tex,
           RaycastResult* out)
{
    if (fc.preintegrate) {
        if (tex.table_segment) return march_table<Volume>(fc, rays, count, tex, tex.table_segment->view, out);
        return march_preintegrated<Volume>(fc, rays, count, tex, tex.segment, out);
    }
    if (tex.cpu.fma) return march_classified<Volume, true>(fc, rays, count, tex, out);
    march_classified<Volume, false>(fc, rays, count, tex, out);
}

template <TexelFormat kFormat>
void march_soa(const RaycastFrameConstants& fc, const RaycastRay* rays, int count, const RaycastTextures& tex,
               RaycastResult* out)
{
    if (tex.cpu.fma) return march<SoaVolume<kFormat, true>>(fc, rays, count, tex, out);
    march<SoaVolume<kFormat, false>>(fc, rays, count, tex, out);
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
    return host_has_avx2() && !fc.shade && (fc.preintegrate || tex.classification) && v.channels == 1 && fits(v, 1) &&
           table_fits;
}

void raycast_march_packet(const RaycastFrameConstants& fc, const RaycastRay* rays, int count,
                          const RaycastTextures& tex, RaycastResult* out)
{
    switch (tex.volume.format) {
        case TexelFormat::u8:
            if (tex.cpu.lerp8_rounds) return march<R8Volume<true>>(fc, rays, count, tex, out);
            return march<R8Volume<false>>(fc, rays, count, tex, out);
        case TexelFormat::u16:
            return march_soa<TexelFormat::u16>(fc, rays, count, tex, out);
        case TexelFormat::f32:
            return march_soa<TexelFormat::f32>(fc, rays, count, tex, out);
    }
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
