// How a fragment program reads and writes its own pixel's framebuffer values (HAVS's k-buffer, VICP's compositing):
// framebuffer fetch (GL_EXT_shader_framebuffer_fetch), or image load/store of the attachments inside a fragment-shader
// interlock (GL_ARB_ or GL_NV_fragment_shader_interlock: desktop GPUs without fetch), which orders one pixel's fragments
// by primitive as the framebuffer does. llvmpipe needs no interlock (its threads shade a tile's fragments one primitive
// after another), so there the image route runs with the interlock compiled out. docs/gl-backend.md, "The k-buffer
// without framebuffer fetch".
#pragma once

#include <string>

#include "gpu/gl/gl_context.h"

namespace uvr::gpu {

// `automatic` takes fetch where the context has it, else the image route; the others ask for one route.
enum class FramebufferAccess { automatic, framebuffer_fetch, images };

// The name by which the image route without an interlock (llvmpipe's) is hidden, as an extension is
// (UVR_GL_HIDE_EXTENSIONS, gl_context.h).
inline constexpr const char* kLlvmpipeImageRoute = "UVR_llvmpipe_image_route";

struct FragmentAccessPath {
    bool images = false;
    std::string interlock;  // "ARB", "NV", or empty (fetch; or images on llvmpipe)
    std::string extension;  // the extension the fragment program enables
};

// The route on this context; throws InputError naming `who` and the extensions it lacks when there is none.
FragmentAccessPath choose_fragment_access(const GlInfo& info, FramebufferAccess access, const std::string& who);

}  // namespace uvr::gpu
