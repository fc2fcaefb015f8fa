// The fast path of texture_sampling.cpp's SoA linear filter: RGBA32F textures, sampled as llvmpipe samples them on
// a CPU with FMA3, emulated on a host with FMA3. The plain path (sample_linear_soa) works channel by channel and
// calls std::fma, which the project's portable build (no -mfma) compiles to a library call; here the four channels
// of a texel are one SSE register and each lerp is one subtraction and one vfmadd, in a function compiled for FMA3
// alone. Each channel sees the same IEEE operations as in the plain path (v1 - v0 rounded once, then w * delta + v0
// fused, rounded once), so the results are the same bits; tests/test_texture_sampling.cpp holds the two equal on
// random and edge coordinates. It is a third of an emulated HAVS frame's fragment time (perf, Blunt Fin).
#include "gpu/pipeline/texture_sampling.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace uvr::gpu {

#if defined(__x86_64__) || defined(__i386__)

bool host_has_fma()
{
    static const bool fma = __builtin_cpu_supports("fma");
    return fma;
}

bool host_has_avx2()
{
    static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return avx2;
}

namespace {

// Every helper carries the target too: GCC inlines a function compiled for FMA3 only into one that is.
__attribute__((target("fma"), always_inline)) inline __m128 lerp4(__m128 w, __m128 v0, __m128 v1)
{
    return _mm_fmadd_ps(w, _mm_sub_ps(v1, v0), v0);
}

__attribute__((target("fma"), always_inline)) inline __m128 texel4(const TextureView& tex, int x, int y, int z)
{
    return _mm_loadu_ps(static_cast<const float*>(tex.texels) + 4 * texel_index(tex, x, y, z));
}

// The four texels of slice z filtered: lerp(t, lerp(s, v00, v01), lerp(s, v10, v11)).
__attribute__((target("fma"), always_inline)) inline __m128 slice4(const TextureView& tex, const LinearTaps& tx,
                                                                   const LinearTaps& ty, int z)
{
    const __m128 wx = _mm_set1_ps(tx.weight);
    const __m128 r0 = lerp4(wx, texel4(tex, tx.i0, ty.i0, z), texel4(tex, tx.i1, ty.i0, z));
    const __m128 r1 = lerp4(wx, texel4(tex, tx.i0, ty.i1, z), texel4(tex, tx.i1, ty.i1, z));
    return lerp4(_mm_set1_ps(ty.weight), r0, r1);
}

}  // namespace

__attribute__((target("fma"))) glm::vec4 sample_linear_f32x4_fma(const TextureView& tex, const float* coord, int dims)
{
    // The same taps and the same lerp tree as sample_linear_soa: x, then y, then (3D) z.
    const LinearTaps tx = wrap_linear_soa(coord[0], tex.width);
    const LinearTaps ty = wrap_linear_soa(coord[1], tex.height);
    __m128 c;
    if (dims == 3) {
        const LinearTaps tz = wrap_linear_soa(coord[2], tex.depth);
        c = lerp4(_mm_set1_ps(tz.weight), slice4(tex, tx, ty, tz.i0), slice4(tex, tx, ty, tz.i1));
    } else {
        c = slice4(tex, tx, ty, 0);
    }
    alignas(16) float out[4];
    _mm_store_ps(out, c);
    return {out[0], out[1], out[2], out[3]};
}

#else

bool host_has_fma() { return false; }
bool host_has_avx2()
{
    return false;
}

glm::vec4 sample_linear_f32x4_fma(const TextureView&, const float*, int) { return glm::vec4(0.0f); }

#endif

}  // namespace uvr::gpu
