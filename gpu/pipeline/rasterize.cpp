// llvmpipe's triangle rasterization (Mesa 22.3), emulated. Every rule below names the Mesa source file and function
// it mirrors; docs/rasterizer.md has the whole story and the experiments that confirm it.
#include "gpu/pipeline/rasterize.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "gpu/pipeline/llvmpipe_cpu.h"
#include "gpu/pipeline/texture_sampling.h"  // x86_cvt_rne

namespace uvr::gpu {

namespace {

// The emulation computes the edge functions exactly in int64 (see setup_triangle). That needs the snapped
// coordinates within +-2^29 fixed units (window coordinates within about +-2.1 million pixels): position differences
// then stay below 2^30, the area and the edge constants below 2^62. llvmpipe itself holds position differences and
// dcdx << 8 in int32 and would wrap much earlier (edges longer than 2^23 fixed units = 32768 pixels), but it never
// sees such triangles: the draw module clips x and y to the viewport first (no guard band outside the "linear" mode),
// and the largest viewport is 16384 pixels. Beyond this bound the emulation reports Facing::none.
constexpr int64_t kMaxFixed = int64_t(1) << 29;

// Framebuffer sides are limited like GL's (16384 for llvmpipe); 2^15 keeps 256 * dcdx * px below 2^54.
constexpr int kMaxSide = 1 << 15;

// Floor of n / d for d > 0 (C++ division truncates towards zero).
int64_t floor_div(int64_t n, int64_t d)
{
    const int64_t q = n / d;
    return (n % d != 0 && n < 0) ? q - 1 : q;
}

// Arithmetic shift right by FIXED_ORDER as llvmpipe writes it (">> FIXED_ORDER" on a signed int): floor division by
// 256, also for negative values.
int64_t fixed_floor(int64_t v) { return floor_div(v, kFixedOne); }

}  // namespace

ViewportArithmetic host_viewport_arithmetic()
{
    // gallivm (lp_bld_misc.cpp) hands LLVM "+fma" when Mesa's util_cpu_caps has FMA (llvmpipe_cpu.h: CPUID, then the
    // environment's overrides); LLVM lowers llvm.fmuladd to vfmadd then and to vmulps + vaddps otherwise.
    return llvmpipe_cpu_caps().fma ? ViewportArithmetic::fused : ViewportArithmetic::separate;
}

WindowCoord viewport_transform(const float clip[4], const Framebuffer& fb, ViewportArithmetic arith)
{
    // The viewport state for glViewport(0, 0, width, height) (main/viewport.c _mesa_get_viewport_xform, float32):
    // scale = 0.5f * size, translate = 0.5f * size + origin. For a window buffer st_atom_viewport.c negates scale[1]
    // and sets translate[1] = fb_height - translate[1]. For integer sizes below 2^24 all of these are exact.
    const float half_w = 0.5f * float(fb.width);
    const float half_h = 0.5f * float(fb.height);
    const float scale_x = half_w, trans_x = half_w + 0.0f;
    float scale_y = half_h, trans_y = half_h + 0.0f;
    if (fb.target == RenderTarget::window) {
        scale_y = -scale_y;
        trans_y = float(fb.height) - trans_y;
    }

    // draw_llvm.c generate_viewport: out3 = 1.0 / w (LLVMBuildFDiv, a correctly rounded division: gallivm sets no
    // fast-math flags that would allow a reciprocal estimate), then per component out = x * out3 (LLVMBuildFMul) and
    // out = lp_build_fmuladd(out, scale, trans).
    const float oow = 1.0f / clip[3];
    const float xn = clip[0] * oow;
    const float yn = clip[1] * oow;
    WindowCoord w;
    if (arith == ViewportArithmetic::fused) {
        w.x = std::fma(xn, scale_x, trans_x);
        w.y = std::fma(yn, scale_y, trans_y);
    } else {
        // Two roundings; the project compiles with -ffp-contract=off, so the compiler does not fuse these either.
        const float px = xn * scale_x;
        const float py = yn * scale_y;
        w.x = px + trans_x;
        w.y = py + trans_y;
    }
    return w;
}

int32_t snap_to_fixed(float v)
{
    // lp_setup_tri.c calc_fixed_position (the x86 SSE branch, which Debian's amd64 build compiles): _mm_sub_ps by
    // pixel_offset, _mm_mul_ps by (float)FIXED_ONE, _mm_cvtps_epi32. pixel_offset is 0.5f: st_atom_rasterizer.c sets
    // half_pixel_center = 1 for GL, and lp_setup.c lp_setup_bind_rasterizer turns that into 0.5f (0 only under
    // multisampling). Subtracting 0.5 puts pixel centres on integer multiples of 256. Both operations are float32;
    // the multiplication by 256 is exact unless it overflows. cvtps rounds with the MXCSR mode, round to nearest even
    // by default (the draw module only sets DAZ/FTZ, not the rounding mode); the scalar subpixel_snap() with
    // util_iround, which rounds half away from zero, is only the fallback for non-SSE builds.
    return x86_cvt_rne((v - 0.5f) * float(kFixedOne));  // NaN and overflow give 0x80000000, as cvtps does
}

namespace {

// Fixed-point positions (calc_fixed_position). int32 in llvmpipe; int64 here so the products below cannot
// overflow (see kMaxFixed). False when a position lies beyond kMaxFixed.
bool fixed_positions(const WindowCoord v[3], int64_t x[3], int64_t y[3])
{
    for (int i = 0; i < 3; ++i) {
        x[i] = snap_to_fixed(v[i].x);
        y[i] = snap_to_fixed(v[i].y);
        if (std::llabs(x[i]) > kMaxFixed || std::llabs(y[i]) > kMaxFixed) return false;
    }
    return true;
}

// The signed area in fixed point (calc_fixed_position): area = dx01 * dy20 - dx20 * dy01, products of int32
// differences taken in 64 bits (IMUL64). It decides culling and facing; the float area plays no part, so a sliver
// that snaps flat is dropped and one that snaps inverted changes its facing.
int64_t fixed_area(const int64_t x[3], const int64_t y[3])
{
    const int64_t dx01 = x[0] - x[1], dy01 = y[0] - y[1];
    const int64_t dx20 = x[2] - x[0], dy20 = y[2] - y[0];
    return dx01 * dy20 - dx20 * dy01;
}

// do_triangle_ccw, the plane setup (the SSE branch computes the same values as the scalar one written out there):
// for the edge from vertex i to vertex i + 1
//     dcdx = y[i] - y[i+1],  dcdy = x[i] - x[i+1],  c = dcdx * x[i] - dcdy * y[i]   (64-bit products),
// and the pixel at fixed position (X, Y) = 256 * (px, py) is inside the edge when
//     c + dcdy * Y - dcdx * X > 0
// (lp_rast_tri_tmp.h tests the sign bit of c - 1 + ..., i.e. >= 1). The fill convention turns "> 0" into ">= 0"
// for the edges that own their boundary by adding 1 to c (c_dec in the SSE code):
//   - dcdx < 0 (y increases along the edge of a ccw triangle: the interior lies at larger x): a left edge, in for
//     both conventions;
//   - dcdx == 0 (a horizontal edge): with bottom_edge_rule == 0 the edge with dcdy > 0, whose interior lies at
//     larger y ("top" in Gallium's y-down naming); with bottom_edge_rule == 1 the edge with dcdy < 0, whose
//     interior lies at smaller y.
// In GL terms both targets thus own left edges and the edges with the interior above them (GL y up): an FBO keeps
// GL's y and includes the smaller-y edge; a window buffer flips y and includes the larger-y edge of setup space,
// which is again the lower one on screen.
void edge_planes(const int64_t x[3], const int64_t y[3], bool bottom_edge_rule, TriangleSetup& s)
{
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        s.dcdx[i] = y[i] - y[j];
        s.dcdy[i] = x[i] - x[j];
        s.c[i] = s.dcdx[i] * x[i] - s.dcdy[i] * y[i];
        if (s.dcdx[i] < 0)
            ++s.c[i];
        else if (s.dcdx[i] == 0 && (bottom_edge_rule ? s.dcdy[i] < 0 : s.dcdy[i] > 0))
            ++s.c[i];
    }
}

// Bounding box in pixels (do_triangle_ccw): x0 inclusive, x1 = (max - 1) >> FIXED_ORDER; in y the same, shifted by
// adj = bottom_edge_rule so that the row owned by the included horizontal edge is inside. The covered pixels are
// exactly the bounding box's pixels that pass the three edge tests: the fill rule never covers a pixel whose centre
// has the triangle's largest x (or the excluded extreme y), and tiles and 4x4 / 16x16 stamps are only an
// acceleration whose trivial accept/reject tests are conservative (lp_setup_bin_triangle, lp_rast_tri_tmp.h).
// Outside the framebuffer nothing is drawn: draw_regions is the framebuffer (no scissor), pixels left of or below
// 0 are never visited, and scissor planes cut off the rest (lp_setup_add_scissor_planes).
void bounding_box(const int64_t x[3], const int64_t y[3], bool bottom_edge_rule, const Framebuffer& fb,
                  TriangleSetup& s)
{
    const int64_t adj = bottom_edge_rule ? 1 : 0;
    const int64_t bx0 = fixed_floor(std::min({x[0], x[1], x[2]}));
    const int64_t bx1 = fixed_floor(std::max({x[0], x[1], x[2]}) - 1);
    const int64_t by0 = fixed_floor(std::min({y[0], y[1], y[2]}) + adj);
    const int64_t by1 = fixed_floor(std::max({y[0], y[1], y[2]}) - 1 + adj);
    s.x0 = int(std::max<int64_t>(bx0, 0));
    s.y0 = int(std::max<int64_t>(by0, 0));
    s.x1 = int(std::min<int64_t>(bx1, fb.width - 1));
    s.y1 = int(std::min<int64_t>(by1, fb.height - 1));
}

}  // namespace

