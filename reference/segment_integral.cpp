#include "reference/segment_integral.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include <immintrin.h>

#include "reference/special_functions.h"

namespace uvr {

namespace {

constexpr double kSqrtPi = 1.77245385090551602730;

// Terms below this contribute nothing at double precision to J, which lies in [e^{-(A+B)}, 1] and is used for
// absolute accuracy (kOracleTolerance in the tests is 1e-10): 1e-17 is a tenth of an ulp of 1.
constexpr double kNegligible = 1e-17;

// J for |B| < kSmallQuadratic: sum_n (-B)^n / n! M_2n(A), stopping once the coefficient is negligible (M_2n <= 1).
// For A <= 4, M_k(A) = integral_0^1 u^k exp(-A u) du comes from its series sum_j (-A)^j / (j! (k + j + 1)), with
// the powers (-A)^j / j! computed once for all k; the largest is below e^4 < 55, so at most two digits are lost to
// alternation, and the series stops once terms are negligible (a handful of terms for the thin cells that make up
// most segments). For A > 4, M_k comes from the upward recurrence M_k = (k M_{k-1} - e^{-A}) / A, whose errors are
// multiplied by k / A per step: at most 12! / 4^12 < 30 overall for the k <= 12 that |B| < 1e-3 can need.
double small_quadratic(double A, double B)
{
    double sum = 0.0, coef = 1.0;
    if (A <= 4.0) {
        // 1 / (k + 1) for k < 96: the divisions of both series, done once.
        static const auto inv = [] {
            std::array<double, 96> t{};
            for (std::size_t k = 0; k < t.size(); ++k) t[k] = 1.0 / double(k + 1);
            return t;
        }();
        double pw[80];
        int terms = 0;
        for (double p = 1.0; terms < 80; ++terms) {
            pw[terms] = p;
            if (std::fabs(p) < kNegligible) break;
            p *= -A * inv[std::size_t(terms)];
        }
        for (int n = 0; n < 8 && std::fabs(coef) >= kNegligible; ++n) {
            double m = 0.0;
            for (int j = 0; j < terms; ++j) m += pw[j] * inv[std::size_t(2 * n + j)];
            sum += coef * m;
            coef *= -B * inv[std::size_t(n)];
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

// 1 - e^{-d}. Most pieces of a fine mesh are optically thin: below d = 1/32 the alternating series
// d - d^2/2 + ... - d^8/8! has first omitted term d^9/9! < 1e-19 (relative error ~1e-16, as expm1's), at a fraction of
// expm1's cost. Evaluated by Estrin's scheme (pairs of terms, then powers d^2 and d^4) rather than Horner's, so that
// its chain of dependent operations is three multiplications deep instead of eight.
double opacity_of_depth(double d)
{
    if (!(d < 0.03125)) return -std::expm1(-d);
    const double d2 = d * d, d4 = d2 * d2;
    const double p01 = 1.0 - d * 0.5, p23 = 1.0 / 6.0 - d * (1.0 / 24.0);
    const double p45 = 1.0 / 120.0 - d * (1.0 / 720.0), p67 = 1.0 / 5040.0 - d * (1.0 / 40320.0);
    return d * ((p01 + d2 * p23) + d4 * (p45 + d2 * p67));
}

// Below this optical size S = A + |B| of a piece, integrate_linear_piece takes 1 - J from its power series
// (thin_one_minus_j) instead of subtracting J from 1, which keeps only the digits the difference from 1 holds: J's
// absolute error of ~1e-16 is 1e-7 of 1 - J at a depth of 1e-9. Above it 1 - J >= S / 3 > 5e-3, so the subtraction
// costs at most 2e-14 relative; below it the series needs at most 7 terms.
constexpr double kThinDepth = 1.0 / 64.0;
constexpr int kThinTerms = 7;  // the most terms a piece below kThinDepth needs (thin_one_minus_j)

// 1 - J = int_0^1 (1 - e^{-f(u)}) du with f(u) = A u + B u^2 (the optical depth to the fraction u of the piece)
//       = sum_{n>=1} (-1)^{n+1} / n! I_n,   I_n = int_0^1 f(u)^n du = sum_j C(n, j) A^{n-j} B^j / (n + j + 1).
// No two nearly equal values are subtracted (A >= 0; B < 0 only with A + 2B >= 0, where the j terms alternate with a
// ratio below 1/2). The first term left out, n = kThinTerms + 1, is below S^8 / 8!, under 1.7e-17 of the sum (>= S / 3)
// for S = A + |B| < kThinDepth, so every piece takes all seven terms. They are summed as sum_j B^j P_j(A) with
// P_j(A) = sum_n c_{n,j} A^{n-j} (Horner in A for each j, then in B): eight short chains a processor runs side by side.
// The coefficients c_{n,j} = (-1)^{n+1} C(n, j) / (n! (n + j + 1)) come from a table computed at compile time.
// Derivation: docs/reference.md, "Thin pieces". kThinCoef[j][m] = c_{j+m, j}: the coefficient of A^m in P_j (zero
// where j + m is 0 or above kThinTerms).
constexpr auto kThinCoef = [] {
    std::array<std::array<double, kThinTerms + 1>, kThinTerms + 1> c{};
    double fact = 1.0;
    for (int n = 1; n <= kThinTerms; ++n) {
        fact *= n;
        double binom = 1.0;
        for (int j = 0; j <= n; ++j) {
            c[std::size_t(j)][std::size_t(n - j)] = (n % 2 ? 1.0 : -1.0) * binom / (fact * double(n + j + 1));
            binom = binom * double(n - j) / double(j + 1);
        }
    }
    return c;
}();

double thin_one_minus_j(double A, double B)
{
    double w = 0.0;
#pragma GCC unroll 8
    for (int j = kThinTerms; j >= 0; --j) {
        const auto& c = kThinCoef[std::size_t(j)];
        double p = 0.0;
#pragma GCC unroll 8
        for (int m = kThinTerms - j; m >= 0; --m) p = p * A + c[std::size_t(m)];
        w = w * B + p;
    }
    return w;
}

// Eight thin pieces at once in two sets of AVX2 lanes (A + |B| < kThinDepth for every lane, so depth < 1/32 too),
// the two sets' chains interleaved: the operations of opacity_of_depth, thin_one_minus_j and integrate_linear_piece in
// the same order, one IEEE operation per lane for each scalar one (no fused multiply-add: the target is AVX2 alone),
// hence the same bits. Inputs and outputs are arrays of kThinLanes; c0 and c1 and out by channel.
constexpr std::size_t kThinLanes = 8;
__attribute__((target("avx2"))) void thin_pieces_avx2(const double* A, const double* B, const double* depth,
                                                      const double* c0, const double* c1, double* out)
{
    constexpr int kSets = int(kThinLanes / 4);
    __m256d a[kSets], b[kSets], d[kSets], alpha[kSets], w0[kSets], w1[kSets];
#pragma GCC unroll 2
    for (int h = 0; h < kSets; ++h) {
        a[h] = _mm256_loadu_pd(A + 4 * h);
        b[h] = _mm256_loadu_pd(B + 4 * h);
        d[h] = _mm256_loadu_pd(depth + 4 * h);
        const __m256d d2 = _mm256_mul_pd(d[h], d[h]), d4 = _mm256_mul_pd(d2, d2);
        const __m256d p01 = _mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(d[h], _mm256_set1_pd(0.5)));
        const __m256d p23 = _mm256_sub_pd(_mm256_set1_pd(1.0 / 6.0), _mm256_mul_pd(d[h], _mm256_set1_pd(1.0 / 24.0)));
        const __m256d p45 =
            _mm256_sub_pd(_mm256_set1_pd(1.0 / 120.0), _mm256_mul_pd(d[h], _mm256_set1_pd(1.0 / 720.0)));
        const __m256d p67 =
            _mm256_sub_pd(_mm256_set1_pd(1.0 / 5040.0), _mm256_mul_pd(d[h], _mm256_set1_pd(1.0 / 40320.0)));
        alpha[h] = _mm256_mul_pd(d[h], _mm256_add_pd(_mm256_add_pd(p01, _mm256_mul_pd(d2, p23)),
                                                     _mm256_mul_pd(d4, _mm256_add_pd(p45, _mm256_mul_pd(d2, p67)))));
        w0[h] = _mm256_setzero_pd();
    }
#pragma GCC unroll 8
    for (int j = kThinTerms; j >= 0; --j) {
        const auto& c = kThinCoef[std::size_t(j)];
        __m256d p[kSets];
#pragma GCC unroll 2
        for (int h = 0; h < kSets; ++h) p[h] = _mm256_setzero_pd();
#pragma GCC unroll 8
        for (int m = kThinTerms - j; m >= 0; --m)
#pragma GCC unroll 2
            for (int h = 0; h < kSets; ++h)
                p[h] = _mm256_add_pd(_mm256_mul_pd(p[h], a[h]), _mm256_set1_pd(c[std::size_t(m)]));
#pragma GCC unroll 2
        for (int h = 0; h < kSets; ++h) w0[h] = _mm256_add_pd(_mm256_mul_pd(w0[h], b[h]), p[h]);
    }
#pragma GCC unroll 2
    for (int h = 0; h < kSets; ++h) {
        w1[h] = _mm256_sub_pd(alpha[h], w0[h]);
        for (int ch = 0; ch < 3; ++ch) {
            const std::size_t at = std::size_t(ch) * kThinLanes + std::size_t(4 * h);
            const __m256d x = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(c0 + at), w0[h]),
                                            _mm256_mul_pd(_mm256_loadu_pd(c1 + at), w1[h]));
            _mm256_storeu_pd(out + at, x);
        }
        _mm256_storeu_pd(out + 3 * kThinLanes + std::size_t(4 * h), alpha[h]);
    }
}

bool host_has_avx2()
{
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
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
    const double alpha = opacity_of_depth(depth);
    // C = c0 - c1 e^{-T} + (c1 - c0) J, rearranged as c0 (1 - J) + c1 (J - e^{-T}) so that both weights are
    // non-negative (J lies between e^{-T} and 1) and nothing cancels when the colour is constant.
    double w0, w1;
    if (A + std::fabs(B) < kThinDepth) {
        // w0 + w1 = 1 - e^{-T} = alpha: w1 from the two accurate values loses at most a factor 3 (w1 >= alpha / 3).
        w0 = thin_one_minus_j(A, B);
        w1 = alpha - w0;
    } else {
        const double J = depth_average_transmittance(A, B);
        w0 = 1.0 - J;
        w1 = J - (1.0 - alpha);  // e^{-T} to an absolute 1e-16: at most 2e-13 of w1 here (w1 >= alpha / 3)
    }
    const glm::dvec3 c = c0 * w0 + c1 * w1;
    return {c.x, c.y, c.z, alpha};
}

SegmentIntegrator::SegmentIntegrator(const TransferFunction& tf) : tf_(tf), breaks_(tf.breakpoints())
{
    // The linear formula of a node list on [lo, hi], from the node interval containing the midpoint.
    auto formula = [](const auto& nodes, auto get, double lo, double hi, auto& v, auto& dv) {
        const double mid = 0.5 * (lo + hi);
        using V = std::decay_t<decltype(get(nodes.front()))>;
        if (!(mid >= nodes.front().s)) {
            v = get(nodes.front());
            dv = V(0.0);
            return;
        }
        if (mid >= nodes.back().s) {
            v = get(nodes.back());
            dv = V(0.0);
            return;
        }
        auto it = std::upper_bound(nodes.begin(), nodes.end(), mid, [](double x, const auto& n) { return x < n.s; });
        const auto& b = *it;
        const auto& a = *(it - 1);
        dv = (get(b) - get(a)) / (b.s - a.s);
        v = get(a) + dv * (lo - a.s);
    };
    const std::size_t n = breaks_.size();
    pieces_.resize(n + 1);
    for (std::size_t k = 0; k <= n; ++k) {
        // The ends are constant: evaluate them just outside the first and last breakpoint.
        const double lo = k == 0 ? breaks_.front() - 1.0 : breaks_[k - 1];
        const double hi = k == n ? breaks_.back() + 1.0 : breaks_[k];
        Piece& p = pieces_[k];
        p.lo = lo;
        formula(tf_.color, [](const ColorNode& c) { return c.rgb; }, lo, hi, p.c, p.dc);
        formula(tf_.extinction, [](const ExtinctionNode& e) { return e.tau; }, lo, hi, p.tau, p.dtau);
    }
}

glm::dvec4 SegmentIntegrator::integrate_piece(const Piece& p, double sa, double sb, double length) const
{
    const glm::dvec3 ca = p.c + p.dc * (sa - p.lo), cb = p.c + p.dc * (sb - p.lo);
    return integrate_linear_piece(ca, cb, p.tau + p.dtau * (sa - p.lo), p.tau + p.dtau * (sb - p.lo), length);
}

glm::dvec4 SegmentIntegrator::integrate(double s_front, double s_back, double length) const
{
    if (!(length > 0.0)) return glm::dvec4(0.0);
    const double ds = s_back - s_front;
    if (s_back >= s_front) {
        // Interval of s_front seen from above (a breakpoint exactly at s_front belongs to the piece after it).
        std::size_t k = std::size_t(std::upper_bound(breaks_.begin(), breaks_.end(), s_front) - breaks_.begin());
        if (k == breaks_.size() || !(breaks_[k] < s_back)) return integrate_piece(pieces_[k], s_front, s_back, length);
        glm::dvec4 acc(0.0);
        double s_prev = s_front, t_prev = 0.0;
        for (; k < breaks_.size() && breaks_[k] < s_back; ++k) {
            const double t = length * ((breaks_[k] - s_front) / ds);
            acc = composite_over(acc, integrate_piece(pieces_[k], s_prev, breaks_[k], t - t_prev));
            s_prev = breaks_[k];
            t_prev = t;
        }
        return composite_over(acc, integrate_piece(pieces_[k], s_prev, s_back, length - t_prev));
    }
    // Descending: the interval of s_front seen from below (a breakpoint exactly at s_front belongs to the piece
    // before it).
    std::size_t k = std::size_t(std::lower_bound(breaks_.begin(), breaks_.end(), s_front) - breaks_.begin());
    if (k == 0 || !(breaks_[k - 1] > s_back)) return integrate_piece(pieces_[k], s_front, s_back, length);
    glm::dvec4 acc(0.0);
    double s_prev = s_front, t_prev = 0.0;
    for (; k > 0 && breaks_[k - 1] > s_back; --k) {
        const double t = length * ((breaks_[k - 1] - s_front) / ds);
        acc = composite_over(acc, integrate_piece(pieces_[k], s_prev, breaks_[k - 1], t - t_prev));
        s_prev = breaks_[k - 1];
        t_prev = t;
    }
    return composite_over(acc, integrate_piece(pieces_[k], s_prev, s_back, length - t_prev));
}

const SegmentIntegrator::Piece* SegmentIntegrator::single_piece(double s_front, double s_back, std::size_t& k) const
{
    // integrate()'s interval of s_front: upper_bound ascending, lower_bound descending; `k` (the previous segment's)
    // is tried first, as consecutive segments of a ray mostly lie in one interval.
    const std::size_t n = breaks_.size();
    if (s_back >= s_front) {
        if (!((k == 0 || breaks_[k - 1] <= s_front) && (k == n || s_front < breaks_[k])))
            k = std::size_t(std::upper_bound(breaks_.begin(), breaks_.end(), s_front) - breaks_.begin());
        return k == n || !(breaks_[k] < s_back) ? &pieces_[k] : nullptr;
    }
    if (!((k == 0 || breaks_[k - 1] < s_front) && (k == n || s_front <= breaks_[k])))
        k = std::size_t(std::lower_bound(breaks_.begin(), breaks_.end(), s_front) - breaks_.begin());
    return k == 0 || !(breaks_[k - 1] > s_back) ? &pieces_[k] : nullptr;
}

void SegmentIntegrator::integrate_many(std::size_t n, const double* s_front, const double* s_back, const double* length,
                                       glm::dvec4* out) const
{
    if (!host_has_avx2()) {
        for (std::size_t i = 0; i < n; ++i) out[i] = integrate(s_front[i], s_back[i], length[i]);
        return;
    }
    // The thin pieces that lie in one interval of the transfer function, kThinLanes at a time: their A, B, depth and
    // end colours exactly as integrate_piece and integrate_linear_piece compute them, gathered by lane.
    constexpr std::size_t kLanes = kThinLanes;
    double A[kLanes], B[kLanes], depth[kLanes], c0[3 * kLanes], c1[3 * kLanes], lanes_out[4 * kLanes];
    std::size_t index[kLanes], m = 0;
    const auto run_lanes = [&] {
        for (std::size_t l = m; l < kLanes; ++l) A[l] = B[l] = depth[l] = 0.0;  // idle lanes compute zeros
        thin_pieces_avx2(A, B, depth, c0, c1, lanes_out);
        for (std::size_t l = 0; l < m; ++l)
            out[index[l]] = {lanes_out[l], lanes_out[kLanes + l], lanes_out[2 * kLanes + l], lanes_out[3 * kLanes + l]};
        m = 0;
    };
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double L = length[i];
        const Piece* p = L > 0.0 ? single_piece(s_front[i], s_back[i], k) : nullptr;
        if (!p) {
            out[i] = integrate(s_front[i], s_back[i], L);
            continue;
        }
        const double sa = s_front[i], sb = s_back[i];
        const glm::dvec3 ca = p->c + p->dc * (sa - p->lo), cb = p->c + p->dc * (sb - p->lo);
        const double tau0 = p->tau + p->dtau * (sa - p->lo), tau1 = p->tau + p->dtau * (sb - p->lo);
        const double a = tau0 * L, b = 0.5 * (tau1 - tau0) * L;
        if (!(a + std::fabs(b) < kThinDepth)) {
            out[i] = integrate_linear_piece(ca, cb, tau0, tau1, L);
            continue;
        }
        A[m] = a;
        B[m] = b;
        depth[m] = 0.5 * (tau0 + tau1) * L;
        for (int ch = 0; ch < 3; ++ch) {
            c0[std::size_t(ch) * kLanes + m] = ca[ch];
            c1[std::size_t(ch) * kLanes + m] = cb[ch];
        }
        index[m++] = i;
        if (m == kLanes) run_lanes();
    }
    if (m > 0) run_lanes();
}

}  // namespace uvr
