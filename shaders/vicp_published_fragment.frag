// VICP-FragmentProg's exit as Moreland's dissertation gives it (--interpolation gpu): the GLSL twin of
// gpu/vicp/vicp_published_fragment.cpp. The smallest interpolated distance greater than 0 (the first on ties; a NaN is
// never chosen), its scalar the exit's; both scalars clamped by comparisons.

struct VicpPublishedExit {
    int face;  // 0..2, or -1: no distance is positive (length 0)
    float s_front, s_back;
    float chord;  // its length (not `length`, which some compilers take for the method)
};

float vicp_published_clamp01(float x)
{
    precise float c = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;  // precise: kept as comparisons, not turned into min/max
    return c;
}

VicpPublishedExit vicp_published_exit(vec3 distance, vec3 scalar, float s)
{
    VicpPublishedExit e;
    e.face = -1;
    e.chord = 0.0;
    for (int i = 0; i < 3; ++i) {
        float d = distance[i];
        if (d > 0.0 && (e.face < 0 || d < e.chord)) {
            e.face = i;
            e.chord = d;
        }
    }
    e.s_front = vicp_published_clamp01(s);
    e.s_back = e.face >= 0 ? vicp_published_clamp01(scalar[e.face]) : 0.0;
    return e;
}