TriangleSetup setup_triangle(const WindowCoord v[3], const Framebuffer& fb)
{
    TriangleSetup s;
    if (fb.width <= 0 || fb.height <= 0 || fb.width > kMaxSide || fb.height > kMaxSide) return s;

    int64_t x[3], y[3];
    if (!fixed_positions(v, x, y)) return s;

    const int64_t area = fixed_area(x, y);
    if (area == 0) return s;  // triangle_both: neither ccw nor cw, nothing is binned

    // area > 0 is what llvmpipe calls counter-clockwise: counter-clockwise with y pointing down, i.e. clockwise in a
    // y-up frame. In an FBO setup space is GL's y-up window space, and st_atom_rasterizer.c flips front_ccw for
    // Y_0_BOTTOM, so area > 0 is a back face; in a window buffer setup space has y down and area > 0 is GL's
    // counter-clockwise, a front face. With GL_CCW front faces, "front" is therefore counter-clockwise in GL window
    // coordinates for both targets.
    const bool llvmpipe_ccw = area > 0;
    const bool y_down = fb.target == RenderTarget::window;
    s.facing = (llvmpipe_ccw == y_down) ? Facing::front : Facing::back;

    // triangle_both: a clockwise triangle is turned counter-clockwise by swapping vertices 0 and 1
    // (rotate_fixed_position_01, since flatshade_first is false under GL's default last-vertex convention). The edges
    // are then the same three lines traversed the other way, so the covered set does not depend on the input order.
    s.swap01 = !llvmpipe_ccw;
    if (!llvmpipe_ccw) {
        std::swap(x[0], x[1]);
        std::swap(y[0], y[1]);
    }

    // pipe_rasterizer_state.bottom_edge_rule: 1 for a window buffer (Y_0_TOP), 0 for an FBO (st_atom_rasterizer.c).
    const bool bottom_edge_rule = y_down;

    edge_planes(x, y, bottom_edge_rule, s);
    bounding_box(x, y, bottom_edge_rule, fb, s);
    return s;
}

