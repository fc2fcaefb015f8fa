#include "gpu/vicp/gl_vicp_fragment.h"

namespace uvr::gpu {

void set_vicp_frame_uniforms(const GlContext& ctx, const GlProgram& program, const VicpFrameConstants& fc)
{
    const GlFunctions& gl = ctx.gl();
    // A uniform the compiler removed (a pass that does not use it) has location -1, which glUniform ignores.
    gl.Uniform1d(program.uniform("vicp_two_over_width"), fc.two_over_width);
    gl.Uniform1d(program.uniform("vicp_two_over_height"), fc.two_over_height);
    auto vec = [&](const char* name, const glm::dvec3& v) { gl.Uniform3d(program.uniform(name), v.x, v.y, v.z); };
    vec("vicp_eye", fc.eye);
    vec("vicp_ray_ox", fc.ray_ox);
    vec("vicp_ray_oy", fc.ray_oy);
    vec("vicp_ray_d0", fc.ray_d0);
    vec("vicp_ray_dx", fc.ray_dx);
    vec("vicp_ray_dy", fc.ray_dy);
    gl.Uniform1f(program.uniform("vicp_threshold"), fc.threshold);
    gl.Uniform1f(program.uniform("vicp_length_scale"), fc.length_scale);
    gl.Uniform1f(program.uniform("vicp_length_bias"), fc.length_bias);
    ctx.check_error("setting the VICP frame uniforms");
}

}  // namespace uvr::gpu
