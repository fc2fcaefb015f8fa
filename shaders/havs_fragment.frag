// HAVS's fragment stage (the HAVS paper, Appendix II): the GLSL twin of gpu/havs/havs_fragment.cpp (and of
// gpu/havs/havs_kbuffer.h, the k-buffer program), operation for operation.
// Read that file's header first; the comments here only say where GLSL needs care.
//
// This file holds the stage's functions, no main(): a pass appends its own main (the harness:
// havs_fragment_harness.frag), which also defines havs_shade(), the segment lookup. preintegration_table.frag is
// compiled in front of it. The prelude gpu/gl/gl_context.cpp
// puts in front carries the pass's defines,
//   HAVS_K            the number of stored entries, 1 .. (draw buffers - 1) * 2 in a real pass,
//   HAVS_DIAGNOSTICS  (optional) havs_kbuffer also updates havs_diag, the emulation's KBufferDiagnostics.
// The snapped edge functions are exact integers held in double, so no 64-bit integer extension is needed.
//
// Bit-faithfulness. Every arithmetic result is `precise`: without it a compiler may fuse a multiply and an add,
// reassociate, or rewrite `a - b < 0` as `a < b`. Measured on llvmpipe (Mesa 22.3.6): without `precise`, 13% of the
// test's double values differ from the emulation's; the float k-buffer part happens to compile unfused there
// (docs/gl-backend.md). Comparisons whose operands matter are made on precise values. The fragment values are
// computed in double (GLSL fp64: llvmpipe runs them as IEEE double operations), the k-buffer program in float, as
// the emulation does. llvmpipe runs shaders with denormals flushed (DAZ and FTZ), the emulation does not.

// ---- Per-frame constants (HavsFrameConstants) ----
uniform double havs_two_over_width, havs_two_over_height;  // gl_FragCoord -> NDC
uniform double havs_origin_x, havs_origin_y;                // orthographic ray origins; 0 under perspective
uniform float havs_threshold;                               // the opacity kill
uniform float havs_length_scale, havs_length_bias;          // the paper's sz.z and sz.w
uniform float havs_max_gap;                                 // segments longer than this contribute nothing (0: none)

// ---- Per-face constants (HavsFace), flat, from a buffer texture ----
struct HavsFace {
    double v[6];      // window coordinates of the vertices, x y each
    float q[9];       // eye-space positions of the three vertices, x y z each (float: HavsFace in havs_fragment.h)
    float inv_w[3];   // 1 / clip w
    float s[3];       // normalized scalars
    int fx[3];        // the rasterizer's snapped vertices (24.8 fixed point)
    int fy[3];
    float side;       // -1 exit, 1 interior, 16 entry face (kSideExit, kSideInterior, kSideEntry)
};

// The records: GlHavsFace of gpu/havs/gl_havs_fragment.h, havs_face_texels RGBA32UI texels a face, read with texelFetch
// (the bits as uploaded: doubles reassembled from their two words). A buffer texture, not a shader storage buffer,
// for speed: llvmpipe reads a storage buffer at an index it cannot prove uniform (gl_PrimitiveID is not, to it) one
// lane and one scalar at a time, while a texel fetch is one gather per channel; on a Blunt Fin frame the former
// 200-byte record's 50 scalar loads cost about 180 ms of 0.55 s (docs/gl-backend.md, "Speed").
layout(binding = 5) uniform usamplerBuffer havs_face_records;  // kHavsFaceUnit
const int havs_face_texels = 9;  // kHavsFaceTexels

// A record's words 2i and 2i + 1 (low word first, as the CPU's little-endian double) as a double.
double havs_record_double(uint w[4 * havs_face_texels], int i)
{
    return packDouble2x32(uvec2(w[2 * i], w[2 * i + 1]));
}

