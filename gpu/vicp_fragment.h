// VICP's fragment stage (seed 003, VICP-FragmentProg), emulated operation by operation, and its GLSL twin
// shaders/vicp_fragment.frag.
//
// Fragment values, in double (GLSL fp64, IEEE operations on llvmpipe), from gl_FragCoord and the tetrahedron's flat
// constants (VicpTet, gpu/vicp_vertex.h): the pixel's ray x(t) = o + t d in the mesh's centred frame (SPEC §2: from
// the eye under perspective, from the image plane under orthographic projection; d is not normalized), the
// barycentric coordinates along it, lambda_i(t) = a_i + t b_i, and where each crosses zero, t_i = -a_i / b_i. The
// ray enters the tetrahedron where the last lambda with b_i > 0 becomes positive and leaves where the first with
// b_i < 0 reaches zero: t_in = max(0, t_i : b_i > 0), t_out = min(t_i : b_i < 0).
//
// The seed picks the exit as "the minimum of the opposite faces' distances greater than zero". The two agree in exact
// arithmetic for a pixel inside the projected face; the sign of b_i (which side of the face the ray is heading to) is
// used here instead of the sign of a rounded distance, because at a pixel next to an edge between two front faces the
// other front face's distance is zero up to rounding, and a positive rounding would end the segment at the entry.
// It also makes the values a function of the tetrahedron and the pixel only, whichever of its front faces the
// rasterizer gave the pixel to. A pixel covered only through snapping (its ray misses the tetrahedron) gets
// t_out <= t_in: a segment of no length, which contributes nothing.
//
// Snapping. The rasterizer snaps vertices to 1/256 pixel, so a pixel next to a cell's projected silhouette can be
// covered by the cell although its ray passes beside it, and the neighbour its ray does cross then does not cover it:
// with the mesh's own points the ray-clip gives the covering cell no length and the neighbour's segment is lost; at
// a grazing angle to a thin cell that is a long one (0.016 in alpha on a Blunt Fin pixel, docs/vicp.md). So the
// constants come from the points where snapping put them (vicp_setup: each point moved, at its own depth, to the ray
// through its snapped window position). The cells so moved still share their faces, a pixel covered by a cell's
// snapped projection has its ray through the moved cell, and along every ray the moved cells' segments follow one
// another without gap or overlap: VICP integrates the mesh the rasterizer drew, each point off by at most 1/512
// pixel on screen (measured: RMSE 5e-6 and largest error 5e-4 on Blunt Fin against the reference; keeping the exact
// points where the ray meets the cell and the moved ones elsewhere mixes two meshes along one ray and does worse,
// 1e-3). The view then enters the constants only through snapping.
//
// Then in float, as the GPU's k-buffer-free compositing does it: the scalars at both ends (clamped to [0, 1]) and the
// segment's length in world units rounded to float; the table coordinates with the seed's scale and bias (as HAVS);
// the lookup; front-to-back compositing into the framebuffer colour, read and written in the shader through
// GL_EXT_shader_framebuffer_fetch like HAVS's k-buffer (docs/vicp.md, "Compositing"); the opacity kill.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/havs_fragment.h"
#include "gpu/pixel_rays.h"
#include "gpu/vicp_vertex.h"

namespace uvr::gpu {

// Per-frame constants (uniforms): the pixels' rays (gpu/pixel_rays.h) relative to the mesh's centre, and the rest.
struct VicpFrameConstants : PixelRays {
    float threshold = 1.0f;                   // the opacity kill; 1 (the default for VICP) never kills
    float length_scale = 0.0f, length_bias = 0.0f;  // the seed's sz.z and sz.w (pre-integrated table)
};

// The segment a fragment integrates, in double before rounding. Distances are world units from the ray's origin.
struct VicpSegment {
    double s_front = 0.0, s_back = 0.0;  // normalized scalars at entry and exit, clamped to [0, 1]
    double t_in = 0.0, t_out = 0.0;      // distances of entry and exit
    double length = 0.0;                 // t_out - t_in (negative or 0: the ray misses the tetrahedron)
};
// A face counts as parallel to the ray when |b_i| <= kParallelFace * sum_j |b_j|. A ray lying in a face's plane (a
// pixel centre on a face seen edge-on, as on an unjittered grid seen along its axes) has b_i = 0 up to the rounding
// of a three-term dot product, ~1e-16 relative; a face at a real angle to the ray has |b_i| of the order of the
// others' (it is |m_i| |d| sin(angle), and |m_i| is the face's area over the cell's volume). 1e-12 lies far from
// both: a ray within 1e-12 radians of a face's plane stays within 1e-12 of the mesh's size from it.
inline constexpr double kParallelFace = 1e-12;

VicpSegment vicp_fragment_values(const VicpFrameConstants& fc, const VicpTet& tet, int px, int py);


// Per-pixel diagnostics: fragments that reached the program, and ordering errors: a segment that ends where the
// segment reaching farthest so far begins, or nearer (in visibility order each segment starts where the one before
// ended; a cell drawn out of order lies wholly in front of one drawn before it). Comparing with that segment's front,
// not its back, keeps the rounding of two cells' distances to their shared face from counting.
struct VicpDiagnostics {
    uint32_t fragments = 0;
    uint32_t ordering_errors = 0;
    float last_back = 0.0f, last_front = 0.0f;  // the farthest-reaching segment composited so far (bookkeeping)
};

// One run of the fragment program's float part on one pixel (`shade` as HAVS's: havs_fragment.h). Returns false when the fragment is killed (the
// framebuffer's alpha is above the threshold): nothing is written.
bool vicp_composite(const VicpFrameConstants& fc, const VicpSegment& segment, glm::vec4& framebuffer,
                    const SegmentShader& shade, VicpDiagnostics* diag);

}  // namespace uvr::gpu
