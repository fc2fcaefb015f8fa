// Runs VICP's vertex stage (vicp_vertex.vert, compiled in front of this file behind vicp_tet.glsl) alone: one case per
// vertex of glDrawArrays(GL_POINTS, 0, n) with the rasterizer discarding, each writing vicp_tet_constants of its inputs
// to a storage buffer (gpu/vicp/gl_vicp_harness.cpp). The layouts are GlVicpVertexCase and GlVicpTet of
// gpu/vicp/gl_vicp_harness.h. With HARNESS_PUBLISHED_VERTEX (vicp_published_vertex.vert compiled in front instead), the
// published vertex program: 11 floats a case in (VicpPublishedVertex), 8 out (distance, s, scalar, 0).
#if defined(HARNESS_PUBLISHED_VERTEX)
layout(std430, binding = 0) readonly buffer HarnessPublishedCases { float harness_published_cases[]; };
layout(std430, binding = 1) writeonly buffer HarnessPublishedOut { float harness_published_out[]; };

void main()
{
    int b = 11 * gl_VertexID;
    vec3 position = vec3(harness_published_cases[b], harness_published_cases[b + 1], harness_published_cases[b + 2]);
    float s = harness_published_cases[b + 3];
    vec3 gradient = vec3(harness_published_cases[b + 4], harness_published_cases[b + 5], harness_published_cases[b + 6]);
    vec3 plane = vec3(harness_published_cases[b + 7], harness_published_cases[b + 8], harness_published_cases[b + 9]);
    VicpPublishedVaryings v = vicp_published_vertex_program(position, s, gradient, plane, harness_published_cases[b + 10]);
    int o = 8 * gl_VertexID;
    for (int k = 0; k < 3; ++k) {
        harness_published_out[o + k] = v.distance[k];
        harness_published_out[o + 4 + k] = v.scalar[k];
    }
    harness_published_out[o + 3] = v.s;
    harness_published_out[o + 7] = 0.0;
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
#else

struct HarnessVertexCase {
    double shape[12];  // four points, x y z each
    double exact[12];
    double s[4];
    uint boundary;
    uint pad;
};
struct HarnessTet {
    double p0[3];
    double m[9];
    double det;
    double base[3];
    double me[9];
    double g[3];
    double s0;
    uint boundary;
    uint pad;
};
layout(std430, binding = 0) readonly buffer HarnessCases { HarnessVertexCase harness_cases[]; };
layout(std430, binding = 1) writeonly buffer HarnessTets { HarnessTet harness_tets[]; };

void main()
{
    HarnessVertexCase c = harness_cases[gl_VertexID];
    dvec3 shape[4], exact[4];
    double s[4];
    for (int i = 0; i < 4; ++i) {
        shape[i] = dvec3(c.shape[3 * i], c.shape[3 * i + 1], c.shape[3 * i + 2]);
        exact[i] = dvec3(c.exact[3 * i], c.exact[3 * i + 1], c.exact[3 * i + 2]);
        s[i] = c.s[i];
    }
    VicpTet t = vicp_tet_constants(shape, exact, s, c.boundary);
    HarnessTet o;
    for (int j = 0; j < 3; ++j) {
        o.p0[j] = t.p0[j];
        o.base[j] = t.base[j];
        o.g[j] = t.g[j];
        for (int i = 0; i < 3; ++i) {
            o.m[3 * i + j] = t.m[i][j];
            o.me[3 * i + j] = t.me[i][j];
        }
    }
    o.det = t.det;
    o.s0 = t.s0;
    o.boundary = t.boundary;
    o.pad = 0u;
    harness_tets[gl_VertexID] = o;
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
#endif
