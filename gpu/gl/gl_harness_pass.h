// The GL objects of one stage-harness pass (gpu/havs/gl_havs_harness.cpp for HAVS, gpu/vicp/gl_vicp_harness.cpp for
// VICP, gpu/raycast/gl_raycast_harness.cpp for the ray caster): input textures, buffer textures and storage buffers, a
// framebuffer of float or integer targets, deleted when the pass ends (also when a check throws), and the reads that
// bring the outputs back.
// Twins: none (the GL side of the stage harnesses; tests only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpu/gl/gl_context.h"

namespace uvr::gpu {

// One case per pixel: a chunk is at most kHarnessWidth x kHarnessRows cases (a 1024 x 256 RGBA32F target, 4 MiB).
inline constexpr int kHarnessWidth = 1024;
inline constexpr int kHarnessRows = 256;

// What every float output attachment is cleared to: a value no case produces, so a pixel whose outputs all still
// hold it was discarded.
inline constexpr float kHarnessSentinel = -1.0e30f;

// The GL objects of one pass, deleted when it ends (also when a check throws).
struct HarnessPass {
    const GlFunctions& gl;
    std::vector<GLuint> textures, buffers;
    GLuint fbo = 0;
    explicit HarnessPass(const GlFunctions& g) : gl(g) {}
    ~HarnessPass()
    {
        if (!textures.empty()) gl.DeleteTextures(GLsizei(textures.size()), textures.data());
        if (!buffers.empty()) gl.DeleteBuffers(GLsizei(buffers.size()), buffers.data());
        if (fbo) {
            gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
            gl.DeleteFramebuffers(1, &fbo);
        }
    }
    GLuint texture(GLenum target, int unit)
    {
        GLuint t = 0;
        gl.GenTextures(1, &t);
        textures.push_back(t);
        gl.ActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.BindTexture(target, t);
        // No mipmaps: without GL_NEAREST as the minification filter the texture would be incomplete.
        gl.TexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl.TexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return t;
    }
    // An RGBA32F input texture holding `texels` (width x height, 4 floats each) on texture unit `unit`.
    void input_2d(int unit, const std::vector<float>& texels, int width, int height)
    {
        texture(GL_TEXTURE_2D, unit);
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, texels.data());
    }
    GLuint storage(int binding, const void* data, std::size_t bytes)
    {
        GLuint b = 0;
        gl.GenBuffers(1, &b);
        buffers.push_back(b);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, b);
        gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), b);
        return b;
    }
    // A buffer texture of RGBA32UI texels over a new buffer holding `data` (`bytes`, whole texels) on texture unit
    // `unit`, for texelFetch.
    void texel_buffer(int unit, const void* data, std::size_t bytes)
    {
        GLuint b = 0, t = 0;
        gl.GenBuffers(1, &b);
        buffers.push_back(b);
        gl.BindBuffer(GL_TEXTURE_BUFFER, b);
        gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
        gl.GenTextures(1, &t);
        textures.push_back(t);
        gl.ActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.BindTexture(GL_TEXTURE_BUFFER, t);
        gl.TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32UI, b);
    }
    // An FBO of colour attachments of the given formats (RGBA32F or RGBA32UI), drawn into in order, cleared to the
    // sentinel (all bits set for the integer ones).
    void targets(const GlContext& ctx, const std::vector<GLenum>& formats, int width, int height)
    {
        gl.GenFramebuffers(1, &fbo);
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
        std::vector<GLenum> draw;
        for (std::size_t i = 0; i < formats.size(); ++i) {
            const GLuint t = texture(GL_TEXTURE_2D, 15);
            const bool integer = formats[i] == GL_RGBA32UI;
            gl.TexImage2D(GL_TEXTURE_2D, 0, GLint(formats[i]), width, height, 0, integer ? GL_RGBA_INTEGER : GL_RGBA,
                          integer ? GL_UNSIGNED_INT : GL_FLOAT, nullptr);
            gl.FramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + i), GL_TEXTURE_2D, t, 0);
            draw.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
        }
        gl.DrawBuffers(GLsizei(draw.size()), draw.data());
        check_framebuffer(ctx, "the stage harness's render targets");
        const float clear[4] = {kHarnessSentinel, kHarnessSentinel, kHarnessSentinel, kHarnessSentinel};
        const GLuint clear_u[4] = {~0u, ~0u, ~0u, ~0u};
        for (std::size_t i = 0; i < formats.size(); ++i) {
            if (formats[i] == GL_RGBA32UI)
                gl.ClearBufferuiv(GL_COLOR, GLint(i), clear_u);
            else
                gl.ClearBufferfv(GL_COLOR, GLint(i), clear);
        }
        gl.Viewport(0, 0, width, height);
    }
    // The first `bytes` of storage buffer `buffer` after a pass wrote it from its shaders.
    void read_storage(GLuint buffer, void* out, std::size_t bytes)
    {
        gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
        gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(bytes), out);
    }
    std::vector<uint32_t> read_uint(int attachment, int width, int height)
    {
        std::vector<uint32_t> out(std::size_t(width) * std::size_t(height) * 4);
        gl.ReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + attachment));
        gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
        gl.ReadPixels(0, 0, width, height, GL_RGBA_INTEGER, GL_UNSIGNED_INT, out.data());
        return out;
    }
    std::vector<float> read(int attachment, int width, int height)
    {
        std::vector<float> out(std::size_t(width) * std::size_t(height) * 4);
        gl.ReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + attachment));
        gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
        gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, out.data());
        return out;
    }
};

}  // namespace uvr::gpu
