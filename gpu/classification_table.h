// The ray caster's post-classification table (seed 002): per scalar, the colour and opacity of one step of the march,
// with the opacity corrected for the step length. Its GLSL twin is shaders/classification_table.frag.
//
// A sample stands for a piece of the ray of length `step` on which the scalar is taken constant, so by SPEC §1 it
// contributes alpha = 1 - exp(-tau(s) * step) and premultiplied colour c(s) * alpha (the emission integral with
// constant c and tau). Texel i holds exactly that, computed in double by SegmentIntegrator (a segment of constant
// scalar) and rounded to float, for the scalar whose normalized value is u = (i + 0.5) / N: the texel-centre
// convention of the pre-integrated table (gpu/preintegration_table.h), so both tables are looked up by the same
// normalized scalar. Correcting the opacity in the table rather than in the shader keeps exp() out of the shader:
// llvmpipe's exp is a polynomial of its own, and the emulation would have to mirror it (docs/raycast.md).
//
// The table is a 2D texture of N x 1 RGBA32F texels (GL_LINEAR, CLAMP_TO_EDGE) read at t = 0.5; N = 4096 by default,
// whose linear interpolation between texels is below the float rounding of the texels for the smooth transfer
// functions of the data sets (docs/raycast.md measures it).
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include "gpu/texture_sampling.h"
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

    // texture(table, vec2(u, 0.5)) as llvmpipe computes it.
    glm::vec4 sample(float u, const LlvmpipeCpu& cpu) const;

private:
    Range range_;
    double step_;
    std::vector<float> texels_;
};

}  // namespace uvr::gpu