bool covers(const TriangleSetup& s, int px, int py)
{
    if (s.facing == Facing::none) return false;
    for (int i = 0; i < 3; ++i) {
        // lp_rast_tri_tmp.h: c at the tile origin is plane.c + dcdy * y - dcdx * x with dcdx, dcdy scaled by
        // FIXED_ONE; a pixel is in when c - 1 >= 0. llvmpipe evaluates the low bits in int32 after shifting out the
        // FIXED_ORDER bits that every step leaves unchanged; that is exact (the comment in lp_rast_tri_tmp.h), so the
        // direct 64-bit evaluation gives the same signs.
        const int64_t e = s.c[i] + kFixedOne * (s.dcdy[i] * py - s.dcdx[i] * px);
        if (e <= 0) return false;
    }
    return true;
}

void row_span(const TriangleSetup& s, int py, int& first, int& last)
{
    first = 0;
    last = -1;
    if (s.empty() || py < s.y0 || py > s.y1) return;
    int64_t lo = s.x0, hi = s.x1;
    for (int i = 0; i < 3; ++i) {
        // Edge i at row py: e(px) = a - d * px with a = c + 256 * dcdy * py and d = 256 * dcdx; the pixel is in when
        // e(px) >= 1, i.e. d * px <= a - 1.
        const int64_t a = s.c[i] + kFixedOne * s.dcdy[i] * py;
        const int64_t d = kFixedOne * s.dcdx[i];
        if (d == 0) {
            if (a <= 0) return;                         // a horizontal edge with the row outside it
        } else if (d > 0) {
            hi = std::min(hi, floor_div(a - 1, d));     // px <= floor((a - 1) / d)
        } else {
            lo = std::max(lo, -floor_div(a - 1, -d));   // px >= ceil((1 - a) / -d) = -floor((a - 1) / -d)
        }
        if (lo > hi) return;
    }
    first = int(lo);
    last = int(hi);
}

