// Runs the HAVS fragment stage (havs_fragment.frag, compiled in front of this file) alone on inputs laid out per
// pixel: one test case per pixel of a full-screen pass (gpu/havs/gl_havs_harness.cpp). Exactly one of
//   HARNESS_ENTRY     havs_fragment_entry on face havs_face(case) at pixel harness_pixels[case]
//   HARNESS_KBUFFER   havs_kbuffer on the case's stored entries, framebuffer colour and incoming entry
//   HARNESS_PAPER      havs_paper_side and havs_paper_entry on the case's varyings (--interpolation gpu)
// is defined; with HARNESS_KBUFFER, HARNESS_SHADE_TABLE looks segments up in the real 3D table
// (preintegration_table.frag), otherwise havs_shade returns the case's colour from a texture, isolating the k-buffer
// logic from the table.
// Textures are read with texelFetch (no filtering: the bits as uploaded).

uniform int harness_width;  // pixels per row: case = y * harness_width + x (+ harness_base)
uniform int harness_base;

int harness_case() { return harness_base + int(gl_FragCoord.y) * harness_width + int(gl_FragCoord.x); }

#if defined(HARNESS_ENTRY)

layout(std430, binding = 1) readonly buffer HarnessPixels { ivec2 harness_pixels[]; };
layout(location = 0) out vec4 out_entry;
layout(location = 1) out uvec4 out_values;  // the double values' bits: x low, x high, distance low, distance high

vec4 havs_shade(float u_front, float u_back, float t_z, float seg_length) { return vec4(0.0); }

void main()
{
    int i = harness_case();
    out_entry = vec4(havs_fragment_entry(havs_face(i), harness_pixels[i]), 0.0, 0.0);
    dvec2 d = havs_fragment_values(havs_face(i), harness_pixels[i]);
    out_values = uvec4(unpackDouble2x32(d.x), unpackDouble2x32(d.y));
}

#elif defined(HARNESS_PAPER)

layout(binding = 0) uniform sampler2D in_varyings;  // (eye x, y, z, s)
layout(binding = 1) uniform sampler2D in_side;      // (side, corner x, y, z)
layout(location = 0) out vec4 out_paper;             // (x, distance, side, 0)

vec4 havs_shade(float u_front, float u_back, float t_z, float seg_length) { return vec4(0.0); }

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 v = texelFetch(in_varyings, p, 0);
    vec4 c = texelFetch(in_side, p, 0);
    float side = havs_paper_side(c.x, c.yzw);
    out_paper = vec4(havs_paper_entry(v.xyz, v.w, side), side, 0.0);
}

#elif defined(HARNESS_KBUFFER)

#define HARNESS_LAYERS ((HAVS_K + 1) / 2)
layout(binding = 0) uniform sampler2DArray in_entries;  // layer j: entries 2j (xy) and 2j + 1 (zw)
layout(binding = 1) uniform sampler2D in_framebuffer;
layout(binding = 2) uniform sampler2D in_incoming;      // xy: the incoming entry
layout(binding = 3) uniform sampler2D in_shade;         // the segment colour havs_shade returns
layout(location = 0) out vec4 out_framebuffer;
layout(location = 1) out vec4 out_shade_args;           // (u_front, u_back, t_z, length) of the lookup; -2: none
layout(location = 2) out vec4 out_entries[HARNESS_LAYERS];

vec4 harness_args = vec4(-2.0);

vec4 havs_shade(float u_front, float u_back, float t_z, float seg_length)
{
    harness_args = vec4(u_front, u_back, t_z, seg_length);
#if defined(HARNESS_SHADE_TABLE)
    return preintegration_lookup(u_front, u_back, t_z);
#else
    return texelFetch(in_shade, ivec2(gl_FragCoord.xy), 0);
#endif
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec2 a[HAVS_K];
    for (int j = 0; j < HARNESS_LAYERS; ++j) {
        vec4 t = texelFetch(in_entries, ivec3(p, j), 0);
        a[2 * j] = t.xy;
        if (2 * j + 1 < HAVS_K) a[2 * j + 1] = t.zw;
    }
    vec4 fb = texelFetch(in_framebuffer, p, 0);
    vec2 a0 = texelFetch(in_incoming, p, 0).xy;
    if (!havs_kbuffer(a0, a, fb)) discard;
    out_framebuffer = fb;
    out_shade_args = harness_args;
    for (int j = 0; j < HARNESS_LAYERS; ++j)
        out_entries[j] = vec4(a[2 * j], 2 * j + 1 < HAVS_K ? a[2 * j + 1] : vec2(-1.0, 0.0));
}

#endif
