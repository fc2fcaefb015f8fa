#include "gpu/vicp/vicp_seed_fragment.h"

namespace uvr::gpu {

namespace {
// Comparisons, so that a NaN stays NaN (as the GLSL twin's and as vicp_fragment_values clamps).
float clamp01(float x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; }
}  // namespace

VicpSeedExit vicp_seed_exit(const VicpSeedVaryings& v)
{
    VicpSeedExit e;
    for (int i = 0; i < 3; ++i) {
        const float d = v.distance[i];
        if (d > 0.0f && (e.face < 0 || d < e.length)) {
            e.face = i;
            e.length = d;
        }
    }
    e.s_front = clamp01(v.s);
    if (e.face >= 0) e.s_back = clamp01(v.scalar[e.face]);
    return e;
}

}  // namespace uvr::gpu
