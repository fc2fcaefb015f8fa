// Runs the ray caster's fragment program (shaders/raycast_fragment.frag through shaders/raycast_harness.frag) alone on
// chosen inputs, for bit-for-bit comparison with its emulation (docs/spec.md §5, stage level), as
// gpu/vicp/gl_vicp_harness.h does for VICP. One case per pixel of a full-screen pass, inputs and outputs in storage
// buffers whose std430 layouts are in gl_raycast_harness.cpp; the frame constants are uniforms, set once a call, the
// cases vary within it:
//   - run_ray: raycast_ray_exact (frame constants and pixel -> the ray, every double before its rounding to float);
//   - run_march: raycast_march (a ray -> colour and samples) over a RaycastVolume's real textures, both
//     classifications, shaded or not, as the renderer binds them;
//   - run_light: raycast_light_factors (a sample's place, its gradient -> the Blinn-Phong factors, in double);
//   - run_ray_published: raycast_ray_published (the box passes' entry and exit texels -> the ray).
// Twins: shaders/raycast_harness.frag (its mains); emulated stage gpu/raycast/raycast_fragment.h; GL uniforms
// gpu/raycast/gl_raycast.h. Tests only (library uvr_gl_harness).
#pragma once

#include <map>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "gpu/gl/gl_context.h"
#include "gpu/raycast/raycast_fragment.h"
#include "gpu/raycast/raycast_setup.h"

namespace uvr::gpu {

// One case of raycast_light_factors: the ray's entry and unit direction, the sample's distance t, the gradient.
struct RaycastLightCase {
    glm::dvec3 entry{0.0}, dir{0.0};
    double t = 0.0;
    glm::vec3 g{0.0f};
};

class GlRaycastHarness {
public:
    explicit GlRaycastHarness(GlContext& ctx);
    ~GlRaycastHarness();
    GlRaycastHarness(const GlRaycastHarness&) = delete;
    GlRaycastHarness& operator=(const GlRaycastHarness&) = delete;

    std::vector<RaycastRayExact> run_ray(const RaycastFrameConstants& fc, const std::vector<glm::ivec2>& pixels);

    // `fc` must be a frame of `rv` (its scalar encoding and table scales), whatever else it changes.
    std::vector<RaycastResult> run_march(const RaycastVolume& rv, const RaycastFrameConstants& fc,
                                         const std::vector<RaycastRay>& rays);

    std::vector<glm::dvec2> run_light(const RaycastFrameConstants& fc, const std::vector<RaycastLightCase>& cases);

    // texels[2 i] is case i's entry (front), texels[2 i + 1] its exit (back).
    std::vector<RaycastRay> run_ray_published(const RaycastFrameConstants& fc, const std::vector<glm::vec4>& texels);

private:
    GlContext& ctx_;
    GLuint vao_ = 0;
    GLuint textures_[3] = {};
    std::map<int, std::unique_ptr<GlProgram>> programs_;  // 0 ray, 1 march, 2 light, 3 published ray

    const GlProgram& program(int which);
};

}  // namespace uvr::gpu
