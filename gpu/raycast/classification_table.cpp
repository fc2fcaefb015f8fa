#include "gpu/raycast/classification_table.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace uvr::gpu {

namespace {
// GL 4.5 guarantees GL_MAX_TEXTURE_SIZE >= 16384; llvmpipe gives 16384.
constexpr int kMaxTexels = 16384;
}  // namespace

ClassificationTable::ClassificationTable(const SegmentIntegrator& integrator, Range range, double step, int texels)
    : range_(range), step_(step)
{
    if (texels < 2 || texels > kMaxTexels)
        throw std::invalid_argument("classification table: size must be in [2, 16384], got " + std::to_string(texels));
    if (!(step > 0.0) || !std::isfinite(step))
        throw std::invalid_argument("classification table: the step must be positive and finite");
    if (!(range_.hi > range_.lo)) range_.hi = range_.lo + 1.0;
    texels_.resize(std::size_t(texels) * 4);
    for (int i = 0; i < texels; ++i) {
        const double s = texel_scalar(i);
        const glm::dvec4 v = integrator.integrate(s, s, step);
        for (int c = 0; c < 4; ++c) texels_[std::size_t(i) * 4 + std::size_t(c)] = static_cast<float>(v[c]);
    }
}

double ClassificationTable::texel_scalar(int i) const
{
    return range_.lo + (i + 0.5) / size() * (range_.hi - range_.lo);
}

TextureView ClassificationTable::view() const
{
    TextureView v;
    v.format = TexelFormat::f32;
    v.channels = 4;
    v.width = size();
    v.height = 1;
    v.depth = 1;
    v.texels = texels_.data();
    return v;
}

ClassificationTable::Sampler ClassificationTable::sampler(const LlvmpipeCpu& cpu) const
{
    const TextureView v = view();
    return {v, cpu, takes_linear_f32x4_fma(v, TextureFilter::linear, cpu)};
}

}  // namespace uvr::gpu
