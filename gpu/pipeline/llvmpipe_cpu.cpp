#include "gpu/pipeline/llvmpipe_cpu.h"

#include <cstdlib>
#include <cstring>

#include "reference/error.h"

namespace uvr::gpu {

namespace {

// Mesa's debug_get_bool_option: unset is false; "n", "no", "0", "f", "F", "false", "FALSE" are false; anything else
// is true.
bool mesa_bool(const char* v)
{
    if (!v) return false;
    for (const char* no : {"n", "no", "0", "f", "F", "false", "FALSE"})
        if (std::strcmp(v, no) == 0) return false;
    return true;
}

CpuCaps cpuid_caps()
{
    CpuCaps c;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    // libgcc's "avx" includes the OS's XGETBV check, as Mesa's has_avx does.
    c.ssse3 = __builtin_cpu_supports("ssse3");
    c.sse4_1 = __builtin_cpu_supports("sse4.1");
    c.avx = __builtin_cpu_supports("avx");
    c.fma = __builtin_cpu_supports("fma") && c.avx;
#endif
    return c;
}

}  // namespace

CpuCaps mesa_cpu_caps(const CpuCaps& cpuid, const char* override_caps, const char* nosse)
{
    // src/util/u_cpu_detect.c, check_cpu_caps_override: each value clears one feature, and clearing a feature clears
    // every later one (sse -> sse2 -> sse3 -> ssse3 -> sse4.1 -> avx -> fma). Unknown values change nothing.
    int keep = 4;  // 0: below ssse3, 1: ssse3, 2: sse4.1, 3: avx, 4: everything
    if (mesa_bool(nosse)) keep = 0;
    if (override_caps) {
        const struct {
            const char* value;
            int keep;
        } cut[] = {{"nosse", 0}, {"sse", 0}, {"sse2", 0}, {"sse3", 0}, {"ssse3", 1}, {"sse4.1", 2}};
        for (const auto& c : cut)
            if (std::strcmp(override_caps, c.value) == 0 && c.keep < keep) keep = c.keep;
    }
    CpuCaps c = cpuid;
    c.ssse3 = c.ssse3 && keep >= 1;
    c.sse4_1 = c.sse4_1 && keep >= 2;
    c.avx = c.avx && keep >= 3;
    c.fma = c.fma && c.avx;
    return c;
}

const CpuCaps& llvmpipe_cpu_caps()
{
    static const CpuCaps caps =
        mesa_cpu_caps(cpuid_caps(), std::getenv("GALLIUM_OVERRIDE_CPU_CAPS"), std::getenv("GALLIUM_NOSSE"));
    return caps;
}

void require_emulated_cpu_caps()
{
    const CpuCaps host = cpuid_caps();
    const CpuCaps& c = llvmpipe_cpu_caps();
    if ((host.ssse3 && !c.ssse3) || (host.sse4_1 && !c.sse4_1)) {
        const char* o = std::getenv("GALLIUM_OVERRIDE_CPU_CAPS");
        const std::string set = mesa_bool(std::getenv("GALLIUM_NOSSE")) ? std::string("GALLIUM_NOSSE")
                                                                        : "GALLIUM_OVERRIDE_CPU_CAPS=" + std::string(o);
        throw InputError("", set +
                                 " takes SSSE3 or SSE4.1 from llvmpipe, whose code without them the emulation does "
                                 "not model; unset it (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1 or avx are emulated)");
    }
}

}  // namespace uvr::gpu
