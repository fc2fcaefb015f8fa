// The rasterizer's attribute interpolation as llvmpipe (Mesa 22.3) performs it: the setup of each attribute's plane
// (a0, dadx, dady) per triangle from the float window positions, and its evaluation per pixel for GLSL's `smooth`
// (perspective-correct), `noperspective` and `flat`. float32 throughout; call under FlushDenormals (llvmpipe runs
// setup and shaders with DAZ and FTZ set).
// Twins: none in shaders/ (fixed function): the GL counterpart is llvmpipe itself, checked by
// tests/test_interpolation.cpp through shaders/interpolation_harness.{vert,frag}.
// Derivation: docs/interpolation.md (the Mesa functions, the operation orders, what was measured).
#pragma once

#include "gpu/pipeline/rasterize.h"
#include "reference/choice.h"

namespace uvr::gpu {

enum class Qualifier { smooth, noperspective, flat };

// --interpolation: gpu (the fragment's inputs are the rasterizer's interpolated varyings, this stage: the published
// pipelines, docs/spec.md §7) or exact (computed in double from the ray through the pixel centre: the lab's variant).
enum class InterpolationMode { gpu, exact };
inline constexpr Choices<InterpolationMode, 2> kInterpolationModes{
    {{InterpolationMode::gpu, "gpu", "the rasterizer's interpolated varyings, the published pipeline; default"},
     {InterpolationMode::exact, "exact", "the fragment's values in double from the ray through the pixel centre"}}};

// A vertex as llvmpipe's triangle setup receives it (the draw module's viewport transform): the window position in
// setup space and 1 / w of its clip coordinates.
struct SetupVertex {
    float x = 0.0f, y = 0.0f;
    float oow = 1.0f;
};
SetupVertex setup_vertex(const float clip[4], const Framebuffer& fb,
                         ViewportArithmetic arith = host_viewport_arithmetic());

// One channel's plane in setup space: value at pixel (px, py) = a0 + dadx * px + dady * py (pixel centres folded in).
struct AttributePlane {
    float a0 = 0.0f, dadx = 0.0f, dady = 0.0f;
};

// The per-triangle part of setup (lp_state_setup.c init_args), in the vertex order setup sees (`order`: which input
// vertex is its v0, v1, v2), and the plane of 1 / w (the position slot's w channel) that perspective correction uses.
struct AttributeSetup {
    int order[3] = {0, 1, 2};
    float x0c = 0.0f, y0c = 0.0f;
    float dx01_ooa = 0.0f, dy01_ooa = 0.0f, dx20_ooa = 0.0f, dy20_ooa = 0.0f;
    AttributePlane oow;
};

// `ts` is the triangle's rasterizer setup (its winding decides the order: lp_setup_tri.c swaps v0 and v1 of a
// clockwise triangle). The triangle must not be empty (ts.facing != Facing::none).
AttributeSetup setup_attributes(const SetupVertex v[3], const TriangleSetup& ts);

// The plane of one channel whose values at the input vertices are value[0..2].
AttributePlane attribute_plane(const AttributeSetup& setup, const SetupVertex v[3], const float value[3], Qualifier q);

// gl_FragCoord.w at setup-space pixel (px, py): the interpolated 1 / w.
float frag_coord_w(const AttributeSetup& setup, int px, int py, ViewportArithmetic arith);
// 1 / gl_FragCoord.w: the factor every `smooth` input of the pixel shares.
float perspective_factor(const AttributeSetup& setup, int px, int py, ViewportArithmetic arith);

// The value of a channel at setup-space pixel (px, py); `factor` is perspective_factor's (used by `smooth` only).
float interpolate(const AttributePlane& plane, Qualifier q, int px, int py, float factor, ViewportArithmetic arith);
// The same for n channels of one qualifier at once (out[i] for planes[i]): the same bits, one call per fragment.
void interpolate(const AttributePlane* planes, int n, Qualifier q, int px, int py, float factor,
                 ViewportArithmetic arith, float* out);

}  // namespace uvr::gpu
