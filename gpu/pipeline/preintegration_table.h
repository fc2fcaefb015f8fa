// Pre-integration tables: the 3D table HAVS looks segments up in (VICP and the ray caster's --preintegrate too), and
// Moreland's 2D partial pre-integration table (Ψ). Input: a SegmentIntegrator, the scalar range, the configuration
// (N, L, max_length, format). Output: the texels, laid out as glTexImage3D takes them, and lookups as llvmpipe
// samples them (gpu/pipeline/texture_sampling.h).
// Twins: shaders/preintegration_table.frag (the 3D table's lookup); upload gpu/gl/gl_preintegration_table.h; what a
// segment contributes gpu/pipeline/segment.h. The Ψ table has none (CPU only).
// Derivation (layout, texel centres, the length axis): docs/tables.md, "Layout and texel centres".
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/pipeline/huge_pages.h"
#include "gpu/pipeline/texture_sampling.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"

namespace uvr::gpu {

// The scalar range a table of `texels` texels per scalar axis spans so that its first and last texel centres hold the
// data's extreme values: the data's range widened by half a texel at each end. Shaders look the table up by the scalar
// normalized over this range. Over the data's own range (texel i at s_min + (i + 0.5) / N of the span) the normalized
// scalars in [0, 0.5 / N] and [1 - 0.5 / N, 1] would clamp to edge texels holding other scalars: an error of order 1 /
// N wherever values crowd the range's ends (docs/tables.md, "Measured errors"; docs/raycast.md). An empty range is
// widened to one unit first, as default_transfer_function does. The ray caster's tables use it; HAVS and VICP keep
// docs/spec.md §1's normalization over the field's own range (measured on the shared meshes, where it does better:
// docs/tables.md, "The scalar axes' ends").
Range texel_centred_range(const Range& data, int texels);

struct PreintegrationConfig {
    int scalar_resolution = 128;  // N: texels along the front and the back scalar, >= 2
    int length_resolution = 128;  // L: texels along the length, >= 2
    double max_length = 1.0;      // world units held by the last length texel (> 0); the caller picks it, e.g. the
                                  // longest segment a mesh can produce
    TexelFormat format = TexelFormat::f32;
};

class PreintegrationTable {
public:
    // Builds the table in parallel (TBB; each texel is independent, so the result does not depend on the
    // scheduling). `range` is the field's scalar range [s_min, s_max]; an empty range (s_max <= s_min) is widened to
    // [s_min, s_min + 1] as default_transfer_function does. Throws std::invalid_argument on a bad configuration.
    PreintegrationTable(const SegmentIntegrator& integrator, Range range, const PreintegrationConfig& config);

    const PreintegrationConfig& config() const { return config_; }
    Range scalar_range() const { return range_; }
    int scalar_resolution() const { return config_.scalar_resolution; }
    int length_resolution() const { return config_.length_resolution; }

    // The real scalar texel i holds (both scalar axes) and the length texel l holds.
    double texel_scalar(int i) const;
    double texel_length(int l) const;

    // The texture coordinates, in float32. normalized_scalar rounds (s - s_min) / (s_max - s_min), computed in double,
    // to float (how a CPU prepares a vertex attribute); how a shader stage computes its coordinate is that stage's
    // business. length_scale and length_bias are the published sz.z and sz.w rounded to float, and length_coordinate
    // is t.z = d * sz.z + sz.w in float, fused (one rounding, as an FMA) or not.
    float normalized_scalar(double s) const;
    float length_scale() const { return length_scale_; }  // (1 - 1/L) / max_len
    float length_bias() const { return length_bias_; }    // 1 / (2L)
    float length_coordinate(float d, bool fused = false) const;

    // The stored texels: N * N * L * 4 values of the configured format, layout above.
    const void* data() const;
    std::size_t size_bytes() const;
    std::size_t texel_count() const { return texel_count_; }
    // The texel as the GPU reads it (unorm converted as llvmpipe converts it), and the view for texture_sampling.
    glm::vec4 texel(int i, int j, int l) const;
    TextureView view() const;

