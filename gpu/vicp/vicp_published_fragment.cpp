#include "gpu/vicp/vicp_published_fragment.h"

namespace uvr::gpu {

namespace {
// Comparisons, so that a NaN stays NaN (as the GLSL twin's and as vicp_fragment_values clamps).
float clamp01(float x)
{
    return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
}
}  // namespace

VicpPublishedExit vicp_published_exit(const VicpPublishedVaryings& v)
{
    VicpPublishedExit e;
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

VicpPublishedPlanes vicp_published_planes(const SetupVertex sv[3], const VicpPublishedVaryings v[3],
                                          const TriangleSetup& ts)
{
    VicpPublishedPlanes p;
    p.setup = setup_attributes(sv, ts);
    for (int c = 0; c < 3; ++c) {
        const float d[3] = {v[0].distance[c], v[1].distance[c], v[2].distance[c]};
        const float x[3] = {v[0].scalar[c], v[1].scalar[c], v[2].scalar[c]};
        p.varying[p.kDistance + c] = attribute_plane(p.setup, sv, d, Qualifier::smooth);
        p.varying[p.kScalar + c] = attribute_plane(p.setup, sv, x, Qualifier::smooth);
    }
    const float s[3] = {v[0].s, v[1].s, v[2].s};
    p.varying[p.kS] = attribute_plane(p.setup, sv, s, Qualifier::smooth);
    return p;
}

VicpPublishedVaryings vicp_published_varyings_at(const VicpPublishedPlanes& p, int px, int py, ViewportArithmetic arith)
{
    return vicp_published_varyings_at(p, px, py, perspective_factor(p.setup, px, py, arith), arith);
}

VicpPublishedVaryings vicp_published_varyings_at(const VicpPublishedPlanes& p, int px, int py, float factor,
                                                 ViewportArithmetic arith)
{
    float at[VicpPublishedPlanes::kCount];
    interpolate(p.varying, VicpPublishedPlanes::kCount, Qualifier::smooth, px, py, factor, arith, at);
    VicpPublishedVaryings v;
    for (int c = 0; c < 3; ++c) {
        v.distance[c] = at[p.kDistance + c];
        v.scalar[c] = at[p.kScalar + c];
    }
    v.s = at[p.kS];
    return v;
}

}  // namespace uvr::gpu
