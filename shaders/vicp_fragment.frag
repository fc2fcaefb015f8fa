// VICP's fragment stage (Moreland's dissertation, VICP-FragmentProg): the GLSL twin of gpu/vicp/vicp_fragment.cpp,
// operation for operation. Read that file's header first; the comments here only say where GLSL needs care.
// vicp_tet.glsl and preintegration_table.frag are compiled in front of this file; a pass appends its own main
// (vicp.frag in the renderer, vicp_harness.frag in the stage harness), which also defines vicp_shade(), the segment's
// colour.
//
// Every arithmetic result is `precise`. The segment is computed in double (IEEE operations on llvmpipe), the
// compositing in float, as the emulation does; llvmpipe runs shaders with denormals flushed and the emulation runs
// under FlushDenormals (gpu/pipeline/denormals.h).

// ---- Per-frame constants (VicpFrameConstants) ----
uniform double vicp_two_over_width, vicp_two_over_height;
uniform dvec3 vicp_eye;
uniform dvec3 vicp_ray_ox, vicp_ray_oy;
uniform dvec3 vicp_ray_d0;
uniform dvec3 vicp_ray_dx, vicp_ray_dy;
uniform float vicp_threshold;
uniform float vicp_length_scale, vicp_length_bias;

// kParallelFace of gpu/vicp/vicp_fragment.h.
const double vicp_parallel_face = 1e-12lf;

// VicpSegment of gpu/vicp/vicp_fragment.h.
struct VicpSegment {
    double s_front, s_back;
    double t_in, t_out;
    double chord;  // its length (not `length`, which some compilers take for the method)
};

// The clamp to [0, 1] written as the emulation's ternaries (GLSL's clamp() leaves NaN handling open).
double vicp_clamp01(double s) { return s < 0.0lf ? 0.0lf : s > 1.0lf ? 1.0lf : s; }

// barycentrics_along of vicp_fragment.cpp: lambda_i(t) = a[i] + t b[i] along q + t d from the gradients m.
void vicp_barycentrics_along(dvec3 m[3], dvec3 q, dvec3 d, out double a[4], out double b[4])
{
    for (int i = 0; i < 3; ++i) {
        precise double ai = (m[i].x * q.x + m[i].y * q.y) + m[i].z * q.z;
        precise double bi = (m[i].x * d.x + m[i].y * d.y) + m[i].z * d.z;
        a[i + 1] = ai;
        b[i + 1] = bi;
    }
    precise double a0 = 1.0lf - ((a[1] + a[2]) + a[3]);
    precise double b0 = 0.0lf - ((b[1] + b[2]) + b[3]);
    a[0] = a0;
    b[0] = b0;
}