    // texture(table, vec3(u_front, u_back, t_z)) as llvmpipe computes it (GL_LINEAR by default).
    glm::vec4 sample(float u_front, float u_back, float t_z, const LlvmpipeCpu& cpu,
                     TextureFilter filter = TextureFilter::linear) const;
    // The same from real scalars and a length: sample(normalized_scalar(s_front), normalized_scalar(s_back),
    // length_coordinate(float(length))).
    glm::vec4 lookup(double s_front, double s_back, double length, const LlvmpipeCpu& cpu,
                     TextureFilter filter = TextureFilter::linear) const;

private:
    PreintegrationConfig config_;
    Range range_;
    float inv_range_ = 1.0f, length_scale_ = 0.0f, length_bias_ = 0.0f;
    std::size_t texel_count_ = 0;
    HugeVector<float> f32_;  // huge pages: docs/gl-backend.md, "Speed"
    HugeVector<uint16_t> u16_;
    HugeVector<uint8_t> u8_;
};

// ---- Moreland & Angel's partial pre-integration ("A fast high accuracy volume renderer for unstructured data",
// VolVis 2004; Moreland's dissertation, 2004) ----
//
// On a piece of length D where colour goes linearly c_f -> c_b and extinction τ_f -> τ_b, write ζ = exp(-(τ_f +
// τ_b) D / 2) (the piece's transmittance) and Ψ = (1/D) ∫_0^D exp(-∫_0^t τ) dt (its mean transmittance, J of
// segment_integral.h). Then
//     C = c_f (1 - Ψ) + c_b (Ψ - ζ),   α = 1 - ζ,
// and Ψ depends only on the two optical depths τ_f D and τ_b D: it is tabulated once for every transfer function,
// over γ = τD / (τD + 1) in [0, 1) on both axes. The table holds Ψ at γ_f = i / M (x), γ_b = j / M (y), and a
// shader reads it at (γ_f + 0.5 / M, γ_b + 0.5 / M) with bilinear filtering (Moreland's Cg listing; his texture's
// x is the back value, here x is the front to match the 3D table).
class PsiTable {
public:
    explicit PsiTable(int resolution = 512);  // built in parallel (TBB), deterministic

    int resolution() const { return m_; }
    float texel(int i, int j) const { return psi_[std::size_t(j) * std::size_t(m_) + std::size_t(i)]; }
    const std::vector<float>& texels() const { return psi_; }
    TextureView view() const;  // R32F, M x M

    static double gamma(double optical_depth) { return optical_depth / (optical_depth + 1.0); }
    // Ψ from the table by bilinear interpolation in double (the interpolation a GPU's linear filter does, without
    // its float rounding), clamped to the edge like CLAMP_TO_EDGE.
    double lookup(double gamma_front, double gamma_back) const;
    // The same through the emulated llvmpipe sampler (R32F, GL_LINEAR), coordinates in float.
    float lookup_emulated(float gamma_front, float gamma_back, const LlvmpipeCpu& cpu) const;

private:
    int m_;
    std::vector<float> psi_;
};

// The premultiplied RGBA of one linear piece (colour c_f -> c_b, extinction tau_f -> tau_b over `length`) by
// Moreland's reconstruction from the Ψ table (double-precision lookup).
glm::dvec4 psi_integrate_piece(const PsiTable& psi, const glm::dvec3& c_front, const glm::dvec3& c_back,
                               double tau_front, double tau_back, double length);

// Partial pre-integration of whole segments for a piecewise-linear transfer function: the segment is split where the
// scalar crosses a node (as SegmentIntegrator does), each piece goes through psi_integrate_piece, and the pieces
// composite front to back. Exact but for the Ψ table's interpolation error.
class PsiSegmentIntegrator {
public:
    PsiSegmentIntegrator(const TransferFunction& tf, const PsiTable& psi);
    glm::dvec4 integrate(double s_front, double s_back, double length) const;

private:
    TransferFunction tf_;
    const PsiTable& psi_;
    std::vector<double> breaks_;
};

}  // namespace uvr::gpu