HavsFace havs_face(int id)
{
    uint w[4 * havs_face_texels];
    for (int t = 0; t < havs_face_texels; ++t) {
        uvec4 texel = texelFetch(havs_face_records, havs_face_texels * id + t);
        w[4 * t] = texel.x;
        w[4 * t + 1] = texel.y;
        w[4 * t + 2] = texel.z;
        w[4 * t + 3] = texel.w;
    }
    // Word offsets: v 0, q 12, inv_w 21, s 24, fx 27, fy 30, side 33 (the static_assert on GlHavsFace).
    HavsFace f;
    for (int i = 0; i < 6; ++i) f.v[i] = havs_record_double(w, i);
    for (int i = 0; i < 9; ++i) f.q[i] = uintBitsToFloat(w[12 + i]);
    for (int i = 0; i < 3; ++i) f.inv_w[i] = uintBitsToFloat(w[21 + i]);
    for (int i = 0; i < 3; ++i) f.s[i] = uintBitsToFloat(w[24 + i]);
    for (int i = 0; i < 3; ++i) f.fx[i] = int(w[27 + i]);
    for (int i = 0; i < 3; ++i) f.fy[i] = int(w[30 + i]);
    f.side = uintBitsToFloat(w[33]);
    return f;
}

// kOutsideTolerance of gpu/havs/havs_fragment.h.
const double havs_outside_tolerance = 0.1lf;

// kSideOutside and kSideEntry of gpu/havs/havs_fragment.h: an extrapolated fragment's side (|x| in [4, 8]) and an entry
// face's (|x| in [16, 32]).
const float havs_side_outside = 4.0;
const float havs_side_entry = 16.0;

// The snapped triangle's edge function from vertex a to vertex b at the fixed-point pixel centre (cx, cy), as the
// emulation's lambda `edge`: integers held in double, every operation exact (kSnappedEdgeBits in havs_fragment.h).
double havs_snapped_edge(HavsFace f, int a, int b, double cx, double cy)
{
    precise double e = (double(f.fx[b]) - double(f.fx[a])) * (cy - double(f.fy[a])) -
                       (double(f.fy[b]) - double(f.fy[a])) * (cx - double(f.fx[a]));
    return e;
}

// The fragment values at window pixel `pix` (gl_FragCoord.xy = pix + 0.5) in double, before the entry's rounding:
// (side * (1 + s), distance). The stage harness reads them too, since rounding to float hides most double-level
// differences.
dvec2 havs_fragment_values(HavsFace f, ivec2 pix)
{
    precise double fx = double(pix.x) + 0.5lf;
    precise double fy = double(pix.y) + 0.5lf;
    precise double e0 = (f.v[4] - f.v[2]) * (fy - f.v[3]) - (f.v[5] - f.v[3]) * (fx - f.v[2]);
    precise double e1 = (f.v[0] - f.v[4]) * (fy - f.v[5]) - (f.v[1] - f.v[5]) * (fx - f.v[4]);
    precise double e2 = (f.v[2] - f.v[0]) * (fy - f.v[1]) - (f.v[3] - f.v[1]) * (fx - f.v[0]);
    precise double sum = (e0 + e1) + e2;
    precise double lim = -havs_outside_tolerance * sum;
    precise bool positive = sum > 0.0lf;
    precise bool inside = positive ? (e0 >= lim && e1 >= lim && e2 >= lim) : (e0 <= lim && e1 <= lim && e2 <= lim);
    precise bool outside = positive ? (e0 < 0.0lf || e1 < 0.0lf || e2 < 0.0lf) : (e0 > 0.0lf || e1 > 0.0lf || e2 > 0.0lf);
    if (!inside) {
        // Covered only because of snapping: the snapped triangle's exact edge functions.
        precise double cx = double(pix.x) * 256.0lf;
        precise double cy = double(pix.y) * 256.0lf;
        e0 = havs_snapped_edge(f, 1, 2, cx, cy);
        e1 = havs_snapped_edge(f, 2, 0, cx, cy);
        e2 = havs_snapped_edge(f, 0, 1, cx, cy);
    }
    precise double w0 = e0 * double(f.inv_w[0]);
    precise double w1 = e1 * double(f.inv_w[1]);
    precise double w2 = e2 * double(f.inv_w[2]);
    precise double inv_sum = 1.0lf / ((w0 + w1) + w2);
    precise double l0 = w0 * inv_sum;
    precise double l1 = w1 * inv_sum;
    precise double l2 = w2 * inv_sum;
    precise double px = (l0 * double(f.q[0]) + l1 * double(f.q[3])) + l2 * double(f.q[6]);
    precise double py = (l0 * double(f.q[1]) + l1 * double(f.q[4])) + l2 * double(f.q[7]);
    precise double pz = (l0 * double(f.q[2]) + l1 * double(f.q[5])) + l2 * double(f.q[8]);
    precise double ndc_x = fx * havs_two_over_width - 1.0lf;
    precise double ndc_y = fy * havs_two_over_height - 1.0lf;
    precise double dx = px - ndc_x * havs_origin_x;
    precise double dy = py - ndc_y * havs_origin_y;
    precise double distance = sqrt((dx * dx + dy * dy) + pz * pz);
    precise double s_raw = (l0 * double(f.s[0]) + l1 * double(f.s[1])) + l2 * double(f.s[2]);
    // Clamped to [0, 1] before encoding (a NaN stays NaN, as in the emulation): see havs_fragment_values.
    precise double s = s_raw < 0.0lf ? 0.0lf : s_raw > 1.0lf ? 1.0lf : s_raw;
    precise double side = f.side == 1.0 && outside ? double(havs_side_outside) : double(f.side);
    precise double x = side * (1.0lf + s);
    return dvec2(x, distance);
}

