#include "gpu/havs/gl_havs_fragment.h"

namespace uvr::gpu {

GlHavsFace pack_havs_face(const HavsFace& f)
{
    GlHavsFace g{};
    for (int j = 0; j < 3; ++j) {
        g.q[3 * j] = f.q[j].x;
        g.q[3 * j + 1] = f.q[j].y;
        g.q[3 * j + 2] = f.q[j].z;
        g.v[2 * j] = f.v[j].x;
        g.v[2 * j + 1] = f.v[j].y;
        g.inv_w[j] = f.inv_w[j];
        g.s[j] = f.s[j];
        g.fx[j] = f.fx[j];
        g.fy[j] = f.fy[j];
    }
    g.side = f.side;
    return g;
}

void bind_havs_face_records(const GlContext& ctx, GLuint texture, GLuint buffer)
{
    const GlFunctions& gl = ctx.gl();
    gl.ActiveTexture(GLenum(GL_TEXTURE0 + kHavsFaceUnit));
    gl.BindTexture(GL_TEXTURE_BUFFER, texture);
    gl.TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32UI, buffer);
}

void set_havs_frame_uniforms(const GlContext& ctx, const GlProgram& program, const HavsFrameConstants& fc)
{
    const GlFunctions& gl = ctx.gl();
    // A uniform the compiler removed (a pass that does not use it) has location -1, which glUniform ignores.
    gl.Uniform1d(program.uniform("havs_two_over_width"), fc.two_over_width);
    gl.Uniform1d(program.uniform("havs_two_over_height"), fc.two_over_height);
    gl.Uniform1d(program.uniform("havs_origin_x"), fc.origin_x);
    gl.Uniform1d(program.uniform("havs_origin_y"), fc.origin_y);
    gl.Uniform1f(program.uniform("havs_threshold"), fc.threshold);
    gl.Uniform1f(program.uniform("havs_length_scale"), fc.length_scale);
    gl.Uniform1f(program.uniform("havs_length_bias"), fc.length_bias);
    gl.Uniform1f(program.uniform("havs_max_gap"), fc.max_gap);
    gl.Uniform1i(program.uniform("havs_orthographic"), fc.orthographic ? 1 : 0);
    ctx.check_error("setting the HAVS frame uniforms");
}

}  // namespace uvr::gpu
