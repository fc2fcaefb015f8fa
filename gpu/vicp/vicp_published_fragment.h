// VICP-FragmentProg as Moreland's dissertation gives it (--interpolation gpu): from the varyings the
// rasterizer interpolated (the distances along the view ray to the three faces opposite the vertices of the projected
// face, the scalars there, and the entry scalar), the exit is the smallest positive distance, and its scalar the exit
// scalar. float32 throughout. Input: VicpPublishedVaryings at a pixel. Output: VicpPublishedExit (entry and exit
// scalars, the length). Twins: shaders/vicp_published_fragment.frag; harness gpu/vicp/gl_vicp_harness.h
// (run_published_exit). Derivation: docs/vicp.md, "The published pipeline".
#pragma once

#include <glm/vec3.hpp>

#include "gpu/pipeline/interpolation.h"

namespace uvr::gpu {

// The fragment program's inputs (all `smooth`): distance[i] and scalar[i] to and at the face opposite the projected
// face's vertex i; s, the scalar on the projected face.
struct VicpPublishedVaryings {
    glm::vec3 distance{0.0f};
    glm::vec3 scalar{0.0f};
    float s = 0.0f;
};

// The segment the fragment integrates: `face` is the chosen entry (0..2) or -1 when no distance is positive (the
// fragment then contributes nothing: length 0).
struct VicpPublishedExit {
    int face = -1;
    float s_front = 0.0f, s_back = 0.0f;  // clamped to [0, 1]
    float length = 0.0f;
};

// The smallest distance greater than 0, the first such index on ties; a NaN distance is never chosen.
VicpPublishedExit vicp_published_exit(const VicpPublishedVaryings& v);

// One front face's varyings as planes of the interpolation stage (gpu/pipeline/interpolation.h), every one `smooth`:
// `sv` and `v` are its three vertices' setup inputs and vertex-program outputs in drawing order, `ts` its rasterizer
// setup. vicp_published_varyings_at evaluates them at setup-space pixel (px, py), as llvmpipe hands them to the
// program.
struct VicpPublishedPlanes {
    AttributeSetup setup;
    // The fragment's smooth inputs in one array, interpolated in one call: distance[0..2], scalar[0..2], s.
    static constexpr int kDistance = 0, kScalar = 3, kS = 6, kCount = 7;
    AttributePlane varying[kCount];
};
VicpPublishedPlanes vicp_published_planes(const SetupVertex sv[3], const VicpPublishedVaryings v[3],
                                          const TriangleSetup& ts);
VicpPublishedVaryings vicp_published_varyings_at(const VicpPublishedPlanes& planes, int px, int py,
                                                 ViewportArithmetic arith);
// The same with the pixel's perspective_factor given (a fragment with more `smooth` inputs computes it once).
VicpPublishedVaryings vicp_published_varyings_at(const VicpPublishedPlanes& planes, int px, int py, float factor,
                                                 ViewportArithmetic arith);

}  // namespace uvr::gpu