// havs_paper_entry (--interpolation gpu): the paper's fragment values from the interpolated varyings, float32: the
// distance by DP3, RSQ, MUL (the dot product written in the order llvmpipe's lowering of dot() gives it, every result
// precise), or -e.z under an orthographic view; the entry side * (1 + s), s clamped as above.
uniform int havs_orthographic;

// havs_paper_side: an interior face's fragment whose pixel centre lies outside its triangle (a corner weight below 0:
// covered through snapping) takes the side kSideOutside, as havs_fragment_values gives it.
float havs_paper_side(float side, vec3 corner)
{
    bool outside = corner.x < 0.0 || corner.y < 0.0 || corner.z < 0.0;
    return side == 1.0 && outside ? havs_side_outside : side;
}

vec2 havs_paper_entry(vec3 e, float s_in, float side)
{
    precise float distance;
    if (havs_orthographic != 0) {
        distance = -e.z;
    } else {
        precise float zz = e.z * e.z;
        precise float yy = e.y * e.y;
        precise float xx = e.x * e.x;
        precise float t = (zz + yy) + xx;
        precise float rsq = inversesqrt(t);
        distance = t * rsq;
    }
#ifdef HAVS_PAPER_ENTRIES
    return vec2(s_in, distance);  // --entries paper: the interpolated scalar itself (MOV a0.x, v.x)
#else
    precise float s = s_in < 0.0 ? 0.0 : s_in > 1.0 ? 1.0 : s_in;
    precise float one_plus_s = 1.0 + s;
    precise float x = side * one_plus_s;
    return vec2(x, distance);
#endif
}

// havs_fragment_entry: the incoming fragment's entry as the k-buffer stores it, float32.
vec2 havs_fragment_entry(HavsFace f, ivec2 pix)
{
    dvec2 d = havs_fragment_values(f, pix);
    return vec2(float(d.x), float(d.y));
}

// What the segment contributes: each pass defines it (preintegration_lookup in a real pass; the harness records its
// arguments and may return a given colour instead).
vec4 havs_shade(float u_front, float u_back, float t_z, float seg_length);


// The flush fragment's distance: +inf, or with --entries paper 2^60, the distance the paper's program computes for the
// ARB witness's flush quads (kPaperFlushFragment); a real entry lies nearer.
// (Macros, not constants: a call of uintBitsToFloat is no constant expression to every compiler.)
#ifdef HAVS_PAPER_ENTRIES
#define havs_flush_distance uintBitsToFloat(0x5d800000u)
#else
#define havs_flush_distance uintBitsToFloat(0x7f800000u)
#endif
bool havs_real_entry(vec2 e) { return e.y > 0.0 && e.y < havs_flush_distance; }

// The normalized scalar of an entry: |x| - 1, or |x| * 0.25 - 1 for an entry face's.
float havs_decode_scalar(float x)
{
    precise float m = abs(x);
    precise float u = m < havs_side_outside ? m - 1.0 : m < havs_side_entry ? m * 0.25 - 1.0 : m * 0.0625 - 1.0;
    return u;
}

