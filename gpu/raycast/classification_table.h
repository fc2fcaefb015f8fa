// The ray caster's post-classification table (Krüger and Westermann): per scalar, the colour and opacity of one step of
// the march, with the opacity corrected for the step length. Input: a SegmentIntegrator, the scalar range, the step, N
// texels. Output: N x 1 RGBA32F texels, and sample() as llvmpipe reads them (GL_LINEAR, CLAMP_TO_EDGE, at t = 0.5).
// Twins: shaders/classification_table.frag; uploaded by upload_raycast_textures (gpu/raycast/gl_raycast.h); harness
// gpu/raycast/gl_raycast_harness.h (run_march). Derivation: docs/raycast.md, "The post-classification table".
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include "gpu/pipeline/texture_sampling.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"

namespace uvr::gpu {

inline constexpr int kClassificationTexels = 4096;

class ClassificationTable {
public:
    // `range` as PreintegrationTable's (an empty range is widened to [lo, lo + 1]); step > 0 in world units. Throws
    // std::invalid_argument on a bad size or step.
    ClassificationTable(const SegmentIntegrator& integrator, Range range, double step,
                        int texels = kClassificationTexels);

    int size() const { return int(texels_.size() / 4); }
    double step() const { return step_; }
    double texel_scalar(int i) const;                  // the real scalar texel i holds
    const std::vector<float>& texels() const { return texels_; }  // RGBA, N texels
    TextureView view() const;                          // RGBA32F, N x 1

    // texture(table, vec2(u, 0.5)) as llvmpipe computes it, its path (sample_2d's) chosen once: a march samples the
    // table every step, and the usual path (RGBA32F, linear, FMA3) is then one direct call.
    struct Sampler {
        TextureView view;
        LlvmpipeCpu cpu;
        bool fma_path = false;  // takes_linear_f32x4_fma
        glm::vec4 operator()(float u) const
        {
            const float coord[3] = {u, 0.5f, 0.0f};
            return fma_path ? sample_linear_f32x4_fma(view, coord, 2)
                            : sample_2d(view, u, 0.5f, TextureFilter::linear, cpu);
        }
    };
    Sampler sampler(const LlvmpipeCpu& cpu) const;
    glm::vec4 sample(float u, const LlvmpipeCpu& cpu) const { return sampler(cpu)(u); }

private:
    Range range_;
    double step_;
    std::vector<float> texels_;
};

}  // namespace uvr::gpu