VicpSegment vicp_fragment_values(VicpTet tet, ivec2 pix)
{
    precise double ndc_x = (double(pix.x) + 0.5lf) * vicp_two_over_width - 1.0lf;
    precise double ndc_y = (double(pix.y) + 0.5lf) * vicp_two_over_height - 1.0lf;
    // The ray, relative to vertex 0.
    precise double qx = ((vicp_eye.x + ndc_x * vicp_ray_ox.x) + ndc_y * vicp_ray_oy.x) - tet.p0.x;
    precise double qy = ((vicp_eye.y + ndc_x * vicp_ray_ox.y) + ndc_y * vicp_ray_oy.y) - tet.p0.y;
    precise double qz = ((vicp_eye.z + ndc_x * vicp_ray_ox.z) + ndc_y * vicp_ray_oy.z) - tet.p0.z;
    precise double dx = (vicp_ray_d0.x + ndc_x * vicp_ray_dx.x) + ndc_y * vicp_ray_dy.x;
    precise double dy = (vicp_ray_d0.y + ndc_x * vicp_ray_dx.y) + ndc_y * vicp_ray_dy.y;
    precise double dz = (vicp_ray_d0.z + ndc_x * vicp_ray_dx.z) + ndc_y * vicp_ray_dy.z;
    // lambda_i(t) = a[i] + t * b[i], from the snapped shape's gradients; the boundary faces' from the exact cell's.
    // Arrays are indexed only by loop counters the compiler unrolls.
    double a[4], b[4];
    vicp_barycentrics_along(tet.m, dvec3(qx, qy, qz), dvec3(dx, dy, dz), a, b);
    precise double bx = qx + (tet.p0.x - tet.base.x);
    precise double by = qy + (tet.p0.y - tet.base.y);
    precise double bz = qz + (tet.p0.z - tet.base.z);
    if (tet.boundary != 0u) {
        double ae[4], be[4];
        vicp_barycentrics_along(tet.me, dvec3(bx, by, bz), dvec3(dx, dy, dz), ae, be);
        for (int i = 0; i < 4; ++i)
            if ((tet.boundary & (1u << uint(i))) != 0u) {
                a[i] = ae[i];
                b[i] = be[i];
            }
    }
    // Entry and exit (vicp_fragment.cpp); a face the ray runs along bounds nothing.
    precise double parallel = vicp_parallel_face * ((abs(b[0]) + abs(b[1])) + (abs(b[2]) + abs(b[3])));
    double t_in = 0.0lf, t_out = 1e300lf;
    for (int i = 0; i < 4; ++i) {
        if (!(abs(b[i]) > parallel)) continue;
        precise double t = -a[i] / b[i];
        if (b[i] > 0.0lf && t > t_in) t_in = t;
        if (b[i] < 0.0lf && t < t_out) t_out = t;
    }
    precise double scale = sqrt((dx * dx + dy * dy) + dz * dz);
    // The scalar along the ray, from the exact cell's field: s(t) = s0 + (g . (o - base) + t g . d).
    precise double ga = (tet.g.x * bx + tet.g.y * by) + tet.g.z * bz;
    precise double gb = (tet.g.x * dx + tet.g.y * dy) + tet.g.z * dz;
    precise double s_in = tet.s0 + (ga + t_in * gb);
    precise double s_out = tet.s0 + (ga + t_out * gb);
    VicpSegment seg;
    seg.s_front = vicp_clamp01(s_in);
    seg.s_back = vicp_clamp01(s_out);
    precise double t_in_w = t_in * scale;
    precise double t_out_w = t_out * scale;
    precise double chord = (t_out - t_in) * scale;  // not `length`: a local of that name hides the built-in
    seg.t_in = t_in_w;
    seg.t_out = t_out_w;
    seg.chord = chord;
    return seg;
}

// What the segment contributes: each pass defines it (preintegration_lookup in the renderer; the harness records its
// arguments and may return a given colour instead).
vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length);

// vicp_composite of gpu/vicp/vicp_fragment.cpp on one pixel: fb is the framebuffer colour, replaced by the composited
// one; diag is VicpDiagnostics as floats (fragments, ordering errors, last back, last front; counts exact below 2^24).
// Returns false when the fragment is killed: fb and diag are left as they were.
bool vicp_composite(VicpSegment seg, inout vec4 fb, inout vec4 diag)
{
    // KIL (threshold - alpha).
    precise float kill = vicp_threshold - fb.a;
    if (kill < 0.0) return false;
    float chord = float(seg.chord);
    vec4 c = vec4(0.0);
    if (chord > 0.0) {
        precise float t_z = chord * vicp_length_scale + vicp_length_bias;
        c = vicp_shade(float(seg.s_front), float(seg.s_back), t_z, chord);
    }
    precise float fragments = diag.x + 1.0;
    diag.x = fragments;
    if (chord > 0.0) {
        float front = float(seg.t_in), back = float(seg.t_out);
        if (back <= diag.w) {
            precise float errors = diag.y + 1.0;
            diag.y = errors;
        }
        if (back > diag.z) {
            diag.z = back;
            diag.w = front;
        }
    }
    // Front to back: fb = c * (1 - fb.a) + fb, per channel (MAD, unfused).
    precise float one_minus_a = 1.0 - fb.a;
    precise vec4 composited = c * one_minus_a + fb;
    fb = composited;
    return true;
}
