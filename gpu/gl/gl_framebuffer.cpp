#include "gpu/gl/gl_framebuffer.h"

namespace uvr::gpu {

void GlFloatFramebuffer::release()
{
    const GlFunctions& gl = ctx_.gl();
    if (fbo_) {
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        gl.DeleteFramebuffers(1, &fbo_);
        fbo_ = 0;
    }
    if (depth_buffer_) {
        gl.DeleteRenderbuffers(1, &depth_buffer_);
        depth_buffer_ = 0;
    }
    if (!textures_.empty()) gl.DeleteTextures(GLsizei(textures_.size()), textures_.data());
    textures_.clear();
    width_ = height_ = 0;
}

void GlFloatFramebuffer::bind(int width, int height)
{
    const GlFunctions& gl = ctx_.gl();
    if (width != width_ || height != height_) {
        release();
        gl.GenFramebuffers(1, &fbo_);
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
        textures_.resize(std::size_t(count_));
        gl.GenTextures(GLsizei(count_), textures_.data());
        gl.ActiveTexture(GL_TEXTURE0);
        std::vector<GLenum> bufs;
        for (int i = 0; i < count_; ++i) {
            gl.BindTexture(GL_TEXTURE_2D, textures_[std::size_t(i)]);
            gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
            gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl.FramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + i), GL_TEXTURE_2D,
                                    textures_[std::size_t(i)], 0);
            bufs.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
        }
        if (depth_ == Depth::d24) {
            gl.GenRenderbuffers(1, &depth_buffer_);
            gl.BindRenderbuffer(GL_RENDERBUFFER, depth_buffer_);
            gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
            gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_buffer_);
        }
        gl.DrawBuffers(GLsizei(count_), bufs.data());
        check_framebuffer(ctx_, what_);
        width_ = width;
        height_ = height;
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
    gl.Viewport(0, 0, width, height);
}

std::vector<glm::vec4> GlFloatFramebuffer::read(int attachment) const
{
    const GlFunctions& gl = ctx_.gl();
    std::vector<glm::vec4> out(std::size_t(width_) * std::size_t(height_));
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.ReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + attachment));
    gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, out.data());
    ctx_.check_error("reading " + what_ + " back");
    return out;
}

}  // namespace uvr::gpu
