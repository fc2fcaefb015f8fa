// Bit-for-bit comparison of an emulated stage's outputs with the GL stage's (docs/spec.md §5), shared by the HAVS and
// VICP stage tests: counts of differing bit patterns, the largest difference in ulps, the first few cases described;
// and the small table both sample in a real 3D texture.
#pragma once

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "gpu/pipeline/preintegration_table.h"

namespace uvr::test {

inline uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }
inline uint64_t bits(double d) { return std::bit_cast<uint64_t>(d); }

// Distance in ulps between two values of one type (ordered as integers); NaN against anything else counts as 2^32.
template <typename F>
uint64_t ulps(F a, F b)
{
    if (std::isnan(a) || std::isnan(b)) return bits(a) == bits(b) ? 0 : (uint64_t(1) << 32);
    using I = std::conditional_t<sizeof(F) == 4, int32_t, int64_t>;
    auto key = [](F f) {
        const I i = std::bit_cast<I>(f);
        // Negative values: order them below zero, -0 next to +0 (saturating at the ends is harmless here).
        return i < 0 ? std::numeric_limits<I>::min() - i : i;
    };
    const I ka = key(a), kb = key(b);
    const uint64_t d = ka > kb ? uint64_t(ka) - uint64_t(kb) : uint64_t(kb) - uint64_t(ka);
    return d;
}

// Counts differing bit patterns and the largest ulp difference, keeping a description of the first few.
struct Mismatches {
    uint64_t count = 0, compared = 0, max_ulps = 0;
    std::ostringstream first;
    template <typename F>
    void check(F emu, F glv, std::size_t c, const char* what)
    {
        ++compared;
        if (bits(emu) == bits(glv)) return;
        max_ulps = std::max(max_ulps, ulps(emu, glv));
        if (count++ < 8)
            first << "case " << c << " " << what << ": emulation " << emu << " (0x" << std::hex << bits(emu)
                  << ") GL " << glv << " (0x" << bits(glv) << std::dec << ")\n";
    }
    std::string summary(const char* stage) const
    {
        std::ostringstream s;
        s << stage << ": " << count << " of " << compared << " values differ, largest difference " << max_ulps
          << " ulps";
        return s.str();
    }
    void report(const char* stage)
    {
        INFO(summary(stage) << "\n" << first.str());
        CHECK(count == 0);
    }
};

// The pre-integrated table the stage tests sample in a real 3D texture: small (24 x 24 x 12 texels, segments up to 3)
// so that a lookup lands between texels at every level, over the scalar range [0, 1], in the given texel format.
inline gpu::PreintegrationTable stage_test_table(const SegmentIntegrator& integrator, gpu::TexelFormat format)
{
    gpu::PreintegrationConfig cfg;
    cfg.scalar_resolution = 24;
    cfg.length_resolution = 12;
    cfg.max_length = 3.0;
    cfg.format = format;
    return gpu::PreintegrationTable(integrator, Range{0.0, 1.0}, cfg);
}

}  // namespace uvr::test
