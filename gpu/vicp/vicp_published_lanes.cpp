#include "gpu/vicp/vicp_published_lanes.h"

#include <stdexcept>

#include "gpu/pipeline/texture_lanes.h"

namespace uvr::gpu {

#if defined(__x86_64__)

namespace {

using namespace simd;

// A plane at the lanes' pixels: fmuladd(dady, y, fmuladd(dadx, x, a0)), as evaluate_fma3 (interpolation.cpp).
UVR_AVX2 V plane_at(const AttributePlane& p, V x, V y)
{
    return _mm256_fmadd_ps(splat(p.dady), y, _mm256_fmadd_ps(splat(p.dadx), x, splat(p.a0)));
}

// x < 0 ? 0 : x > 1 ? 1 : x, by comparisons that are false on a NaN, which stays (vicp_published_fragment.cpp).
UVR_AVX2 V clamp01(V x)
{
    const V zero = _mm256_setzero_ps(), one = splat(1.0f);
    const V upper = _mm256_blendv_ps(x, one, _mm256_cmp_ps(x, one, _CMP_GT_OQ));
    return _mm256_blendv_ps(upper, zero, _mm256_cmp_ps(x, zero, _CMP_LT_OQ));
}

// The published segment in lanes: entry and exit scalars, the length (0 where no distance is positive).
struct ExitLanes {
    V s_front, s_back, length;
};

// vicp_published_varyings_at and vicp_published_exit: the factor 1 / (interpolated 1 / w), each smooth input's plane
// times it, then the smallest positive distance (the first on ties) and its scalar.
UVR_AVX2 ExitLanes published_exit(const VicpPublishedPlanes& p, V x, V y)
{
    const V factor = _mm256_div_ps(splat(1.0f), plane_at(p.setup.oow, x, y));
    const V zero = _mm256_setzero_ps(), all = _mm256_castsi256_ps(splat(-1));  // all: every bit set
    V found = zero, length = zero, scalar = zero;
    for (int i = 0; i < 3; ++i) {
        const V d = _mm256_mul_ps(plane_at(p.varying[p.kDistance + i], x, y), factor);
        const V nearer = _mm256_or_ps(_mm256_andnot_ps(found, all), _mm256_cmp_ps(d, length, _CMP_LT_OQ));
        const V take = _mm256_and_ps(_mm256_cmp_ps(d, zero, _CMP_GT_OQ), nearer);
        length = _mm256_blendv_ps(length, d, take);
        scalar = _mm256_blendv_ps(scalar, _mm256_mul_ps(plane_at(p.varying[p.kScalar + i], x, y), factor), take);
        found = _mm256_or_ps(found, take);
    }
    ExitLanes e;
    e.s_front = clamp01(_mm256_mul_ps(plane_at(p.varying[p.kS], x, y), factor));
    e.s_back = _mm256_and_ps(clamp01(scalar), found);  // 0 where no face was chosen
    e.length = length;
    return e;
}

}  // namespace

bool vicp_published_lanes_available(ViewportArithmetic arith)
{
    static const bool host = host_has_avx2() && host_has_fma();
    return host && arith == ViewportArithmetic::fused;
}

__attribute__((target("avx2,fma"))) void composite_published_lanes(const VicpPublishedPlanes& planes,
                                                                   const VicpFrameConstants& fc,
                                                                   const TableSegmentShader& shade,
                                                                   const FragmentBatch& batch, int width, glm::vec4* fb)
{
    // Lanes past the batch repeat its first fragment (valid inputs) and write nothing.
    alignas(32) int32_t px[8], py[8], at[8];
    for (int l = 0; l < 8; ++l) {
        const int k = l < batch.n ? l : 0;
        px[l] = batch.px[k];
        py[l] = batch.py[k];
        at[l] = 4 * (py[l] * width + px[l]);  // the pixel's first float in fb: below 2^30 for --size's 16384^2
    }
    const V x = _mm256_cvtepi32_ps(_mm256_load_si256(reinterpret_cast<const I*>(px)));
    const V y = _mm256_cvtepi32_ps(_mm256_load_si256(reinterpret_cast<const I*>(py)));
    const ExitLanes e = published_exit(planes, x, y);

    // vicp_composite: the kill (threshold - alpha < 0), the table's colour where the length is positive (t_z a
    // multiply and an add), then fb = c * (1 - fb.a) + fb per channel, unfused.
    const Rgba dst = texels8(reinterpret_cast<const float*>(fb), at);
    const V zero = _mm256_setzero_ps();
    const V killed = _mm256_cmp_ps(_mm256_sub_ps(splat(fc.threshold), dst.c[3]), zero, _CMP_LT_OQ);
    const V has = _mm256_cmp_ps(e.length, zero, _CMP_GT_OQ);
    const V t_z = _mm256_add_ps(_mm256_mul_ps(e.length, splat(fc.length_scale)), splat(fc.length_bias));
    const Rgba c = segment_lookup(shade.view, e.s_front, e.s_back, t_z);
    const V one_minus_a = _mm256_sub_ps(splat(1.0f), dst.c[3]);
    alignas(32) float out[4][8];
#pragma GCC unroll 4
    for (int ch = 0; ch < 4; ++ch)
        _mm256_store_ps(out[ch], _mm256_add_ps(_mm256_mul_ps(_mm256_and_ps(c.c[ch], has), one_minus_a), dst.c[ch]));
    const int live = ~_mm256_movemask_ps(killed);
    for (int l = 0; l < batch.n; ++l)
        if (live >> l & 1) fb[at[l] / 4] = glm::vec4(out[0][l], out[1][l], out[2][l], out[3][l]);
}

#else

bool vicp_published_lanes_available(ViewportArithmetic)
{
    return false;
}

void composite_published_lanes(const VicpPublishedPlanes&, const VicpFrameConstants&, const TableSegmentShader&,
                               const FragmentBatch&, int, glm::vec4*)
{
    throw std::logic_error("composite_published_lanes: not built for this processor");
}

#endif

}  // namespace uvr::gpu
