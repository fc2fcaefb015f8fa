// Pre-integration tables: building them (exact integrals, quantized as Mesa quantizes an upload) and reading them.
#include "gpu/pipeline/preintegration_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace uvr::gpu {

Range texel_centred_range(const Range& data, int texels)
{
    const double span = data.hi > data.lo ? data.hi - data.lo : 1.0;
    Range r;
    r.lo = data.lo - 0.5 * span / double(texels - 1);
    r.hi = r.lo + span * double(texels) / double(texels - 1);
    return r;
}

namespace {

// Up to 4096 texels per axis (a 4096^2 x 4096 table would be 2^38 texels: the limit only guards the size arithmetic).
constexpr int kMaxResolution = 4096;

void check_config(const PreintegrationConfig& c)
{
    auto fail = [](const std::string& what) { throw std::invalid_argument("pre-integration table: " + what); };
    if (c.scalar_resolution < 2 || c.scalar_resolution > kMaxResolution)
        fail("scalar resolution must be in [2, 4096], got " + std::to_string(c.scalar_resolution));
    if (c.length_resolution < 2 || c.length_resolution > kMaxResolution)
        fail("length resolution must be in [2, 4096], got " + std::to_string(c.length_resolution));
    if (!(c.max_length > 0.0) || !std::isfinite(c.max_length))
        fail("maximum length must be positive and finite, got " + std::to_string(c.max_length));
}

}  // namespace

PreintegrationTable::PreintegrationTable(const SegmentIntegrator& integrator, Range range,
                                         const PreintegrationConfig& config)
    : config_(config), range_(range)
{
    check_config(config_);
    if (!(range_.hi > range_.lo)) range_.hi = range_.lo + 1.0;
    const int n = config_.scalar_resolution, nl = config_.length_resolution;
    inv_range_ = static_cast<float>(1.0 / (range_.hi - range_.lo));
    length_scale_ = static_cast<float>((1.0 - 1.0 / nl) / config_.max_length);
    length_bias_ = static_cast<float>(1.0 / (2.0 * nl));
    texel_count_ = std::size_t(n) * std::size_t(n) * std::size_t(nl);
    const std::size_t values = texel_count_ * 4;
    switch (config_.format) {
    case TexelFormat::f32: f32_.resize(values); break;
    case TexelFormat::u16: u16_.resize(values); break;
    case TexelFormat::u8: u8_.resize(values); break;
    }

    // One row (fixed back scalar j and length l) per task. Every texel is a pure function of (i, j, l), written to
    // its own place, so the table is the same bits whatever the thread count and scheduling.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, std::size_t(n) * std::size_t(nl)),
                      [&](const tbb::blocked_range<std::size_t>& rows) {
        for (std::size_t row = rows.begin(); row != rows.end(); ++row) {
            const int j = int(row % std::size_t(n)), l = int(row / std::size_t(n));
            const double s_back = texel_scalar(j), d = texel_length(l);
            for (int i = 0; i < n; ++i) {
                const glm::dvec4 v = integrator.integrate(texel_scalar(i), s_back, d);
                const std::size_t at = (row * std::size_t(n) + std::size_t(i)) * 4;
                for (int c = 0; c < 4; ++c) {
                    // The value a GL upload of float data would carry, then Mesa's conversion of it.
                    const float f = static_cast<float>(v[c]);
                    switch (config_.format) {
                    case TexelFormat::f32: f32_[at + std::size_t(c)] = f; break;
                    case TexelFormat::u16: u16_[at + std::size_t(c)] = float_to_unorm16(f); break;
                    case TexelFormat::u8: u8_[at + std::size_t(c)] = float_to_unorm8(f); break;
                    }
                }
            }
        }
    });
}

double PreintegrationTable::texel_scalar(int i) const
{
    return range_.lo + (i + 0.5) / config_.scalar_resolution * (range_.hi - range_.lo);
}

double PreintegrationTable::texel_length(int l) const
{
    return l * config_.max_length / (config_.length_resolution - 1);
}

float PreintegrationTable::normalized_scalar(double s) const
{
    return static_cast<float>((s - range_.lo) / (range_.hi - range_.lo));
}

float PreintegrationTable::length_coordinate(float d, bool fused) const
{
    if (fused) return std::fma(d, length_scale_, length_bias_);
    const float scaled = d * length_scale_;
    return scaled + length_bias_;
}

const void* PreintegrationTable::data() const
{
    switch (config_.format) {
    case TexelFormat::f32: return f32_.data();
    case TexelFormat::u16: return u16_.data();
    case TexelFormat::u8: return u8_.data();
    }
    return nullptr;
}

std::size_t PreintegrationTable::size_bytes() const
{
    return texel_count_ * 4 * std::size_t(texel_channel_bytes(config_.format));
}

TextureView PreintegrationTable::view() const
{
    TextureView v;
    v.format = config_.format;
    v.channels = 4;
    v.width = v.height = config_.scalar_resolution;
    v.depth = config_.length_resolution;
    v.texels = data();
    return v;
}

glm::vec4 PreintegrationTable::texel(int i, int j, int l) const { return texel_fetch(view(), i, j, l); }

glm::vec4 PreintegrationTable::sample(float u_front, float u_back, float t_z, const LlvmpipeCpu& cpu,
                                      TextureFilter filter) const
{
    return sample_3d(view(), u_front, u_back, t_z, filter, cpu);
}

glm::vec4 PreintegrationTable::lookup(double s_front, double s_back, double length, const LlvmpipeCpu& cpu,
                                      TextureFilter filter) const
{
    return sample(normalized_scalar(s_front), normalized_scalar(s_back),
                  length_coordinate(static_cast<float>(length)), cpu, filter);
}

// ---- Ψ ----

