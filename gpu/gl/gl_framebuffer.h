// The float framebuffer a GL driver renders a frame into (HAVS: colour, k-buffer targets, diagnostics; VICP: colour,
// diagnostics; the ray caster's box passes: entry, exit, with a 24-bit depth buffer): `count` RGBA32F colour
// attachments, every one drawn into, made for a size and made again when the size changes, and read back exactly
// (glReadPixels of a float attachment returns the stored bits).
// Twins: none (GL side only). Used by gpu/havs/gl_havs.cpp, gpu/vicp/gl_vicp.cpp and gpu/raycast/gl_raycast.cpp.
#pragma once

#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "gpu/gl/gl_context.h"

namespace uvr::gpu {

class GlFloatFramebuffer {
public:
    enum class Depth {
        none,
        d24
    };  // d24: a GL_DEPTH_COMPONENT24 renderbuffer (the Krüger and Westermann ray caster's)
    GlFloatFramebuffer(const GlContext& ctx, int count, std::string what, Depth depth = Depth::none)
        : ctx_(ctx), count_(count), what_(what), depth_(depth)
    {
    }
    ~GlFloatFramebuffer() { release(); }
    GlFloatFramebuffer(const GlFloatFramebuffer&) = delete;
    GlFloatFramebuffer& operator=(const GlFloatFramebuffer&) = delete;

    // Binds the framebuffer at width x height (making it when the size differs from the last) and sets the viewport.
    // Throws InputError when it is incomplete.
    void bind(int width, int height);
    // The rows of attachment i as GL stores them (row 0 at the bottom).
    std::vector<glm::vec4> read(int attachment) const;
    // The texture behind attachment i (for image load/store), valid after bind().
    GLuint texture(int attachment) const { return textures_.at(std::size_t(attachment)); }

private:
    const GlContext& ctx_;
    int count_;
    std::string what_;
    Depth depth_;
    GLuint fbo_ = 0, depth_buffer_ = 0;
    std::vector<GLuint> textures_;
    int width_ = 0, height_ = 0;
    void release();
};

}  // namespace uvr::gpu
