#include "gpu/gl/gl_fragment_access.h"

#include "reference/error.h"

namespace uvr::gpu {

namespace {
constexpr const char* kFramebufferFetch = "GL_EXT_shader_framebuffer_fetch";
constexpr const char* kInterlockArb = "GL_ARB_fragment_shader_interlock";
constexpr const char* kInterlockNv = "GL_NV_fragment_shader_interlock";
}  // namespace

FragmentAccessPath choose_fragment_access(const GlInfo& info, FramebufferAccess access, const std::string& who)
{
    if (access != FramebufferAccess::images && info.has_extension(kFramebufferFetch))
        return {false, "", kFramebufferFetch};
    if (access == FramebufferAccess::framebuffer_fetch)
        throw InputError("", "the GL context (" + info.summary() + ") lacks " + kFramebufferFetch + ", which " + who +
                                 " was asked to use");
    if (info.has_extension(kInterlockArb)) return {true, "ARB", kInterlockArb};
    if (info.has_extension(kInterlockNv)) return {true, "NV", kInterlockNv};
    if (renderer_is_software(info.renderer) && !info.hides(kLlvmpipeImageRoute)) return {true, "", ""};
    throw InputError("", "the GL context (" + info.summary() + ") has neither " + kFramebufferFetch +
                             " nor a fragment-shader interlock (" + kInterlockArb + " or " + kInterlockNv +
                             "), one of which the GL backend of " + who +
                             " needs (docs/gl-backend.md); use --backend emu");
}

}  // namespace uvr::gpu
