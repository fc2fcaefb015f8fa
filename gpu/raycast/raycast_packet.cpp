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

// The march's position of sample k in every lane (raycast_march's position(k)); where `at_exit`, the lane's exit.
UVR_AVX2 void position_at(const Lanes& lanes, int k, V at_exit, V* p)
{
    const V kf = splat(static_cast<float>(k));
    for (int a = 0; a < 3; ++a)
        p[a] = _mm256_blendv_ps(_mm256_add_ps(lanes.tex0[a], _mm256_mul_ps(kf, lanes.dtex[a])), lanes.exit[a], at_exit);
}

// raycast_march's scalar(p): the volume's value, normalized.
template <class Volume>
UVR_AVX2 V scalar_of(const RaycastFrameConstants& fc, const RaycastTextures& tex, const V* p)
{
    const V u = Volume::sample(tex.volume, p[0], p[1], p[2]);
    return _mm256_add_ps(_mm256_mul_ps(u, splat(fc.scalar_scale)), splat(fc.scalar_bias));
}

// raycast_gradient in the lanes: per axis, the lookups one texel up and down, their difference times the axis's scale.
template <class Volume>
UVR_AVX2 void gradient_of(const RaycastFrameConstants& fc, const RaycastTextures& tex, const V* p, V* g)
{
    const float texel[3] = {fc.texel.x, fc.texel.y, fc.texel.z};
    const float scale[3] = {fc.gradient_scale.x, fc.gradient_scale.y, fc.gradient_scale.z};
    for (int a = 0; a < 3; ++a) {
        V up[3] = {p[0], p[1], p[2]}, down[3] = {p[0], p[1], p[2]};
        up[a] = _mm256_add_ps(p[a], splat(texel[a]));
        down[a] = _mm256_sub_ps(p[a], splat(texel[a]));
        const V u = Volume::sample(tex.volume, up[0], up[1], up[2]);
        const V d = Volume::sample(tex.volume, down[0], down[1], down[2]);
        g[a] = _mm256_mul_ps(_mm256_sub_ps(u, d), splat(scale[a]));
    }
}

