// VICP's fragment stage (Moreland's dissertation, VICP-FragmentProg), emulated operation by operation:
// vicp_fragment_values (the frame's constants, the tetrahedron's flat VicpTet, the pixel -> the segment of the pixel's
// ray in the cell, in double) and vicp_composite (the segment, the framebuffer colour, a SegmentShader -> the colour
// composited front to back in float, or a kill). Twins: shaders/vicp_fragment.frag; GL uniforms
// gpu/vicp/gl_vicp_fragment.h; harness gpu/vicp/gl_vicp_harness.h. Derivation: docs/vicp.md, "The fragment values" (the
// exit by direction), "Snapping" (the constants come from the points where the rasterizer snapped them) and "The float
// part".
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/pipeline/segment.h"
#include "gpu/pipeline/pixel_rays.h"
#include "gpu/vicp/vicp_vertex.h"

namespace uvr::gpu {

// Per-frame constants (uniforms): the pixels' rays (gpu/pipeline/pixel_rays.h) relative to the mesh's centre, and the
// rest.
struct VicpFrameConstants : PixelRays {
    float threshold = 1.0f;                   // the opacity kill; 1 (the default for VICP) never kills
    float length_scale = 0.0f, length_bias = 0.0f;  // the published sz.z and sz.w (pre-integrated table)
};

// The segment a fragment integrates, in double before rounding. Distances are world units from the ray's origin.
struct VicpSegment {
    double s_front = 0.0, s_back = 0.0;  // normalized scalars at entry and exit, clamped to [0, 1]
    double t_in = 0.0, t_out = 0.0;      // distances of entry and exit
    double length = 0.0;                 // t_out - t_in (negative or 0: the ray misses the tetrahedron)
    int exit_face = -1;                  // the vertex whose opposite face is the exit, -1 for none (emulation only:
                                         // the published wrong-exit diagnostic, gpu/vicp/vicp.cpp)
    // The ray runs parallel to a face and outside its plane (kParallelOutside), so it misses the cell whatever the
    // other faces say. Only --coverage exact reads it (emulation only): the rasterizer never covers such a pixel.
    bool misses = false;
};
// A face counts as parallel to the ray when |b_i| <= kParallelFace * sum_j |b_j|. A ray lying in a face's plane (a
// pixel centre on a face seen edge-on, as on an unjittered grid seen along its axes) has b_i = 0 up to the rounding
// of a three-term dot product, ~1e-16 relative; a face at a real angle to the ray has |b_i| of the order of the
// others' (it is |m_i| |d| sin(angle), and |m_i| is the face's area over the cell's volume). 1e-12 lies far from
// both: a ray within 1e-12 radians of a face's plane stays within 1e-12 of the mesh's size from it.
inline constexpr double kParallelFace = 1e-12;
// A ray parallel to face i keeps lambda_i = a_i all along. It lies outside the face's plane when a_i <
// -kParallelOutside
// * sum_j |a_j|: a ray in the plane has a_i at the rounding of the dot products that make the a's, ~1e-16 of their
// size, while a pixel beside the plane is a pixel's width over the cell's size away (1e-4 and more).
inline constexpr double kParallelOutside = 1e-12;

VicpSegment vicp_fragment_values(const VicpFrameConstants& fc, const VicpTet& tet, int px, int py);
// The exit parameter vicp_fragment_values starts from: it stays there when no face bounds the ray's way out.
inline constexpr double kVicpNoExit = 1e300;


// Per-pixel diagnostics: fragments that reached the program, and ordering errors: a segment that ends where the
// segment reaching farthest so far begins, or nearer (in visibility order each segment starts where the one before
// ended; a cell drawn out of order lies wholly in front of one drawn before it). Comparing with that segment's front,
// not its back, keeps the rounding of two cells' distances to their shared face from counting.
struct VicpDiagnostics {
    uint32_t fragments = 0;
    uint32_t ordering_errors = 0;
    float last_back = 0.0f, last_front = 0.0f;  // the farthest-reaching segment composited so far (bookkeeping)
};

// One run of the fragment program's float part on one pixel (`shade` as HAVS's: havs_fragment.h; a SegmentShader or,
// without std::function's call, the table's TableSegmentShader). Returns false when the fragment is killed (the
// framebuffer's alpha is above the threshold): nothing is written.
template <class Shade>
bool vicp_composite(const VicpFrameConstants& fc, const VicpSegment& seg, glm::vec4& fb, const Shade& shade,
                    VicpDiagnostics* diag)
{
    // KIL (threshold - alpha), as HAVS.
    if (fc.threshold - fb.a < 0.0f) return false;
    const float length = float(seg.length);
    glm::vec4 c(0.0f);
    if (length > 0.0f) {
        const float t_z = length * fc.length_scale + fc.length_bias;
        c = shade(float(seg.s_front), float(seg.s_back), t_z, length);
    }
    if (diag) {
        ++diag->fragments;
        if (length > 0.0f) {
            const float front = float(seg.t_in), back = float(seg.t_out);
            if (back <= diag->last_front) ++diag->ordering_errors;
            if (back > diag->last_back) {
                diag->last_back = back;
                diag->last_front = front;
            }
        }
    }
    // Front to back: fb = c * (1 - fb.a) + fb, per channel (MAD, unfused).
    const float one_minus_a = 1.0f - fb.a;
    fb = glm::vec4(c.r * one_minus_a + fb.r, c.g * one_minus_a + fb.g, c.b * one_minus_a + fb.b,
                   c.a * one_minus_a + fb.a);
    return true;
}

}  // namespace uvr::gpu
