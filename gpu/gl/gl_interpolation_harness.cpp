#include "gpu/gl/gl_interpolation_harness.h"

#include "gpu/gl/gl_harness_pass.h"

namespace uvr::gpu {

GlInterpolationHarness::GlInterpolationHarness(GlContext& ctx) : ctx_(ctx)
{
    ctx_.make_current();
    program_ = std::make_unique<GlProgram>(ctx_, GlShaderSource{{"interpolation_harness.vert"}, {}, {}},
                                           GlShaderSource{{"interpolation_harness.frag"}, {}, {}});
    ctx_.gl().GenVertexArrays(1, &vao_);
}

GlInterpolationHarness::~GlInterpolationHarness()
{
    program_.reset();
    if (vao_) ctx_.gl().DeleteVertexArrays(1, &vao_);
}

InterpolationImages GlInterpolationHarness::run(const std::vector<InterpolationTriangle>& triangles, int width,
                                                int height)
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    // The vertex records the vertex shader reads by gl_VertexID: (clip, value), two vec4 a vertex (std430).
    std::vector<float> records;
    records.reserve(triangles.size() * 24);
    for (const InterpolationTriangle& t : triangles)
        for (int v = 0; v < 3; ++v) {
            records.insert(records.end(), t.clip[v], t.clip[v] + 4);
            records.insert(records.end(), t.value[v], t.value[v] + 4);
        }
    HarnessPass pass(gl);
    pass.storage(0, records.data(), records.size() * sizeof(float));
    pass.targets(ctx_, {GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F}, width, height);
    gl.UseProgram(program_->id());
    gl.BindVertexArray(vao_);
    gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(3 * triangles.size()));
    InterpolationImages out;
    out.smooth = pass.read(0, width, height);
    out.noperspective = pass.read(1, width, height);
    out.flat = pass.read(2, width, height);
    out.info = pass.read(3, width, height);
    ctx_.check_error("the interpolation harness pass");
    return out;
}

}  // namespace uvr::gpu