PsiTable::PsiTable(int resolution) : m_(resolution)
{
    if (m_ < 2 || m_ > kMaxResolution)
        throw std::invalid_argument("Psi table: resolution must be in [2, 4096], got " + std::to_string(m_));
    psi_.resize(std::size_t(m_) * std::size_t(m_));
    // Texel (i, j) holds Ψ at γ_f = i / M, γ_b = j / M, i.e. optical depths x = γ / (1 - γ) (finite: γ < 1). With
    // A = x_f and B = (x_b - x_f) / 2, J(A, B) = ∫_0^1 exp(-(A u + B u^2)) du is exactly Ψ, and A + 2B = x_b >= 0
    // is the domain depth_average_transmittance needs.
    tbb::parallel_for(tbb::blocked_range<int>(0, m_), [&](const tbb::blocked_range<int>& rows) {
        for (int j = rows.begin(); j != rows.end(); ++j) {
            const double gb = double(j) / m_, xb = gb / (1.0 - gb);
            for (int i = 0; i < m_; ++i) {
                const double gf = double(i) / m_, xf = gf / (1.0 - gf);
                psi_[std::size_t(j) * std::size_t(m_) + std::size_t(i)] =
                    static_cast<float>(depth_average_transmittance(xf, 0.5 * (xb - xf)));
            }
        }
    });
}

TextureView PsiTable::view() const
{
    TextureView v;
    v.format = TexelFormat::f32;
    v.channels = 1;
    v.width = v.height = m_;
    v.depth = 1;
    v.texels = psi_.data();
    return v;
}

double PsiTable::lookup(double gamma_front, double gamma_back) const
{
    // Texel space: the coordinate γ + 0.5 / M times M, minus the half texel, is γ M.
    auto taps = [this](double g, int& i0, int& i1, double& w) {
        const double u = g * m_;
        if (!(u > 0.0)) {
            i0 = i1 = 0;
            w = 0.0;
        } else if (u >= m_ - 1) {
            i0 = i1 = m_ - 1;
            w = 0.0;
        } else {
            i0 = int(u);
            i1 = i0 + 1;
            w = u - i0;
        }
    };
    int x0, x1, y0, y1;
    double wx, wy;
    taps(gamma_front, x0, x1, wx);
    taps(gamma_back, y0, y1, wy);
    const double r0 = texel(x0, y0) + wx * (double(texel(x1, y0)) - texel(x0, y0));
    const double r1 = texel(x0, y1) + wx * (double(texel(x1, y1)) - texel(x0, y1));
    return r0 + wy * (r1 - r0);
}

float PsiTable::lookup_emulated(float gamma_front, float gamma_back, const LlvmpipeCpu& cpu) const
{
    const float half_texel = 0.5f / static_cast<float>(m_);
    return sample_2d(view(), gamma_front + half_texel, gamma_back + half_texel, TextureFilter::linear, cpu).r;
}

glm::dvec4 psi_integrate_piece(const PsiTable& psi, const glm::dvec3& c_front, const glm::dvec3& c_back,
                               double tau_front, double tau_back, double length)
{
    if (!(length > 0.0)) return glm::dvec4(0.0);
    const double xf = tau_front * length, xb = tau_back * length;
    const double depth = 0.5 * (xf + xb);
    const double alpha = -std::expm1(-depth);
    const double zeta = 1.0 - alpha;
    const double p = psi.lookup(PsiTable::gamma(xf), PsiTable::gamma(xb));
    const glm::dvec3 c = c_front * (1.0 - p) + c_back * (p - zeta);
    return {c.r, c.g, c.b, alpha};
}

PsiSegmentIntegrator::PsiSegmentIntegrator(const TransferFunction& tf, const PsiTable& psi)
    : tf_(tf), psi_(psi), breaks_(tf.breakpoints())
{
}

glm::dvec4 PsiSegmentIntegrator::integrate(double s_front, double s_back, double length) const
{
    if (!(length > 0.0)) return glm::dvec4(0.0);
    // The scalars where the segment crosses a node, in ray order.
    std::vector<double> cuts;
    const double lo = std::min(s_front, s_back), hi = std::max(s_front, s_back);
    for (double b : breaks_)
        if (b > lo && b < hi) cuts.push_back(b);
    if (s_back < s_front) std::reverse(cuts.begin(), cuts.end());
    cuts.push_back(s_back);

    // On each piece colour and extinction are linear in s; their end values come from two interior points, which
    // lie in one node interval, so a jump (two nodes at one s) is taken from the piece's own side.
    auto ends = [this](double sa, double sb, glm::dvec3& ca, glm::dvec3& cb, double& ta, double& tb) {
        const double q1 = sa + 0.25 * (sb - sa), q3 = sa + 0.75 * (sb - sa);
        const glm::dvec3 c1 = tf_.color_at(q1), c3 = tf_.color_at(q3);
        const double t1 = tf_.tau_at(q1), t3 = tf_.tau_at(q3);
        ca = c1 - 0.5 * (c3 - c1);
        cb = c3 + 0.5 * (c3 - c1);
        ta = std::max(0.0, t1 - 0.5 * (t3 - t1));
        tb = std::max(0.0, t3 + 0.5 * (t3 - t1));
    };
    glm::dvec4 acc(0.0);
    double s_prev = s_front, t_prev = 0.0;
    for (double s : cuts) {
        const double t = s == s_back ? length : length * ((s - s_front) / (s_back - s_front));
        glm::dvec3 ca, cb;
        double ta, tb;
        ends(s_prev, s, ca, cb, ta, tb);
        acc = composite_over(acc, psi_integrate_piece(psi_, ca, cb, ta, tb, t - t_prev));
        s_prev = s;
        t_prev = t;
    }
    return acc;
}

}  // namespace uvr::gpu
