#include "gpu/gl/gl_preintegration_table.h"

namespace uvr::gpu {

void upload_preintegration_table(const GlContext& ctx, const PreintegrationTable& table, TextureFilter filter,
                                 GLuint& texture)
{
    const GlFunctions& gl = ctx.gl();
    if (!texture) gl.GenTextures(1, &texture);
    gl.ActiveTexture(GL_TEXTURE4);
    gl.BindTexture(GL_TEXTURE_3D, texture);
    const int n = table.scalar_resolution(), l = table.length_resolution();
    GLenum internal = GL_RGBA32F, type = GL_FLOAT;
    if (table.config().format == TexelFormat::u16) internal = GL_RGBA16, type = GL_UNSIGNED_SHORT;
    if (table.config().format == TexelFormat::u8) internal = GL_RGBA8, type = GL_UNSIGNED_BYTE;
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexImage3D(GL_TEXTURE_3D, 0, GLint(internal), n, n, l, 0, GL_RGBA, type, table.data());
    const GLint f = filter == TextureFilter::linear ? GL_LINEAR : GL_NEAREST;
    for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) gl.TexParameteri(GL_TEXTURE_3D, p, f);
    for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        gl.TexParameteri(GL_TEXTURE_3D, p, GL_CLAMP_TO_EDGE);
    ctx.check_error("uploading the pre-integration table");
}

}  // namespace uvr::gpu