// The shading of raycast_march on the lanes `on`: the gradient in the lanes, each lane's light factors
// (raycast_light, double precision, its own ray and distance t[l]), then raycast_lit in the lanes.
template <class Volume>
__attribute__((target("avx2,fma"))) Rgba shade(const RaycastFrameConstants& fc, const RaycastTextures& tex,
                                               const RaycastRay* rays, int count, I on, const double* t, const V* p,
                                               Rgba c)
{
    V g[3];
    gradient_of<Volume>(fc, tex, p, g);
    alignas(32) float gx[8], gy[8], gz[8], m[8] = {}, q[8] = {};
    alignas(32) int32_t marching[8];
    _mm256_store_ps(gx, g[0]);
    _mm256_store_ps(gy, g[1]);
    _mm256_store_ps(gz, g[2]);
    _mm256_store_si256(reinterpret_cast<I*>(marching), on);
    for (int l = 0; l < count; ++l) {
        if (!marching[l]) continue;
        const glm::vec2 f = raycast_light(fc, rays[l], t[l], glm::vec3(gx[l], gy[l], gz[l]));
        m[l] = f.x;
        q[l] = f.y;
    }
    const V mv = _mm256_load_ps(m), qv = _mm256_load_ps(q);
    for (int ch = 0; ch < 3; ++ch) c.c[ch] = _mm256_add_ps(_mm256_mul_ps(c.c[ch], mv), _mm256_mul_ps(c.c[3], qv));
    return c;
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
        V p[3];
        position_at(lanes, k, _mm256_setzero_ps(), p);
        Rgba c = classify<kFma>(table, ty, scalar_of<Volume>(fc, tex, p));
        if (fc.shade) {
            double t[8];
            for (double& tl : t) tl = double(k) * fc.step;
            c = shade<Volume>(fc, tex, rays, count, active, t, p, c);
        }
        composite(acc, c, active);
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
    V p[3];
    position_at(lanes, 0, _mm256_setzero_ps(), p);
    V previous = scalar_of<Volume>(fc, tex, p);
    V acc[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    I alive = _mm256_cmpgt_epi32(lanes.n, _mm256_setzero_si256());  // a ray without samples takes none
    I taken = _mm256_and_si256(alive, splat(1));                    // the entry's sample
    for (int k = 1; k <= lanes.longest; ++k) {
        const I active = _mm256_and_si256(alive, _mm256_cmpgt_epi32(lanes.n, splat(k - 1)));  // k <= n
        if (_mm256_testz_si256(active, active)) break;
        const V last = _mm256_castsi256_ps(_mm256_cmpeq_epi32(lanes.n, splat(k)));
        position_at(lanes, k, last, p);
        const V x = scalar_of<Volume>(fc, tex, p);
        const V length = _mm256_blendv_ps(splat(fc.step_f), lanes.last_length, last);
        const V t_z = _mm256_add_ps(_mm256_mul_ps(length, splat(fc.length_scale)), splat(fc.length_bias));
        const I lit =
            _mm256_and_si256(active, _mm256_castps_si256(_mm256_cmp_ps(length, _mm256_setzero_ps(), _CMP_GT_OQ)));
        Rgba c = segment_lookup(table, previous, x, t_z);
        if (fc.shade) {
            double t[8];
            for (int l = 0; l < 8; ++l) t[l] = l < count && k == rays[l].samples ? rays[l].length : double(k) * fc.step;
            c = shade<Volume>(fc, tex, rays, count, lit, t, p, c);
        }
        composite(acc, c, lit);
        taken = _mm256_sub_epi32(taken, active);
        previous = _mm256_blendv_ps(previous, x, _mm256_castsi256_ps(active));
        alive = _mm256_andnot_si256(opaque(acc, fc.threshold), alive);
    }
    store_results(acc, taken, count, out);
}

// The segments of the m marching lanes of one step: out[i] for (u_front[i], u_back[i], length[i]); the exact
// integral takes them together in its lanes, any other shader one by one.
template <class Segment>
void segments_of(const RaycastFrameConstants& fc, const Segment& segment, int m, const float* u_front,
                 const float* u_back, const float* length, glm::vec4* out)
{
    for (int i = 0; i < m; ++i)
        out[i] = segment(u_front[i], u_back[i], length[i] * fc.length_scale + fc.length_bias, length[i]);
}
void segments_of(const RaycastFrameConstants&, const ExactSegmentShader& segment, int m, const float* u_front,
                 const float* u_back, const float* length, glm::vec4* out)
{
    segment.many(std::size_t(m), u_front, u_back, length, out);
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
    V p[3];
    position_at(lanes, 0, _mm256_setzero_ps(), p);
    _mm256_store_ps(previous, scalar_of<Volume>(fc, tex, p));
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
        position_at(lanes, k, last, p);
        _mm256_store_ps(x, scalar_of<Volume>(fc, tex, p));
        // The shading's gradients, in the lanes; each lane's light below.
        alignas(32) float g[3][8];
        if (fc.shade) {
            V gv[3];
            gradient_of<Volume>(fc, tex, p, gv);
            for (int a = 0; a < 3; ++a) _mm256_store_ps(g[a], gv[a]);
        }
        // The marching lanes' segments of positive length, all at once; `at[l]`: lane l's in c, -1 where it has none,
        // -2 where the lane does not march.
        float u_front[8], u_back[8], length[8];
        glm::vec4 c[8];
        int at[8], m = 0;
        for (int l = 0; l < count; ++l) {
            at[l] = -2;
            if (!alive[l] || k > rays[l].samples) continue;
            length[m] = k == rays[l].samples ? rays[l].last_length : fc.step_f;
            at[l] = -1;
            if (!(length[m] > 0.0f)) continue;
            u_front[m] = previous[l];
            u_back[m] = x[l];
            at[l] = m++;
        }
        segments_of(fc, segment, m, u_front, u_back, length, c);
        for (int l = 0; l < count; ++l) {
            if (at[l] == -2) continue;
            ++out[l].samples;
            if (at[l] >= 0) {
                glm::vec4 ci = c[at[l]];
                if (fc.shade) {
                    const double t = k == rays[l].samples ? rays[l].length : double(k) * fc.step;
                    ci = raycast_lit(ci, raycast_light(fc, rays[l], t, glm::vec3(g[0][l], g[1][l], g[2][l])));
                }
                raycast_composite(out[l].colour, ci);
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
        if (tex.exact_segment) return march_preintegrated<Volume>(fc, rays, count, tex, *tex.exact_segment, out);
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
    return host_has_avx2() && (fc.preintegrate || tex.classification) && v.channels == 1 && fits(v, 1) && table_fits;
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
