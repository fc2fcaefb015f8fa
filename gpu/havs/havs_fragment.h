// HAVS's fragment stage (the HAVS paper, Appendix II), emulated operation by operation, in two parts as in the shader:
// the fragment's entry (--interpolation gpu: havs_varyings_at / havs_paper_side / havs_paper_entry, the paper's DP3,
// RSQ, MUL on the interpolated varyings in float32; exact: havs_fragment_values / havs_fragment_entry, a face's flat
// HavsFace in double) and havs_kbuffer (the incoming entry, the k stored entries, the framebuffer colour, a
// SegmentShader -> the written entries and colour, in float32, or a kill).
// Twins: shaders/havs_fragment.frag; GL uniforms gpu/havs/gl_havs_fragment.h; harness gpu/havs/gl_havs_harness.h.
// Derivation: docs/havs.md, "The paper's interpolation", "Exact interpolation", "The two parts" and "The entry
// encoding" (the sides kSideExit, kSideEntry, kSideOutside, kSideInterior; empty and flush entries).
#pragma once

#include <cstdint>
#include <functional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/pipeline/interpolation.h"
#include "gpu/pipeline/segment.h"

namespace uvr::gpu {

inline constexpr float kSideExit = -1.0f, kSideInterior = 1.0f, kSideOutside = 4.0f, kSideEntry = 16.0f;

struct KEntry {
    float x = -1.0f;  // encoded scalar
    float y = 0.0f;   // radial distance from the eye
};
inline constexpr KEntry kEmptyEntry{-1.0f, 0.0f};
inline constexpr KEntry kFlushFragment{-1.0f, __builtin_inff()};
// --entries paper (the program as the paper prints it, which the ARB witness runs): an entry's x is the interpolated
// scalar itself, an exit face's vertices carry paper_exit_scalar(s) < 0, a segment is nullified only when its front is
// negative, and the flush fragment lies at 2^60: what the paper's DP3/RSQ/MUL give the ARB flush quads' eye position
// (0, 0, 2^60) exactly (a square of 2^120, its root and reciprocal are powers of two). docs/havs-arb.md.
inline constexpr KEntry kPaperFlushFragment{-1.0f, 0x1p60f};
inline float paper_exit_scalar(float s)
{
    return -1.0f - s;
}

// Per-frame constants (uniforms).
struct HavsFrameConstants {
    double two_over_width = 0.0, two_over_height = 0.0;  // gl_FragCoord -> NDC: ndc = coord * (2 / size) - 1
    double origin_x = 0.0, origin_y = 0.0;   // orthographic: half width and half height of the view; perspective: 0
    float threshold = 0.99f;                 // the opacity kill (KIL 0.99 - alpha)
    float length_scale = 0.0f, length_bias = 0.0f;  // the paper's sz.z and sz.w
    float max_gap = 0.0f;  // segments longer than this contribute nothing (the longest edge; 0 = no limit)
    bool orthographic = false;   // --interpolation gpu: the distance along parallel rays is -z (havs_paper_entry)
    bool paper_entries = false;  // --entries paper (kPaperFlushFragment)
};

// Per-face constants (flat), computed by the CPU stage (havs_setup.cpp) in double. The window coordinates stay
// double: the edge functions subtract them from the pixel centre, and a float's 3e-5 pixel at 512 would move
// fragments on faces a fraction of a pixel across (see the header). The vertices' eye-space positions, 1 / w and
// scalars are rounded to float once: they enter only as the weighted mean's values and relative weights, where a
// float's 6e-8 relative error is below the stored entry's own float rounding, and a vertex rounds the same in every
// face that shares it, so faces still meet. In float they make the GL record 9 texels instead of 13, and each texel
// fetch costs llvmpipe about 3 ms of a Blunt Fin frame (docs/gl-backend.md, "Speed").
struct HavsFace {
    glm::vec3 q[3];                       // eye-space positions of the vertices
    glm::dvec2 v[3];                      // window coordinates of the vertices (window_position_d)
    int32_t fx[3] = {0, 0, 0}, fy[3] = {0, 0, 0};  // the rasterizer's snapped vertices (viewport_transform, 24.8)
    float inv_w[3] = {0, 0, 0};           // 1 / clip w of each vertex
    float s[3] = {0, 0, 0};               // normalized scalar of each vertex, in [0, 1]
    float side = 1.0f;                    // kSideExit, kSideInterior or kSideEntry (see the entry encoding)
};

// How far outside the triangle a pixel centre may lie and still take the exact weights, as a fraction of the
// triangle's height over the edge it is beyond (a weight of -kOutsideTolerance). Two kinds of coverage lie outside:
// a pixel near an edge that snapping handed to the neighbouring face (a weight of -1e-4 to -0.05 here): extrapolating
// this face's plane a little past the edge is accurate, while the snapped weights would move the point by up to
// 1/512 pixel along the face, a large depth error on faces seen at a grazing angle (0.03 units on an Oxygen Post
// pixel); and a sliver seen edge-on whose snapped triangle covers pixels its true one does not (weights of -200),
// where only the snapped weights keep the fragment on the mesh. Measured on Blunt Fin, the Oxygen Post and the torus
// (docs/havs.md): 0.1 separates the two.
inline constexpr double kOutsideTolerance = 0.1;

// The snapped edge functions are integers computed in double: the fixed-point differences, their products and the
// products' difference must all be exact, i.e. below 2^53. A drawn triangle's snapped vertices lie in the viewport
// (the clip stage leaves nothing for the GPU to clip, and a viewport is at most 16384 = 2^14 pixels), so they and the
// pixel centres 256 * p are below 2^22 fixed units in magnitude: differences below 2^23, products below 2^46, their
// difference below 2^47. Exact with margin, and equal to the 64-bit integer edge functions the rasterizer uses. Double
// rather than int64 so that the shader needs no GL_ARB_gpu_shader_int64, which not every GPU driver offers (on
// llvmpipe the two cost the same, measured on a Blunt Fin frame).
inline constexpr int kSnappedEdgeBits = 47;

// The fragment values in double before the k-buffer stores them as float32: x = side * (1 + s_n) and the distance;
// `snapped` says whether the weights came from the snapped vertices (kOutsideTolerance), `outside` whether the pixel
// centre lies outside the face's triangle at all (then an interior face's side becomes kSideOutside). The GL stage test
// compares the shader's doubles with these.
struct FragmentValues {
    double x = 0.0, distance = 0.0;
    bool snapped = false;
    bool outside = false;
};
// `covered_exactly` (--coverage exact, emulation only): the pixel's ray crosses the face, so its values are the
// crossing's whatever rounding says of the edge functions (never the snapped weights, never kSideOutside).
FragmentValues havs_fragment_values(const HavsFrameConstants& fc, const HavsFace& face, int px, int py,
                                    bool covered_exactly = false);

// The incoming fragment's entry at window pixel (px, py) (gl_FragCoord.xy = (px + 0.5, py + 0.5)).
KEntry havs_fragment_entry(const HavsFrameConstants& fc, const HavsFace& face, int px, int py,
                           bool covered_exactly = false);

// --interpolation gpu (the paper's pipeline, docs/spec.md §7): what the paper's fragment program receives, as the
// rasterizer interpolated it: the eye-space position (texture coordinate 1, smooth), the normalized scalar (texture
// coordinate 0, smooth) and the face's side (a flat attribute: kSideExit, kSideInterior, or kSideEntry once the facing
// is known).
struct HavsVaryings {
    glm::vec3 eye{0.0f};
    float s = 0.0f;
    float side = kSideInterior;
};

// One triangle's varyings as planes of the interpolation stage (gpu/pipeline/interpolation.h). `sv`, `eye` and `s`
// per vertex, in drawing order; `ts` the rasterizer's setup of the same triangle (its winding orders the vertices).
struct HavsVaryingPlanes {
    AttributeSetup setup;
    AttributePlane smooth[4];  // the eye position x, y, z and the scalar
    AttributePlane corner[3];  // noperspective (1, 0, 0), (0, 1, 0), (0, 0, 1) at the vertices, in drawing order
    float side = kSideInterior;
};
HavsVaryingPlanes havs_varying_planes(const SetupVertex sv[3], const glm::vec3 eye[3], const float s[3], float side,
                                      const TriangleSetup& ts);
// The varyings at setup-space pixel (px, py); an interior face's side becomes kSideOutside where a corner weight is
// below 0 (the pixel centre lies outside the triangle: covered through snapping), as havs_fragment_values marks it.
HavsVaryings havs_varyings_at(const HavsVaryingPlanes& planes, int px, int py, ViewportArithmetic arith);

// The side of a fragment whose corner weights (the noperspective (1,0,0), (0,1,0), (0,0,1) of its triangle) are
// `corner`: an interior face's becomes kSideOutside where one is below 0.
float havs_paper_side(float side, const glm::vec3& corner);

// The paper's fragment values in float32 from the varyings: the distance |e| by DP3, RSQ, MUL (t = e.e, then
// t * (1 / sqrt(t))), or -e.z under an orthographic view (the paper is perspective only: docs/havs.md); the entry
// side * (1 + s) with s clamped to [0, 1] as in havs_fragment_values; with paper_entries the scalar itself.
KEntry havs_paper_entry(const HavsFrameConstants& fc, const HavsVaryings& v);

struct KBufferDiagnostics {
    uint32_t fragments = 0;        // fragments that reached the program (flush passes not counted)
    uint32_t max_held = 0;         // most real entries stored at once
    uint32_t ordering_errors = 0;  // a segment composited from a front nearer than the previous segment's back
    float last_back = 0.0f;        // back distance of the last composited segment (bookkeeping)
};

// One run of the fragment program on one pixel. `entries` holds the k stored entries (a1..ak of the paper). Returns
// false when the fragment is killed (the framebuffer's alpha is above the threshold) or k < 1: nothing is written.
bool havs_kbuffer(const HavsFrameConstants& fc, KEntry incoming, KEntry* entries, int k, glm::vec4& framebuffer,
                  const SegmentShader& shade, KBufferDiagnostics* diag);

// The flush: what k runs of havs_kbuffer on kFlushFragment composite over `framebuffer` from the k stored `entries`,
// bit for bit, in k log k steps instead of k^2 (the entries are left as they are; a frame's flush is its last use of
// them).
void havs_flush(const HavsFrameConstants& fc, const KEntry* entries, int k, glm::vec4& framebuffer,
                const SegmentShader& shade, KBufferDiagnostics* diag);

}  // namespace uvr::gpu
