// HAVS's fragment stage (seed 000, Appendix II), emulated operation by operation in float32, and its GLSL twin
// shaders/havs_fragment.frag.
//
// Two parts, as in the shader:
//  1. Fragment values. The seed interpolates the scalar and the eye-space position per fragment; interpolators cannot
//     be mirrored bit for bit, so each face carries flat constants instead (HavsFace, computed once per face on the
//     CPU and uploaded as they are) and the fragment computes from gl_FragCoord alone. Barycentric weights: the three
//     2D edge functions at the pixel centre from the face's float window coordinates, accurate to their rounding
//     (~3e-5 pixel). Rasterization, though, snaps vertices to 1/256 pixel, and a face seen nearly edge-on can cover
//     pixels its float projection does not; there the float weights would extrapolate, placing the fragment where
//     there is nothing (an Oxygen Post pixel got two fragments 6 units before the mesh begins). When the pixel lies
//     outside the float triangle by more than kOutsideTolerance, the weights come instead from the snapped vertices
//     the rasterizer used: exact integer edge functions (24.8 fixed point: differences below 2^21, products below
//     2^42, exact in int64 here and in double in the shader), non-negative on every covered pixel, so the fragment
//     lies inside the triangle the rasterizer drew. Each weight is divided by its vertex's clip w (perspective
//     correction); the eye-space point is the weighted mean of the vertices' eye-space positions, its distance from
//     the pixel's ray origin (the eye, or the image plane under orthographic projection) the radial distance of SPEC
//     §2, and the normalized scalar the weighted mean of the vertices' scalars. Weighted means stay inside the
//     triangle whatever its angle to the view. Every float operation is written out in a fixed order; the shader
//     marks them `precise`.
//  2. The k-buffer program: the seed's selection chain generalized to k stored entries, its tie behaviour, the opacity
//     kill, the nullified contribution, the table coordinates with the seed's scale and bias, front-to-back
//     compositing, and the write-back of the remaining entries.
//
// Entry encoding. An entry is (x, y) = (encoded scalar, distance). x = side * (1 + s_n): s_n in [0, 1] the
// normalized scalar, side -1 for a boundary face the ray leaves the mesh through (exact gaps: a segment that starts
// there is a gap and is nullified, as the seed nullifies entries with x < 0), +1 otherwise. Decoding |x| - 1 is exact
// (Sterbenz), so the back scalar of a segment that ends on the boundary stays exact; 1 + s_n rounds s_n to 2^-23 of
// the range. An empty entry is (-1, 0): it is selected first, and its segment nullified, so the first k fragments of a
// pixel fill the buffer. A flush fragment is (-1, +inf); a segment that ends on one is nullified too (see
// havs_kbuffer).
#pragma once

#include <cstdint>
#include <functional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace uvr::gpu {

struct KEntry {
    float x = -1.0f;  // encoded scalar
    float y = 0.0f;   // radial distance from the eye
};
inline constexpr KEntry kEmptyEntry{-1.0f, 0.0f};
inline constexpr KEntry kFlushFragment{-1.0f, __builtin_inff()};

// Per-frame constants (uniforms).
struct HavsFrameConstants {
    float two_over_width = 0.0f, two_over_height = 0.0f;  // gl_FragCoord -> NDC: ndc = coord * (2 / size) - 1
    float origin_x = 0.0f, origin_y = 0.0f;  // orthographic: half width and half height of the view; perspective: 0
    float threshold = 0.99f;                 // the opacity kill (KIL 0.99 - alpha)
    float length_scale = 0.0f, length_bias = 0.0f;  // the seed's sz.z and sz.w
    float max_gap = 0.0f;  // --gaps maxgap: segments longer than this contribute nothing; 0 = exact gaps
};

// Per-face constants (flat), computed by the CPU stage (havs.cpp) in double and rounded to float once.
struct HavsFace {
    glm::vec3 q[3];                       // eye-space positions of the vertices
    glm::vec2 v[3];                       // float window coordinates of the vertices (viewport_transform)
    int32_t fx[3] = {0, 0, 0}, fy[3] = {0, 0, 0};  // the same snapped as the rasterizer snaps them (24.8)
    float inv_w[3] = {0, 0, 0};           // 1 / clip w of each vertex
    float s[3] = {0, 0, 0};               // normalized scalar of each vertex, in [0, 1]
    float side = 1.0f;                    // -1: a boundary face the ray leaves the mesh through (exact gaps)
};

// How far outside the float triangle a pixel centre may lie, as a fraction of the triangle's doubled area (the sum of
// its edge functions), and still take the float weights. A pixel whose coverage comes from snapping lies up to 1/512
// pixel outside, i.e. 1e-3 of the doubled area for a triangle of about 2 square pixels and far more for slivers; the
// float edge functions' own rounding is ~3e-5 pixel times an edge length, below 1e-3 of the doubled area unless the
// triangle is thinner than ~0.03 pixel. Between the two, either choice is consistent with the coverage.
inline constexpr float kOutsideTolerance = 1e-3f;

// The incoming fragment's entry at window pixel (px, py) (gl_FragCoord.xy = (px + 0.5, py + 0.5)).
KEntry havs_fragment_entry(const HavsFrameConstants& fc, const HavsFace& face, int px, int py);

// What the table lookup (or, in emulation, the exact integral) returns for the segment from entry `front` to entry
// `back`: u_front = |front.x| - 1, u_back = |back.x| - 1, t_z = (back.y - front.y) * length_scale + length_bias.
using SegmentShader = std::function<glm::vec4(float u_front, float u_back, float t_z, float length)>;

struct KBufferDiagnostics {
    uint32_t fragments = 0;        // fragments that reached the program (flush passes not counted)
    uint32_t max_held = 0;         // most real entries stored at once
    uint32_t ordering_errors = 0;  // a segment composited from a front nearer than an earlier composited front
    float last_front = 0.0f;       // distance of the last composited real front (bookkeeping)
};

// The emulation takes any k from 1 to kMaxK (the GL backend every k its draw buffers allow).
inline constexpr int kMaxK = 255;

// One run of the fragment program on one pixel. `entries` holds the k stored entries (a1..ak of the seed). Returns
// false when the fragment is killed (the framebuffer's alpha is above the threshold): nothing is written.
bool havs_kbuffer(const HavsFrameConstants& fc, KEntry incoming, KEntry* entries, int k, glm::vec4& framebuffer,
                  const SegmentShader& shade, KBufferDiagnostics* diag);

}  // namespace uvr::gpu
