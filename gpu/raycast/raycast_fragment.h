// The ray caster's fragment program (Krüger and Westermann), emulated operation by operation: the pixel's ray in double
// from gl_FragCoord, clipped against the samples' box (raycast_ray_exact, raycast_ray); the march in float through the
// volume texture, post-classified or pre-integrated (raycast_march); optional Blinn-Phong shading (raycast_gradient,
// raycast_light_factors). Input: RaycastFrameConstants, the pixel, RaycastTextures. Output: RaycastResult (the colour
// and the number of samples). Twins: shaders/raycast_fragment.frag; GL uniforms gpu/raycast/gl_raycast.h
// (set_raycast_frame_uniforms); harness gpu/raycast/gl_raycast_harness.h. Derivation: docs/raycast.md gives the
// decisions, and the arithmetic under "The arithmetic".
#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/raycast/classification_table.h"
#include "gpu/pipeline/segment.h"
#include "gpu/pipeline/pixel_rays.h"
#include "gpu/pipeline/texture_sampling.h"

namespace uvr::gpu {

// Per-frame constants (uniforms): the pixels' rays (gpu/pipeline/pixel_rays.h) relative to the box's centre, and the
// rest.
struct RaycastFrameConstants : PixelRays {
    glm::dvec3 box_lo{0.0}, box_hi{0.0};  // the samples' box, relative to its centre
    glm::dvec3 tex_scale{0.0};            // 1 / (dims * spacing): world units to texture coordinates
    glm::dvec3 tex_half{0.0};             // 0.5 / dims: texel 0's centre
    glm::vec3 tex_extent{0.0f};           // float(dims * spacing): world units per texture unit (the published passes)
    double step = 1.0;                    // world units
    int max_samples = 0;                  // no ray takes more (setup: the box's diagonal over the step, plus 2)
    int preintegrate = 0;
    float threshold = 0.95f;                          // early termination (docs/spec.md §3)
    float scalar_scale = 1.0f, scalar_bias = 0.0f;    // texture value -> normalized scalar
    float step_f = 1.0f;                              // float(step): a full segment's length (pre-integration)
    float length_scale = 0.0f, length_bias = 0.0f;    // the pre-integrated table's sz.z and sz.w
    // Shading (shade != 0).
    int shade = 0;
    glm::dvec3 light{0.0};                // the light's position, relative to the box's centre
    double ambient = 0.0, diffuse = 0.0, specular = 0.0;
    int shininess = 0;
    glm::vec3 texel{0.0f};                // 1 / dims: one texel in texture coordinates
    glm::vec3 gradient_scale{0.0f};       // 1 / (2 spacing)
};

// What the double part hands the march (a function of the pixel and the frame only).
struct RaycastRay {
    int samples = 0;                // n; 0 when the ray misses the box
    glm::vec3 tex0{0.0f};           // the entry, texture coordinates
    glm::vec3 dtex{0.0f};           // one step, texture coordinates
    glm::vec3 tex_exit{0.0f};       // the exit (pre-integration's last sample)
    float last_length = 0.0f;       // pre-integration: the last segment's length, in (0, step]
    double length = 0.0;            // L, world units
    glm::dvec3 entry{0.0}, dir{0.0};  // world entry point (centred frame) and unit direction: shading's positions
};

// The double part's results before their rounding to float: what the stage harness compares
// (gpu/raycast/gl_raycast_harness.h), so that a change in the double arithmetic shows even where it vanishes in the
// float it is rounded to.
struct RaycastRayExact {
    int samples = 0;
    glm::dvec3 tex0{0.0}, dtex{0.0}, tex_exit{0.0};
    double last_length = 0.0;
    double length = 0.0;
    glm::dvec3 entry{0.0}, dir{0.0};
};

RaycastRayExact raycast_ray_exact(const RaycastFrameConstants& fc, int px, int py);
RaycastRay rounded_ray(const RaycastRayExact& e);  // each float member rounded from its double once
inline RaycastRay raycast_ray(const RaycastFrameConstants& fc, int px, int py)
{
    return rounded_ray(raycast_ray_exact(fc, px, py));
}

// The published ray (--interpolation gpu) from the pixel's texels of the two box passes (gpu/raycast/raycast_box.h):
// the entry `front` and the exit `back` as llvmpipe interpolated them (alpha 1 where a fragment wrote them). In float:
// the difference in world units, its length by DP3, RSQ, MUL, the step as the difference times step / length; the
// sample count and the last segment in double from that length. No samples where either texel is unwritten or the
// length is 0. docs/raycast.md, "The published passes".
RaycastRay raycast_ray_published(const RaycastFrameConstants& fc, const glm::vec4& front, const glm::vec4& back);

// The textures the march reads, as the emulation holds them.
struct RaycastTextures {
    TextureView volume;                         // one channel, R8 / R16 / R32F
    const ClassificationTable* classification = nullptr;
    SegmentShader segment;                      // pre-integration (table as llvmpipe samples it, or exact)
    std::optional<TableSegmentShader> table_segment;  // segment's usual path as a plain call, where it is one
    std::optional<ExactSegmentShader> exact_segment;  // segment as a plain call where it is the exact integral
    LlvmpipeCpu cpu;
};

struct RaycastResult {
    glm::vec4 colour{0.0f};
    uint32_t samples = 0;  // texture positions classified (pre-integration counts the exit too)
};

RaycastResult raycast_march(const RaycastFrameConstants& fc, const RaycastRay& ray, const RaycastTextures& tex);

// The shaded colour: c.rgb * m + c.a * p with the light factors f = (m, p), alpha unchanged (unfused).
inline glm::vec4 raycast_lit(const glm::vec4& c, const glm::vec2& f)
{
    return {c.r * f.x + c.a * f.y, c.g * f.x + c.a * f.y, c.b * f.x + c.a * f.y, c.a};
}

// The march's compositing, front to back: acc = c * (1 - acc.a) + acc, per channel (MAD, unfused), as VICP's.
inline void raycast_composite(glm::vec4& acc, const glm::vec4& c)
{
    const float one_minus_a = 1.0f - acc.a;
    acc = glm::vec4(c.r * one_minus_a + acc.r, c.g * one_minus_a + acc.g, c.b * one_minus_a + acc.b,
                    c.a * one_minus_a + acc.a);
}

// The shading factors (m, p) at texture position p of sample distance t (world units past the entry) with the float
// gradient g (exposed for the stage tests), and the shaded colour.
// raycast_light_factors is the double part (compared by the stage harness); raycast_light rounds it to float.
glm::dvec2 raycast_light_factors(const RaycastFrameConstants& fc, const RaycastRay& ray, double t, const glm::vec3& g);
inline glm::vec2 raycast_light(const RaycastFrameConstants& fc, const RaycastRay& ray, double t, const glm::vec3& g)
{
    const glm::dvec2 f = raycast_light_factors(fc, ray, t, g);
    return {float(f.x), float(f.y)};
}
glm::vec3 raycast_gradient(const RaycastFrameConstants& fc, const RaycastTextures& tex, const glm::vec3& p);

}  // namespace uvr::gpu
