// llvmpipe runs every shader with the x86 MXCSR's denormals-are-zero (DAZ, bit 6) and flush-to-zero (FTZ, bit 15) bits
// set (measured: docs/gl-backend.md, "Where bit-identity fails: denormals"). The emulated fragment stage runs under the
// same bits, set on the calling thread for the lifetime of a FlushDenormals and restored after, so that a denormal
// colour, a texel or an underflowing product rounds as on the GPU. On other CPUs the scope does nothing (llvmpipe's
// behaviour there is unmeasured).
// Twins: none (a CPU-side scope: the MXCSR bits llvmpipe's shader threads run under).
#pragma once

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#define UVR_HAVE_MXCSR 1
#endif

namespace uvr::gpu {

class FlushDenormals {
public:
#ifdef UVR_HAVE_MXCSR
    static constexpr unsigned kDazFtz = 0x8040u;  // FTZ (bit 15) | DAZ (bit 6)
    FlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kDazFtz); }
    ~FlushDenormals() { _mm_setcsr(saved_); }
#else
    FlushDenormals() = default;
#endif
    FlushDenormals(const FlushDenormals&) = delete;
    FlushDenormals& operator=(const FlushDenormals&) = delete;

private:
#ifdef UVR_HAVE_MXCSR
    unsigned saved_;
#endif
};

}  // namespace uvr::gpu
