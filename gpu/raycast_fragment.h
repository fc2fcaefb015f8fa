// The ray caster's fragment program (seed 002), emulated operation by operation, and its GLSL twin
// shaders/raycast_fragment.frag. docs/raycast.md gives the decisions; this header the arithmetic.
//
// 1. The ray, in double (GLSL fp64, IEEE operations on llvmpipe), from gl_FragCoord alone: the pixel's ray
//    x(t) = o + t d in the volume's centred frame (SPEC §2, as VICP's: d is not normalized), clipped against the
//    samples' box by the slab test; t_in is at least 0, so a camera inside the box starts at the eye. The seed instead
//    rasterizes the box's front and back faces with texture coordinates as colours and takes the difference: that
//    puts llvmpipe's interpolation between the ray and the data, which cannot be mirrored bit for bit, and it needs
//    the box in front of the near plane. The pass here is one full-screen triangle; a pixel whose ray misses the box
//    (t_out <= t_in: also the grazing ray and the box of zero thickness) takes no sample.
//    The march takes n = ceil(L / step) samples, L = (t_out - t_in) |d| the length inside the box in world units,
//    sample k at distance k * step past the entry (k = 0 .. n-1), as the seed's loop, which stops at the first
//    position past the exit. Positions are texture coordinates, where texel i's centre (i + 0.5) / dims is sample i:
//    the entry's tex0 and the step's dtex are computed in double and rounded to float once.
// 2. The march, in float: sample k at tex0 + float(k) * dtex (no accumulated error); u = texture(volume, p).r;
//    the normalized scalar x = u * scalar_scale + scalar_bias (the texture's encoding to SPEC §1's normalized scalar);
//      - post-classification: the sample's colour and opacity from the classification table at x (opacity corrected
//        for the step there, gpu/classification_table.h);
//      - --preintegrate: the segment between consecutive samples from the pre-integrated table of HAVS at
//        (x_previous, x, step), and a last segment from sample n-1 to the exit point, of its own length (the
//        table's length axis spans [0, step]);
//    optionally shaded (below); composited front to back as VICP's fragments (c * (1 - a) + acc, unfused); the
//    march stops when the accumulated alpha passes the threshold (acc.a > threshold: 1 never stops it).
// 3. Shading (the seed's "lab 6"), optional: the gradient by central differences of the texture in float (six more
//    fetches, one texel apart, scaled by 1 / (2 spacing) per axis), then in double (where llvmpipe's division and
//    square root are IEEE, as VICP's exercise them; float division may be lowered to a reciprocal) the Blinn-Phong
//    factors with a point light, two-sided (|n . l|, |n . h|: the gradient's sign does not matter):
//      m = ambient + diffuse |n . l|,  p = specular |n . h|^shininess  (h = normalize(l + v)),
//    rounded to float, and the premultiplied colour becomes c.rgb * m + c.a * p (alpha unchanged). A zero gradient
//    (a homogeneous region has no normal) leaves the sample unshaded.
#pragma once

#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/classification_table.h"
#include "gpu/havs_fragment.h"
#include "gpu/pixel_rays.h"
#include "gpu/texture_sampling.h"

namespace uvr::gpu {

// Per-frame constants (uniforms): the pixels' rays (gpu/pixel_rays.h) relative to the box's centre, and the rest.
struct RaycastFrameConstants : PixelRays {
    glm::dvec3 box_lo{0.0}, box_hi{0.0};  // the samples' box, relative to its centre
    glm::dvec3 tex_scale{0.0};            // 1 / (dims * spacing): world units to texture coordinates
    glm::dvec3 tex_half{0.0};             // 0.5 / dims: texel 0's centre
    double step = 1.0;                    // world units
    int max_samples = 0;                  // no ray takes more (setup: the box's diagonal over the step, plus 2)
    int preintegrate = 0;
    float threshold = 0.95f;              // early termination (SPEC §3)
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

// The double part's results before their rounding to float: what the stage harness compares (gpu/gl_raycast_harness.h),
// so that a change in the double arithmetic shows even where it vanishes in the float it is rounded to.
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

// The textures the march reads, as the emulation holds them.
struct RaycastTextures {
    TextureView volume;                         // one channel, R8 / R16 / R32F
    const ClassificationTable* classification = nullptr;
    SegmentShader segment;                      // pre-integration (table as llvmpipe samples it, or exact)
    LlvmpipeCpu cpu;
};

struct RaycastResult {
    glm::vec4 colour{0.0f};
    uint32_t samples = 0;  // texture positions classified (pre-integration counts the exit too)
};

RaycastResult raycast_march(const RaycastFrameConstants& fc, const RaycastRay& ray, const RaycastTextures& tex);

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
