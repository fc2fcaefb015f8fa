// Runs VICP's fragment stage (vicp_fragment.frag, compiled in front of this file behind preintegration_table.frag
// and vicp_tet.glsl) alone: one case per pixel of a full-screen pass, inputs and outputs in storage buffers laid out
// as gpu/vicp/gl_vicp_harness.h's Gl* structs. Exactly one of
//   HARNESS_VALUES     vicp_fragment_values of tetrahedron harness_tets[case] at pixel harness_pixels[case]
//   HARNESS_COMPOSITE  vicp_composite of the case's segment onto its framebuffer colour and diagnostics
//   HARNESS_PUBLISHED_EXIT  vicp_published_exit (vicp_published_fragment.frag) of harness_published_varyings[2 case], [2 case + 1]
// is defined; with HARNESS_COMPOSITE, HARNESS_SHADE_TABLE looks the segment up in the real 3D table, otherwise
// vicp_shade returns the case's own colour, isolating the compositing from the table. HARNESS_NONE is the fragment
// side of the vertex harness's program, which never runs (the rasterizer discards).

uniform int harness_width;  // pixels per row: case = y * harness_width + x
uniform int harness_count;  // cases in this pass; the pixels past the last do nothing

int harness_case() { return int(gl_FragCoord.y) * harness_width + int(gl_FragCoord.x); }

#if defined(HARNESS_PUBLISHED_EXIT)

layout(std430, binding = 0) readonly buffer HarnessPublishedVaryings { vec4 harness_published_varyings[]; };  // (distance, s), (scalar, 0)
layout(std430, binding = 1) writeonly buffer HarnessPublishedExits { vec4 harness_published_exits[]; };  // (s_front, s_back, length, face)

vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length) { return vec4(0.0); }

void main()
{
    int i = harness_case();
    if (i >= harness_count) return;
    vec4 a = harness_published_varyings[2 * i], b = harness_published_varyings[2 * i + 1];
    VicpPublishedExit e = vicp_published_exit(a.xyz, b.xyz, a.w);
    harness_published_exits[i] = vec4(e.s_front, e.s_back, e.chord, float(e.face));
}

#elif defined(HARNESS_VALUES)

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
layout(std430, binding = 0) readonly buffer HarnessTets { HarnessTet harness_tets[]; };
layout(std430, binding = 1) readonly buffer HarnessPixels { ivec2 harness_pixels[]; };
layout(std430, binding = 2) writeonly buffer HarnessSegments { double harness_segments[]; };  // 5 a case

vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length) { return vec4(0.0); }

void main()
{
    int i = harness_case();
    if (i >= harness_count) return;
    HarnessTet h = harness_tets[i];
    VicpTet t;
    t.p0 = dvec3(h.p0[0], h.p0[1], h.p0[2]);
    t.base = dvec3(h.base[0], h.base[1], h.base[2]);
    t.g = dvec3(h.g[0], h.g[1], h.g[2]);
    for (int k = 0; k < 3; ++k) {
        t.m[k] = dvec3(h.m[3 * k], h.m[3 * k + 1], h.m[3 * k + 2]);
        t.me[k] = dvec3(h.me[3 * k], h.me[3 * k + 1], h.me[3 * k + 2]);
    }
    t.det = h.det;
    t.s0 = h.s0;
    t.boundary = h.boundary;
    VicpSegment s = vicp_fragment_values(t, harness_pixels[i]);
    harness_segments[5 * i] = s.s_front;
    harness_segments[5 * i + 1] = s.s_back;
    harness_segments[5 * i + 2] = s.t_in;
    harness_segments[5 * i + 3] = s.t_out;
    harness_segments[5 * i + 4] = s.chord;
}

#elif defined(HARNESS_COMPOSITE)

struct HarnessCompositeCase {
    double segment[5];  // s_front, s_back, t_in, t_out, length
    vec4 framebuffer;
    vec4 diagnostics;
    vec4 shade;         // what vicp_shade returns without HARNESS_SHADE_TABLE
};
struct HarnessCompositeResult {
    vec4 framebuffer;
    vec4 diagnostics;
    vec4 shade_args;    // (u_front, u_back, t_z, length) of the lookup; all -2 when none was made
    uint written;       // 0: killed (the pass would discard)
    uint pad[3];
};
layout(std430, binding = 0) readonly buffer HarnessCases { HarnessCompositeCase harness_cases[]; };
layout(std430, binding = 1) writeonly buffer HarnessResults { HarnessCompositeResult harness_results[]; };

vec4 harness_args = vec4(-2.0);
int harness_i = 0;

vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length)
{
    harness_args = vec4(u_front, u_back, t_z, seg_length);
#if defined(HARNESS_SHADE_TABLE)
    return preintegration_lookup(u_front, u_back, t_z);
#else
    return harness_cases[harness_i].shade;
#endif
}

void main()
{
    harness_i = harness_case();
    if (harness_i >= harness_count) return;
    HarnessCompositeCase c = harness_cases[harness_i];
    VicpSegment s;
    s.s_front = c.segment[0];
    s.s_back = c.segment[1];
    s.t_in = c.segment[2];
    s.t_out = c.segment[3];
    s.chord = c.segment[4];
    vec4 fb = c.framebuffer, diag = c.diagnostics;
    HarnessCompositeResult r;
    r.written = vicp_composite(s, fb, diag) ? 1u : 0u;
    r.framebuffer = fb;
    r.diagnostics = diag;
    r.shade_args = harness_args;
    r.pad = uint[3](0u, 0u, 0u);
    harness_results[harness_i] = r;
}

#elif defined(HARNESS_NONE)

vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length) { return vec4(0.0); }
void main() {}

#endif
