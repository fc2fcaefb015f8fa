// Which GL device counts as hardware (gpu/gl/gl_context.h, docs/gpu.md "Which device"): by what the device says of
// itself, on the extension lists and renderer strings of NVIDIA, AMD and Mesa's software devices.
#include "gpu/gl/gl_context.h"
#include "test_support.h"

using namespace uvr::gpu;

TEST_CASE("an EGL device is software only when it says so")
{
    // NVIDIA's EGL device with its DRM node, and in a container without /dev/dri (no EGL_EXT_device_drm): a GPU both
    // times (a rule that asked for the DRM node took the second for software).
    CHECK_FALSE(egl_device_is_software("EGL_NV_device_cuda EGL_EXT_device_drm EGL_EXT_device_persistent_id"));
    CHECK_FALSE(egl_device_is_software("EGL_NV_device_cuda EGL_EXT_device_persistent_id"));
    // AMD (Mesa's radeonsi) through its DRM render node.
    CHECK_FALSE(egl_device_is_software("EGL_EXT_device_drm EGL_EXT_device_drm_render_node"));
    // Mesa's software device.
    CHECK(egl_device_is_software("EGL_MESA_device_software"));
    CHECK(egl_device_is_software("EGL_EXT_device_drm EGL_MESA_device_software"));
    // A word inside another is not the word.
    CHECK_FALSE(egl_device_is_software("EGL_MESA_device_software_x"));
}

TEST_CASE("a renderer string of llvmpipe or softpipe is software, a GPU's is not")
{
    CHECK(renderer_is_software("llvmpipe (LLVM 15.0.6, 256 bits)"));
    CHECK(renderer_is_software("softpipe"));
    CHECK_FALSE(renderer_is_software("NVIDIA H200/PCIe/SSE2"));
    CHECK_FALSE(renderer_is_software("AMD Radeon Pro W7900 (radeonsi, navi31, LLVM 15.0.7, DRM 3.54, 6.5.0)"));
}