#ifdef HAVS_DIAGNOSTICS
// KBufferDiagnostics of the emulation, as floats (counts are exact below 2^24): fragments, most entries held at once,
// ordering errors, the last composited segment's back distance. The pass loads it before havs_kbuffer and stores it
// after.
vec4 havs_diag;
#endif

// havs_kbuffer: one run of the program on one pixel. a[] holds the k stored entries (x, y) and is overwritten with
// the k remaining ones; fb is the framebuffer colour, replaced by the composited one. Returns false when the fragment
// is killed: a[] and fb are left as they were (the frame pass writes them back unchanged; the harness discards).
bool havs_kbuffer(vec2 a0, inout vec2 a[HAVS_K], inout vec4 fb)
{
    // KIL (threshold - alpha).
    precise float kill = havs_threshold - fb.a;
    if (kill < 0.0) return false;
#ifdef HAVS_DIAGNOSTICS
    if (havs_real_entry(a0)) havs_diag.x += 1.0;
#endif
    // The selection chain: on t < 0 the running minimum stays, otherwise (ties included) the stored entry becomes
    // the minimum.
    vec2 r[HAVS_K + 1];
    r[0] = a0;
    for (int i = 1; i <= HAVS_K; ++i) {
        precise float t = r[0].y - a[i - 1].y;
        if (t < 0.0) {
            r[i] = a[i - 1];
        } else {
            r[i] = r[0];
            r[0] = a[i - 1];
        }
    }
    // The second smallest among r1..rk, and which it is (the program may mark it an exit below). Arrays are indexed
    // only by loop counters, which the compiler unrolls: a dynamic index costs llvmpipe a memory round trip per lane.
    vec2 second = r[1];
    int second_i = 1;
    for (int i = 2; i <= HAVS_K; ++i) {
        precise float t = second.y - r[i].y;
        if (!(t < 0.0)) {
            second = r[i];
            second_i = i;
        }
    }
    precise float seg_length = second.y - r[0].y;
    vec4 c = vec4(0.0);
#ifdef HAVS_PAPER_ENTRIES
    // --entries paper: the paper's CMP c, r0.x, 0.0, c alone; the scalars are the table coordinates as they are.
    precise bool nullified = r[0].x < 0.0;
    if (!nullified) {
        precise float t_z = seg_length * havs_length_scale + havs_length_bias;
        c = havs_shade(r[0].x, second.x, t_z, seg_length);
    }
    bool mark = false;
#else
    precise bool nullified = r[0].x < 0.0 || isinf(second.y) || second.x >= havs_side_entry ||
                             (havs_max_gap > 0.0 && seg_length > havs_max_gap);
    if (!nullified) {
        precise float t_z = seg_length * havs_length_scale + havs_length_bias;
        c = havs_shade(havs_decode_scalar(r[0].x), havs_decode_scalar(second.x), t_z, seg_length);
    }
    // Exact gaps: an extrapolated fragment right behind an exit is marked an exit too (havs_fragment.cpp).
    bool mark = havs_real_entry(r[0]) && r[0].x < 0.0 && havs_real_entry(second) && second.x >= havs_side_outside &&
                second.x < havs_side_entry;
#endif
#ifdef HAVS_DIAGNOSTICS
    if (havs_real_entry(r[0])) {
        if (r[0].y < havs_diag.w) havs_diag.z += 1.0;
        if (havs_real_entry(second)) havs_diag.w = max(havs_diag.w, second.y);
    }
#endif
    // Front to back: fb = c * (1 - fb.a) + fb.
    precise float one_minus_a = 1.0 - fb.a;
    precise vec4 composited = c * one_minus_a + fb;
    fb = composited;
    for (int i = 1; i <= HAVS_K; ++i) a[i - 1] = (mark && i == second_i) ? vec2(-r[i].x, r[i].y) : r[i];
#ifdef HAVS_DIAGNOSTICS
    float held = 0.0;
    for (int i = 1; i <= HAVS_K; ++i) held += havs_real_entry(r[i]) ? 1.0 : 0.0;
    havs_diag.y = max(havs_diag.y, held);
#endif
    return true;
}