bool may_cover_pixel(const WindowCoord v[3])
{
    int64_t x[3], y[3];
    for (int i = 0; i < 3; ++i) {
        x[i] = snap_to_fixed(v[i].x);
        y[i] = snap_to_fixed(v[i].y);
        if (x[i] == INT32_MIN || y[i] == INT32_MIN) return true;  // NaN or out of range: left to setup_triangle
    }
    // Pixel centres are the multiples of kFixedOne (snap_to_fixed); the arithmetic shift is a floor division.
    const auto centre_within = [](int64_t lo, int64_t hi) { return (hi >> kFixedOrder) << kFixedOrder >= lo; };
    return centre_within(std::min({x[0], x[1], x[2]}), std::max({x[0], x[1], x[2]})) &&
           centre_within(std::min({y[0], y[1], y[2]}), std::max({y[0], y[1], y[2]}));
}

bool covers_any_pixel(const TriangleSetup& s)
{
    if (s.empty()) return false;
    // Most such triangles are a few pixels wide: their pixels tested one by one (multiplications) cost less than
    // row_span's 64-bit divisions; 16 is llvmpipe's own small-triangle block (4 x 4).
    if (int64_t(s.x1 - s.x0 + 1) * int64_t(s.y1 - s.y0 + 1) <= 16) {
        for (int py = s.y0; py <= s.y1; ++py)
            for (int px = s.x0; px <= s.x1; ++px)
                if (covers(s, px, py)) return true;
        return false;
    }
    for (int py = s.y0; py <= s.y1; ++py) {
        int first = 0, last = -1;
        row_span(s, py, first, last);
        if (first <= last) return true;
    }
    return false;
}

}  // namespace uvr::gpu
