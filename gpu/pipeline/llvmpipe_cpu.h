// The CPU features llvmpipe's generated code depends on, decided as Mesa 22.3 decides them: util_cpu_caps from CPUID
// (FMA counts only with AVX enabled by the OS), then GALLIUM_NOSSE and GALLIUM_OVERRIDE_CPU_CAPS, which Mesa reads in
// release builds too and which can take features away (sse4.1 and below take FMA). LP_NATIVE_VECTOR_WIDTH sets the
// vector width only and does not change what is fused. docs/rasterizer.md, "The CPU's features".
#pragma once

#include <string>

namespace uvr::gpu {

struct CpuCaps {
    bool ssse3 = false;
    bool sse4_1 = false;
    bool avx = false;  // with the OS's support (XGETBV), as Mesa requires
    bool fma = false;  // FMA3, which Mesa counts only with avx
};

// Mesa's rule, from what CPUID reports and the two variables' values (nullptr: unset). Exposed for the tests.
CpuCaps mesa_cpu_caps(const CpuCaps& cpuid, const char* override_caps, const char* nosse);

// This process's caps (CPUID and the environment, read once, as Mesa reads them once).
const CpuCaps& llvmpipe_cpu_caps();

// Throws InputError when the environment takes from llvmpipe a feature whose absence the emulation does not model
// (SSSE3 or SSE4.1: other filtering and rounding code); only FMA may be taken away (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1).
void require_emulated_cpu_caps();

}  // namespace uvr::gpu
