#include "reference/segment_integral.h"

#include <algorithm>
#include <cmath>

#include "reference/special_functions.h"

namespace uvr {

namespace {

constexpr double kSqrtPi = 1.77245385090551602730;

// Terms below this contribute nothing at double precision to J, which lies in [e^{-(A+B)}, 1] and is used for
// absolute accuracy (kOracleTolerance in the tests is 1e-10).
constexpr double kNegligible = 1e-18;

// M_k(A) = integral_0^1 u^k exp(-A u) du for A <= 4 by its series sum_j (-A)^j / (j! (k + j + 1)): the largest term
// is below e^4 < 55, so at most two digits are lost to alternation; the loop stops once terms are negligible (a
// handful of terms for the thin cells that make up most segments).
double moment_series(double A, int k)
{
    double term = 1.0, sum = 1.0 / (k + 1);
    for (int j = 1; j < 80; ++j) {
        term *= -A / j;
        const double t = term / (k + j + 1);
        sum += t;
        if (std::fabs(t) < kNegligible) break;
    }
    return sum;
}

// J for |B| < kSmallQuadratic: sum_n (-B)^n / n! M_2n(A), stopping once the coefficient is negligible (M_2n <= 1).
// For A > 4, M_k comes from the upward recurrence M_k = (k M_{k-1} - e^{-A}) / A, whose errors are multiplied by
// k / A per step: at most 12! / 4^12 < 30 overall for the k <= 12 that |B| < 1e-3 can need.
double small_quadratic(double A, double B)
{
    double sum = 0.0, coef = 1.0;
    if (A <= 4.0) {
        for (int n = 0; n < 8 && std::fabs(coef) >= kNegligible; ++n) {
            sum += coef * moment_series(A, 2 * n);
            coef *= -B / (n + 1);
        }
        return sum;
    }
    const double ea = std::exp(-A);
    double m = -std::expm1(-A) / A;  // M_0
    for (int n = 0; n < 8 && std::fabs(coef) >= kNegligible; ++n) {
        sum += coef * m;
        coef *= -B / (n + 1);
        m = ((2 * n + 1) * m - ea) / A;  // M_{2n+1}
        m = ((2 * n + 2) * m - ea) / A;  // M_{2n+2}
    }
    return sum;
}

}  // namespace

double depth_average_transmittance(double A, double B)
{
    if (std::fabs(B) < kSmallQuadratic) {
        if (B == 0.0) return A == 0.0 ? 1.0 : -std::expm1(-A) / A;
        return small_quadratic(A, B);
    }
    const double ab = std::exp(-(A + B));
    if (B > 0.0) {
        const double sb = std::sqrt(B);
        const double x0 = A / (2.0 * sb);
        return kSqrtPi / (2.0 * sb) * (erfcx(x0) - ab * erfcx(x0 + sb));
    }
    const double sb = std::sqrt(-B);
    const double y1 = A / (2.0 * sb);
    // A + 2B >= 0 means y1 >= sqrt(-B), so y0 >= 0; clamp the rounding of exact equality.
    const double y0 = std::max(0.0, y1 - sb);
    return (dawson(y1) - ab * dawson(y0)) / sb;
}

glm::dvec4 integrate_linear_piece(const glm::dvec3& c0, const glm::dvec3& c1, double tau0, double tau1, double L)
{
    if (!(L > 0.0)) return glm::dvec4(0.0);
    const double A = tau0 * L;
    const double B = 0.5 * (tau1 - tau0) * L;
    const double depth = 0.5 * (tau0 + tau1) * L;
    const double trans = std::exp(-depth);
    const double alpha = -std::expm1(-depth);
    const double J = depth_average_transmittance(A, B);
    // C = c0 - c1 e^{-T} + (c1 - c0) J, rearranged as c0 (1 - J) + c1 (J - e^{-T}) so that both weights are
    // non-negative (J lies between e^{-T} and 1) and nothing cancels when the colour is constant.
    const double w0 = 1.0 - J;
    const double w1 = J - trans;
    const glm::dvec3 c = c0 * w0 + c1 * w1;
    return {c.x, c.y, c.z, alpha};
}

SegmentIntegrator::SegmentIntegrator(const TransferFunction& tf) : tf_(tf), breaks_(tf.breakpoints()) {}

void SegmentIntegrator::piece_ends(double sa, double sb, glm::dvec3& ca, glm::dvec3& cb, double& ta, double& tb) const
{
    const double mid = 0.5 * (sa + sb);
    auto eval = [mid](const auto& nodes, auto get, double s) {
        using V = decltype(get(nodes.front()));
        if (mid < nodes.front().s) return get(nodes.front());
        if (mid >= nodes.back().s) return get(nodes.back());
        auto it = std::upper_bound(nodes.begin(), nodes.end(), mid, [](double v, const auto& n) { return v < n.s; });
        const auto& b = *it;
        const auto& a = *(it - 1);
        const double w = (s - a.s) / (b.s - a.s);
        return V(get(a) + (get(b) - get(a)) * w);
    };
    auto color = [](const ColorNode& n) { return n.rgb; };
    auto tau = [](const ExtinctionNode& n) { return n.tau; };
    ca = eval(tf_.color, color, sa);
    cb = eval(tf_.color, color, sb);
    ta = eval(tf_.extinction, tau, sa);
    tb = eval(tf_.extinction, tau, sb);
}

glm::dvec4 SegmentIntegrator::integrate(double s_front, double s_back, double length) const
{
    if (!(length > 0.0)) return glm::dvec4(0.0);
    glm::dvec3 ca, cb;
    double ta, tb;
    if (s_front == s_back) {
        piece_ends(s_front, s_back, ca, cb, ta, tb);
        return integrate_linear_piece(ca, cb, ta, tb, length);
    }
    // Breakpoints strictly inside (s_front, s_back), visited in the ray's order.
    const double lo = std::min(s_front, s_back), hi = std::max(s_front, s_back);
    auto first = std::upper_bound(breaks_.begin(), breaks_.end(), lo);
    auto last = std::lower_bound(breaks_.begin(), breaks_.end(), hi);
    const double ds = s_back - s_front;
    glm::dvec4 acc(0.0);
    double s_prev = s_front, t_prev = 0.0;
    auto add_piece = [&](double s_next, double t_next) {
        piece_ends(s_prev, s_next, ca, cb, ta, tb);
        acc = composite_over(acc, integrate_linear_piece(ca, cb, ta, tb, t_next - t_prev));
        s_prev = s_next;
        t_prev = t_next;
    };
    const std::ptrdiff_t n = last - first;
    for (std::ptrdiff_t k = 0; k < n; ++k) {
        const double b = s_front < s_back ? first[k] : first[n - 1 - k];
        add_piece(b, length * ((b - s_front) / ds));
    }
    add_piece(s_back, length);
    return acc;
}

}  // namespace uvr
