// Triangle rasterization as llvmpipe (Mesa 22.3, the OSMesa of Debian 12) performs it, so that the emulated pipeline
// covers exactly the pixels a GL run covers. Input: clip coordinates (viewport_transform) or setup-space window
// coordinates (WindowCoord) and a Framebuffer. Output: the covered pixels in GL window coordinates (row from the
// bottom; spec_row() gives docs/spec.md §2's row) and the facing, from the fixed-point area.
// Twins: none in shaders/ (fixed function): the GL counterpart is llvmpipe's own rasterizer, and
// tests/test_rasterize.cpp keeps OSMesa's coverage of 32 triangles.
// Derivation: docs/rasterizer.md lists the rules, the Mesa sources they come from, how they were checked against
// OSMesa, and what stays open; its "The stages, coordinates, and what is not emulated" says what setup space is.
#pragma once

#include <cstddef>
#include <cstdint>
#include "reference/choice.h"

namespace uvr::gpu {

// llvmpipe's sub-pixel precision (lp_rast.h: FIXED_ORDER 8, FIXED_ONE 256): vertices snap to 1/256 pixel.
inline constexpr int kFixedOrder = 8;
inline constexpr int32_t kFixedOne = 1 << kFixedOrder;

// Which colour buffer the GL backend draws into. Mesa's state tracker sets up the two differently:
// - fbo: a framebuffer object. Gallium orientation Y_0_BOTTOM: no viewport flip (st_atom_viewport.c), and
//   pipe_rasterizer_state.bottom_edge_rule = 0 (st_atom_rasterizer.c). Setup space = GL window coordinates.
// - window: the buffer given to OSMesaMakeCurrent. Y_0_TOP: the viewport is flipped (scale[1] = -h/2,
//   translate[1] = fb_height - translate[1]) and bottom_edge_rule = 1. Setup space has y pointing down.
// Both give the same fill rule in GL terms (left and bottom edges are in, see rasterize_triangle), but the float
// arithmetic of the flipped viewport rounds differently, so the covered pixels can differ at exact ties.
enum class RenderTarget { fbo, window };

// How the draw module's JIT code evaluates window = (clip / w) * scale + translate. Mesa 22.3 builds it with
// lp_build_fmuladd (llvm.fmuladd), which LLVM fuses into one FMA instruction on a CPU that has FMA3 and evaluates as
// a multiply and an add otherwise (docs/rasterizer.md).
enum class ViewportArithmetic { fused, separate };

// What llvmpipe uses on the CPU this runs on (FMA3 present: fused).
ViewportArithmetic host_viewport_arithmetic();

// A vertex position in setup space: float32 window coordinates in pixels (see the header comment and RenderTarget).
struct WindowCoord {
    float x = 0.0f, y = 0.0f;
};

// A framebuffer of width x height pixels of the given kind. The draw region is the whole framebuffer (no scissor).
struct Framebuffer {
    int width = 0;
    int height = 0;
    RenderTarget target = RenderTarget::fbo;
};

// Clip coordinates (x, y, z, w) to setup-space window coordinates for a glViewport(0, 0, width, height), emulating
// draw_llvm.c generate_viewport: oow = 1.0f / w (an IEEE division), then x * oow, then (x * oow) * scale + translate,
// fused or not. All float32. Only meaningful for vertices that draw does not clip (|x|, |y|, |z| <= w).
WindowCoord viewport_transform(const float clip[4], const Framebuffer& fb,
                               ViewportArithmetic arith = host_viewport_arithmetic());

// A setup-space coordinate snapped to llvmpipe's fixed point, as calc_fixed_position does it with SSE:
// (v - 0.5f) * 256.0f in float32, then _mm_cvtps_epi32, i.e. rounded to nearest, ties to even; a NaN or a value
// outside the int32 range gives INT32_MIN (the "integer indefinite" of cvtps). Integer value k means the window
// coordinate k / 256 + 0.5, so pixel i's centre is at fixed 256 * i.
int32_t snap_to_fixed(float v);

// Which side of a triangle faces the viewer, from the sign of llvmpipe's fixed-point area (not the float one): front
// means counter-clockwise in GL window coordinates (glFrontFace(GL_CCW), the default). A triangle whose snapped area is
// zero is culled by llvmpipe whatever its float area (Facing::none) and covers nothing.
enum class Facing { none, front, back };

// The edge functions of one triangle, as lp_setup_tri.c do_triangle_ccw leaves them in struct lp_rast_plane.
// Pixel (px, py) of setup space is covered iff for every edge i
//     c[i] + kFixedOne * (dcdy[i] * py - dcdx[i] * px) > 0,
// where c already carries the fill-rule bias. dcdx and dcdy are kept unscaled here (llvmpipe stores them << 8).
struct TriangleSetup {
    Facing facing = Facing::none;
    int64_t c[3] = {0, 0, 0};
    int64_t dcdx[3] = {0, 0, 0};
    int64_t dcdy[3] = {0, 0, 0};
    // llvmpipe's bounding box in setup-space pixels (inclusive), clipped to the framebuffer; empty when x0 > x1 or
    // y0 > y1. Every covered pixel lies inside it (checked by the tests against rasterize_triangle_reference).
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    // Whether llvmpipe swapped vertices 0 and 1 to make the triangle counter-clockwise in its own terms (a positive
    // fixed-point area): the order its attribute setup then sees (gpu/pipeline/interpolation.h).
    bool swap01 = false;
    bool empty() const { return facing == Facing::none || x0 > x1 || y0 > y1; }
};

TriangleSetup setup_triangle(const WindowCoord v[3], const Framebuffer& fb);

// Whether setup-space pixel (px, py) passes the three edge tests (no bounding-box or framebuffer test).
bool covers(const TriangleSetup& s, int px, int py);

// The covered columns [first, last] of setup-space row py (first > last when none), within the bounding box: the fast
// path used by rasterize_triangle. Solves each edge inequality for px with exact integer floor division.
void row_span(const TriangleSetup& s, int py, int& first, int& last);

// Whether the triangle covers at least one pixel (the union of row_span over its bounding box is not empty). A
// triangle that covers none makes no fragment: llvmpipe bins and sets it up for nothing.
bool covers_any_pixel(const TriangleSetup& s);

// Which of a frame's triangles a GL driver sends (--send, HAVS and VICP): those that make fragments (they cover a pixel
// under the rasterizer's snapped coverage; for VICP, front-facing too), or every one, as the publications do. A
// triangle that makes no fragment changes no bit of the frame; llvmpipe would set it up, bin it and (VICP's back faces)
// shade it for nothing (docs/gl-backend.md, "Triangles that cover no pixel"; docs/vicp.md, "Culling").
enum class TriangleSubmission { covered, all };
inline constexpr Choices<TriangleSubmission, 2> kTriangleSubmissions{
    {{TriangleSubmission::covered, "covered",
      "the CPU sends the triangles that make fragments: those that cover a pixel, for VICP front-facing; the same "
      "image"},
     {TriangleSubmission::all, "all", "every face, as the publications do"}}};
// A quick test before setup_triangle: false when no pixel centre lies within the bounding box of the snapped vertices,
// so that the triangle covers no pixel; true when it may (covers_any_pixel decides).
bool may_cover_pixel(const WindowCoord v[3]);

// GL row y (from the bottom) <-> docs/spec.md §2 image row (from the top).
inline int spec_row(int gl_row, int height) { return height - 1 - gl_row; }

// Visits every pixel of a width x height frame read back from GL (rows from the bottom): f(gl_index, spec_index), the
// second the same pixel's index in docs/spec.md §2 order (rows from the top). The frame drivers store their frames with
// it.
template <class F>
void for_each_gl_pixel(int width, int height, F&& f)
{
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            f(std::size_t(y) * std::size_t(width) + std::size_t(x),
              std::size_t(spec_row(y, height)) * std::size_t(width) + std::size_t(x));
}

// The GL row of setup-space row py.
inline int gl_row(int py, const Framebuffer& fb) { return fb.target == RenderTarget::window ? fb.height - 1 - py : py; }

// Calls emit(x, y) once for every covered pixel, x the column, y the GL row (from the bottom), and returns the
// triangle's facing (emit is not called for Facing::none). Vertex order does not change the covered set, only the
// facing. Rows are visited bottom-up in setup space, columns left to right; the order does not matter to a GL result
// because one triangle covers a pixel at most once and llvmpipe keeps triangle order per pixel.
//
// The fill rule in GL terms (both targets): a pixel centre exactly on an edge is covered when the triangle's interior
// lies to the right of a non-horizontal edge (a "left" edge) or above a horizontal edge (a "bottom" edge, GL y up), and
// not otherwise. For a vertex exactly at a pixel centre this means: covered iff a point moved right by e and up by e*e
// (e -> 0) lies inside.
template <class Emit>
Facing rasterize_triangle(const WindowCoord v[3], const Framebuffer& fb, Emit&& emit)
{
    const TriangleSetup s = setup_triangle(v, fb);
    if (s.empty()) return s.facing;
    for (int py = s.y0; py <= s.y1; ++py) {
        int first = 0, last = -1;
        row_span(s, py, first, last);
        const int y = gl_row(py, fb);
        for (int px = first; px <= last; ++px) emit(px, y);
    }
    return s.facing;
}

// The plain scalar path: tests every pixel of the framebuffer with covers(), ignoring the bounding box. Slow; it is
// the definition rasterize_triangle is tested against, bit for bit.
template <class Emit>
Facing rasterize_triangle_reference(const WindowCoord v[3], const Framebuffer& fb, Emit&& emit)
{
    const TriangleSetup s = setup_triangle(v, fb);
    if (s.facing == Facing::none) return s.facing;
    for (int py = 0; py < fb.height; ++py)
        for (int px = 0; px < fb.width; ++px)
            if (covers(s, px, py)) emit(px, gl_row(py, fb));
    return s.facing;
}

}  // namespace uvr::gpu
