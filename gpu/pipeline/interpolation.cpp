// llvmpipe's attribute setup and interpolation (Mesa 22.3), emulated. Each step names the Mesa function it mirrors;
// every line is one IEEE float32 operation in the order LLVM receives it (gallivm sets no fast-math flags, so LLVM
// neither reassociates nor contracts; the project compiles with -ffp-contract=off, so neither does GCC here). The
// only fused operations are gallivm's explicit lp_build_fmuladd calls, fused exactly when the CPU has FMA3, as in the
// viewport transform (ViewportArithmetic). docs/interpolation.md has the sources and the measurements.
#include "gpu/pipeline/interpolation.h"

#include "gpu/pipeline/texture_sampling.h"  // host_has_fma

#include <cmath>
#include <utility>

namespace uvr::gpu {

namespace {

// lp_build_fmuladd(a, b, c) = a * b + c: llvm.fmuladd, one rounding on an FMA3 CPU, two otherwise.
float fmuladd(float a, float b, float c, ViewportArithmetic arith)
{
    if (arith == ViewportArithmetic::fused) return std::fma(a, b, c);
    const float p = a * b;
    return p + c;
}

// The half-pixel offset setup subtracts from v0 (init_args: pixel_center = 0.5 for GL's half_pixel_center without
// multisampling): a0 is then the plane's value at setup-space pixel (0, 0)'s centre, so a pixel's integer
// coordinates enter the evaluation as they are.
constexpr float kPixelCenter = 0.5f;

}  // namespace

SetupVertex setup_vertex(const float clip[4], const Framebuffer& fb, ViewportArithmetic arith)
{
    // draw_llvm.c generate_viewport: the position's w becomes oow = 1.0f / w (an FDiv), x and y the window position.
    const WindowCoord w = viewport_transform(clip, fb, arith);
    return SetupVertex{w.x, w.y, 1.0f / clip[3]};
}

AttributeSetup setup_attributes(const SetupVertex in[3], const TriangleSetup& ts)
{
    AttributeSetup s;
    // lp_setup_tri.c triangle_both: a triangle whose fixed-point area is negative reaches do_triangle_ccw, and with
    // it the JIT setup function, as (v1, v0, v2) under GL's last-vertex convention (flatshade_first = 0), so that the
    // provoking vertex v2 stays last. a0 is computed relative to setup's v0, so the order changes the rounding.
    if (ts.swap01) std::swap(s.order[0], s.order[1]);
    const SetupVertex& v0 = in[s.order[0]];
    const SetupVertex& v1 = in[s.order[1]];
    const SetupVertex& v2 = in[s.order[2]];

    // lp_state_setup.c init_args, in its order: xy0_center = v0.xy - pixel_center, dxy01 = v0.xy - v1.xy,
    // dxy20 = v2.xy - v0.xy, ef = dxy01 * (dy20, dx20), area = e - f, ooa = 1 / area (an FDiv: the reciprocal estimate
    // of lp_build_rcp is not used there), then dxy20 * ooa and dxy01 * ooa. The float area is the unsnapped one; its
    // sign may disagree with the fixed-point area of a sliver, which flips both derivatives' signs and the plane not.
    s.x0c = v0.x - kPixelCenter;
    s.y0c = v0.y - kPixelCenter;
    const float dx01 = v0.x - v1.x, dy01 = v0.y - v1.y;
    const float dx20 = v2.x - v0.x, dy20 = v2.y - v0.y;
    const float e = dx01 * dy20;
    const float f = dy01 * dx20;
    const float area = e - f;
    const float ooa = 1.0f / area;
    s.dx20_ooa = dx20 * ooa;
    s.dy20_ooa = dy20 * ooa;
    s.dx01_ooa = dx01 * ooa;
    s.dy01_ooa = dy01 * ooa;

    // The position slot's w channel: calc_coef4 on the vertices' oow as they are (slot 0 is never perspective
    // corrected).
    const float oow[3] = {in[0].oow, in[1].oow, in[2].oow};
    s.oow = attribute_plane(s, in, oow, Qualifier::noperspective);
    return s;
}

AttributePlane attribute_plane(const AttributeSetup& s, const SetupVertex in[3], const float value[3], Qualifier q)
{
    // emit_tri_coef: LP_INTERP_CONSTANT (flat) stores the provoking vertex's value as a0 (v2 under the last-vertex
    // convention, which the swap keeps last) and zero derivatives: no arithmetic, the bits as they are.
    if (q == Qualifier::flat) return AttributePlane{value[2], 0.0f, 0.0f};
    float a0v = value[s.order[0]], a1v = value[s.order[1]], a2v = value[s.order[2]];
    if (q == Qualifier::smooth) {
        // apply_perspective_corr: each vertex's value times its own oow (one FMul), before the plane.
        a0v = a0v * in[s.order[0]].oow;
        a1v = a1v * in[s.order[1]].oow;
        a2v = a2v * in[s.order[2]].oow;
    }
    // calc_coef4: da01 = a0 - a1, da20 = a2 - a0; dadx = da01 * dy20_ooa - da20 * dy01_ooa; dady = da20 * dx01_ooa -
    // da01 * dx20_ooa (the subtraction's operands in that order); a0 = a0v - (dadx * x0c + dady * y0c). The
    // derivative is da * (d * ooa), not (da * d) * ooa: init_args scales the differences by ooa once per triangle.
    const float da01 = a0v - a1v;
    const float da20 = a2v - a0v;
    const float dadx = da01 * s.dy20_ooa - da20 * s.dy01_ooa;
    const float dady = da20 * s.dx01_ooa - da01 * s.dx20_ooa;
    const float dadx_x0 = dadx * s.x0c;
    const float dady_y0 = dady * s.y0c;
    const float offset = dadx_x0 + dady_y0;
    return AttributePlane{a0v - offset, dadx, dady};
}

namespace {

#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("fma"))) void evaluate_fma3(const AttributePlane* p, int n, float x, float y, float* out)
{
    for (int i = 0; i < n; ++i) out[i] = __builtin_fmaf(p[i].dady, y, __builtin_fmaf(p[i].dadx, x, p[i].a0));
}
#endif

// lp_bld_interp.c attribs_update_simple: a = fmuladd(dady, y, fmuladd(dadx, x, a0)), x first, for n planes. The
// block's origin and the lane's offset in its 4x4 stamp add up to the pixel's integer coordinates exactly (small
// integers in float), so the value depends on the pixel alone, not on the stamp, the vector width or the thread. On an
// FMA3 host the fused path is one vfmadd each (evaluate_fma3: the portable build's std::fma is a library call, which
// cost an emulated Blunt Fin frame about 100 ms; a HAVS fragment evaluates eight planes).
void evaluate(const AttributePlane* p, int n, int px, int py, ViewportArithmetic arith, float* out)
{
    const float x = float(px), y = float(py);
#if defined(__x86_64__) || defined(__i386__)
    static const bool fma = host_has_fma();
    if (arith == ViewportArithmetic::fused && fma) {
        evaluate_fma3(p, n, x, y, out);
        return;
    }
#endif
    for (int i = 0; i < n; ++i) out[i] = fmuladd(p[i].dady, y, fmuladd(p[i].dadx, x, p[i].a0, arith), arith);
}

float evaluate(const AttributePlane& p, int px, int py, ViewportArithmetic arith)
{
    float out;
    evaluate(&p, 1, px, py, arith, &out);
    return out;
}

}  // namespace

float frag_coord_w(const AttributeSetup& s, int px, int py, ViewportArithmetic arith)
{
    // lp_build_interp_soa_update_pos_dyn: the position's w is the oow plane evaluated like any input.
    return evaluate(s.oow, px, py, arith);
}

float perspective_factor(const AttributeSetup& s, int px, int py, ViewportArithmetic arith)
{
    // attribs_update_simple: the reciprocal of the interpolated oow is lp_build_rcp, an FDiv on this path (the RCPPS
    // estimate is compiled out), computed once per pixel and shared by the perspective inputs.
    return 1.0f / frag_coord_w(s, px, py, arith);
}

void interpolate(const AttributePlane* planes, int n, Qualifier q, int px, int py, float factor,
                 ViewportArithmetic arith, float* out)
{
    if (q == Qualifier::flat) {
        for (int i = 0; i < n; ++i) out[i] = planes[i].a0;
        return;
    }
    evaluate(planes, n, px, py, arith, out);
    // Perspective: the interpolated a * w_clip times 1 / (interpolated 1 / w), an FMul (two roundings in all, not a
    // division by the interpolated oow).
    if (q == Qualifier::smooth)
        for (int i = 0; i < n; ++i) out[i] = out[i] * factor;
}

float interpolate(const AttributePlane& p, Qualifier q, int px, int py, float factor, ViewportArithmetic arith)
{
    float out;
    interpolate(&p, 1, q, px, py, factor, arith, &out);
    return out;
}

}  // namespace uvr::gpu
