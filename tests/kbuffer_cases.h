// Random inputs of HAVS's k-buffer program (the HAVS paper, Appendix II) for the stage tests: exact ties from a
// per-case pool of distances, empty and flush entries, +inf, every side of the entry encoding, framebuffer alphas at
// the kill threshold and one ulp either side, segments a maximum gap long. test_havs_gl_stage.cpp runs them through
// GLSL, test_havs_kbuffer.cpp through the program's instances.
#pragma once

#include <cmath>
#include <vector>

#include "gpu/havs/gl_havs_harness.h"
#include "gpu/havs/havs_fragment.h"
#include "case_rng.h"

namespace uvr::test {

using gpu::KBufferCases;
using gpu::KEntry;
using gpu::kEmptyEntry;
using gpu::kFlushFragment;
using gpu::kSideEntry;
using gpu::kSideExit;
using gpu::kSideInterior;
using gpu::kSideOutside;

inline float next_up(float x) { return std::nextafter(x, INFINITY); }
inline float next_down(float x) { return std::nextafter(x, -INFINITY); }

struct KBufferGen : test::CaseRng {
    float max_gap;
    explicit KBufferGen(uint64_t seed, float gap) : CaseRng(seed), max_gap(gap) {}

    // A per-case pool of distances, so that entries tie exactly; some pairs a maximum-length segment apart (exactly,
    // and one ulp either side) and some zero-length.
    std::vector<float> pool;
    void new_pool()
    {
        pool.clear();
        const int n = 1 + pick(6);
        for (int i = 0; i < n; ++i) pool.push_back(unif(0.25f, 8.0f));
        if (max_gap > 0.0f && pick(2) == 0) {
            // 1 + max_gap is exact for the gaps used here (dyadic), so the segment length comes out as max_gap.
            const float base = 1.0f, variants[3] = {max_gap, next_up(max_gap), next_down(max_gap)};
            pool.push_back(base);
            pool.push_back(base + variants[pick(3)]);
        }
    }
    float distance()
    {
        switch (pick(12)) {
        case 0: return INFINITY;
        case 1: return unif(0.01f, 100.0f);
        default: return pool[std::size_t(pick(int(pool.size())))];
        }
    }
    float scalar() { return pick(16) == 0 ? float(pick(2)) : unif(0.0f, 1.0f); }
    // Exit, entry and extrapolated faces' entries (1 in 5 each), interior faces' (2 in 5).
    float side()
    {
        const int p = pick(5);
        return p == 0 ? kSideExit : p == 1 ? kSideEntry : p == 2 ? kSideOutside : kSideInterior;
    }
    KEntry real() { return {side() * (1.0f + scalar()), distance()}; }
    KEntry stored()
    {
        switch (pick(8)) {
        case 0: return kEmptyEntry;
        case 1: return kFlushFragment;
        default: return real();
        }
    }
    KEntry incoming() { return pick(8) == 0 ? kFlushFragment : real(); }
    glm::vec4 framebuffer(float threshold)
    {
        float a;
        switch (pick(8)) {
        case 0: a = threshold; break;
        case 1: a = next_up(threshold); break;
        case 2: a = next_down(threshold); break;
        case 3: a = float(pick(2)); break;
        default: a = unif(0.0f, 1.0f);
        }
        return {unif(0.0f, 1.0f) * a, unif(0.0f, 1.0f) * a, unif(0.0f, 1.0f) * a, a};
    }
    glm::vec4 colour()
    {
        const float a = pick(10) == 0 ? float(pick(2)) : unif(0.0f, 1.0f);
        return {unif(0.0f, 1.0f) * a, unif(0.0f, 1.0f) * a, unif(0.0f, 1.0f) * a, a};
    }
};

inline KBufferCases make_kbuffer_cases(KBufferGen& g, int k, std::size_t n, float threshold)
{
    KBufferCases cs;
    cs.k = k;
    for (std::size_t i = 0; i < n; ++i) {
        g.new_pool();
        cs.incoming.push_back(g.incoming());
        for (int e = 0; e < k; ++e) cs.entries.push_back(g.stored());
        cs.framebuffer.push_back(g.framebuffer(threshold));
        cs.shade.push_back(g.colour());
    }
    return cs;
}

}  // namespace uvr::test
