// The interpolation stage's GL side (tests only): triangles drawn by llvmpipe with a program that writes each
// varying, as the rasterizer interpolated it, to RGBA32F targets: once `smooth`, once `noperspective`, once `flat`.
// Twins: gpu/pipeline/interpolation.h (the emulation); shaders/interpolation_harness.{vert,frag}.
#pragma once

#include <memory>
#include <vector>

#include "gpu/gl/gl_context.h"

namespace uvr::gpu {

// A triangle: per vertex its clip coordinates (x, y, z, w, inside the frustum: the draw module must not clip it) and
// four attribute values.
struct InterpolationTriangle {
    float clip[3][4];
    float value[3][4];
};

// What the pass wrote, per pixel of a width x height FBO (GL rows from the bottom), four floats each; pixels no
// triangle covered hold kHarnessSentinel. `info` is (gl_PrimitiveID, gl_FrontFacing, gl_FragCoord.w, 0).
struct InterpolationImages {
    std::vector<float> smooth, noperspective, flat, info;
};

class GlInterpolationHarness {
public:
    explicit GlInterpolationHarness(GlContext& ctx);
    ~GlInterpolationHarness();
    // Draws the triangles in order in one glDrawArrays (a later triangle overwrites an earlier one's pixels).
    InterpolationImages run(const std::vector<InterpolationTriangle>& triangles, int width, int height);

private:
    GlContext& ctx_;
    std::unique_ptr<GlProgram> program_;
    GLuint vao_ = 0;
};

}  // namespace uvr::gpu
