#include "gpu/havs/havs_paper_span.h"

#include <cmath>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "gpu/pipeline/texture_sampling.h"  // host_has_fma

namespace uvr::gpu {

namespace {

void paper_entries_scalar(const HavsFrameConstants& fc, const HavsVaryingPlanes& p, int py, int first, int last,
                          ViewportArithmetic arith, KEntry* out)
{
    for (int px = first; px <= last; ++px) out[px - first] = havs_paper_entry(fc, havs_varyings_at(p, px, py, arith));
}

#if defined(__x86_64__) || defined(__i386__)
bool host_has_avx2_fma()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && host_has_fma();
}

// fma(dady, y, fma(dadx, x, a0)), as interpolation.cpp's evaluate: x first.
__attribute__((target("avx2,fma"), always_inline)) inline __m256 plane_at(const AttributePlane& a, __m256 x, __m256 y)
{
    return _mm256_fmadd_ps(_mm256_set1_ps(a.dady), y, _mm256_fmadd_ps(_mm256_set1_ps(a.dadx), x, _mm256_set1_ps(a.a0)));
}

// Eight pixels a lane each, every operation the scalar path's in the same order: the plane as fma(dady, y, fma(dadx, x,
// a0)) (interpolation.cpp's evaluate), 1 / oow and the products by it, the corner comparisons (ordered: a NaN weight is
// not below 0), then havs_paper_entry's DP3/RSQ/MUL and its clamp. Each is an IEEE operation that rounds once per lane
// as its scalar form does, under the same MXCSR (FTZ, DAZ), so the bits are the scalar path's. Lanes past `last`
// compute values for pixels that are not covered; they are not stored.
__attribute__((target("avx2,fma"))) void paper_entries_avx2(const HavsFrameConstants& fc, const HavsVaryingPlanes& p,
                                                            int py, int first, int last, KEntry* out)
{
    const __m256 y = _mm256_set1_ps(float(py));
    const __m256 lanes = _mm256_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const bool interior = p.side == kSideInterior;
    for (int px = first; px <= last; px += 8) {
        // Columns are small integers: float(px) + lane is exact, the x the scalar path converts.
        const __m256 x = _mm256_add_ps(_mm256_set1_ps(float(px)), lanes);
        const __m256 factor = _mm256_div_ps(one, plane_at(p.setup.oow, x, y));
        const __m256 ex = _mm256_mul_ps(plane_at(p.smooth[0], x, y), factor);
        const __m256 ey = _mm256_mul_ps(plane_at(p.smooth[1], x, y), factor);
        const __m256 ez = _mm256_mul_ps(plane_at(p.smooth[2], x, y), factor);
        const __m256 s = _mm256_mul_ps(plane_at(p.smooth[3], x, y), factor);
        __m256 distance;
        if (fc.orthographic) {
            distance = _mm256_xor_ps(ez, _mm256_set1_ps(-0.0f));  // -e.z
        } else {
            const __m256 t =
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ez, ez), _mm256_mul_ps(ey, ey)), _mm256_mul_ps(ex, ex));
            distance = _mm256_mul_ps(t, _mm256_div_ps(one, _mm256_sqrt_ps(t)));
        }
        __m256 xs;
        if (fc.paper_entries) {
            xs = s;
        } else {
            __m256 side = _mm256_set1_ps(p.side);
            if (interior) {
                const __m256 outside =
                    _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(plane_at(p.corner[0], x, y), zero, _CMP_LT_OQ),
                                              _mm256_cmp_ps(plane_at(p.corner[1], x, y), zero, _CMP_LT_OQ)),
                                 _mm256_cmp_ps(plane_at(p.corner[2], x, y), zero, _CMP_LT_OQ));
                side = _mm256_blendv_ps(side, _mm256_set1_ps(kSideOutside), outside);
            }
            // s < 0 ? 0 : s > 1 ? 1 : s (a NaN fails both comparisons and stays).
            __m256 clamped = _mm256_blendv_ps(s, one, _mm256_cmp_ps(s, one, _CMP_GT_OQ));
            clamped = _mm256_blendv_ps(clamped, zero, _mm256_cmp_ps(s, zero, _CMP_LT_OQ));
            xs = _mm256_mul_ps(side, _mm256_add_ps(one, clamped));
        }
        alignas(32) float xv[8], yv[8];
        _mm256_store_ps(xv, xs);
        _mm256_store_ps(yv, distance);
        const int n = last - px + 1 < 8 ? last - px + 1 : 8;
        for (int i = 0; i < n; ++i) out[px - first + i] = KEntry{xv[i], yv[i]};
    }
}
#endif

}  // namespace

void havs_paper_entries(const HavsFrameConstants& fc, const HavsVaryingPlanes& p, int py, int first, int last,
                        ViewportArithmetic arith, KEntry* out, SpanPath path)
{
#if defined(__x86_64__) || defined(__i386__)
    static const bool avx2 = host_has_avx2_fma();
    if (path == SpanPath::fastest && arith == ViewportArithmetic::fused && avx2) {
        paper_entries_avx2(fc, p, py, first, last, out);
        return;
    }
#endif
    paper_entries_scalar(fc, p, py, first, last, arith, out);
}

}  // namespace uvr::gpu
