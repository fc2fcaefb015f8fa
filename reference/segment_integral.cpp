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

// 1 - e^{-d} below d = 1/8 from its alternating series d - d^2/2 + ... (relative error ~1e-16, as expm1's, at a
// fraction of its cost): 8 terms below 1/32 (the first left out, d^9/9!, is below 1e-19 of d), 12 terms up to 1/8
// (d^13/13!: below 3e-21 of d). Estrin's scheme (pairs of terms, then the powers d^2, d^4, d^8) keeps the chain of
// dependent operations three or four multiplications deep. pieces_avx2 does the same arithmetic in lanes.
constexpr double kShortOpacityDepth = 1.0 / 32.0, kSeriesOpacityDepth = 1.0 / 8.0;
double opacity_of_depth(double d)
{
    if (!(d < kSeriesOpacityDepth)) return -std::expm1(-d);
    const double d2 = d * d, d4 = d2 * d2;
    const double p01 = 1.0 - d * 0.5, p23 = 1.0 / 6.0 - d * (1.0 / 24.0);
    const double p45 = 1.0 / 120.0 - d * (1.0 / 720.0), p67 = 1.0 / 5040.0 - d * (1.0 / 40320.0);
    const double low = (p01 + d2 * p23) + d4 * (p45 + d2 * p67);
    if (d < kShortOpacityDepth) return d * low;
    const double p89 = 1.0 / 362880.0 - d * (1.0 / 3628800.0), p1011 = 1.0 / 39916800.0 - d * (1.0 / 479001600.0);
    return d * (low + (d4 * d4) * (p89 + d2 * p1011));
}

// Below these optical sizes S = A + |B| of a piece, integrate_linear_piece takes 1 - J from its power series
// (one_minus_j_series) instead of subtracting J from 1, which keeps only the digits the difference from 1 holds: J's
// absolute error of ~1e-16 is 1e-7 of 1 - J at a depth of 1e-9. Above kMediumDepth, 1 - J >= S / 3 > 0.04, so the
// subtraction costs at most 3e-15 relative.
constexpr double kThinDepth = 1.0 / 64.0, kMediumDepth = 1.0 / 8.0;
constexpr int kThinTerms = 7, kMediumTerms = 11;  // the terms a piece below kThinDepth, kMediumDepth needs

// 1 - J = int_0^1 (1 - e^{-f(u)}) du with f(u) = A u + B u^2 (the optical depth to the fraction u of the piece)
//       = sum_{n>=1} (-1)^{n+1} / n! I_n,   I_n = int_0^1 f(u)^n du = sum_j C(n, j) A^{n-j} B^j / (n + j + 1).
// f >= 0 on [0, 1], so the terms alternate and shrink, and no two nearly equal values are subtracted (A >= 0; B < 0
// only with A + 2B >= 0, where the j terms alternate with a ratio below 1/2). The first term left out, n = Terms + 1,
// is at most S^{n} / n! against a sum of at least S / 3: below 1.7e-17 of it for 7 terms under kThinDepth, below
// 7.3e-19 for 11 terms under kMediumDepth. The terms are summed as sum_j B^j P_j(A) with
// P_j(A) = sum_n c_{n,j} A^{n-j} (Horner in A for each j, then in B): short chains a processor runs side by side.
// The coefficients c_{n,j} = (-1)^{n+1} C(n, j) / (n! (n + j + 1)) come from a table computed at compile time.
// Derivation: docs/reference.md, "Thin pieces". kSeriesCoef[j][m] = c_{j+m, j}: the coefficient of A^m in P_j (zero
// where j + m is 0 or above kMediumTerms).
constexpr auto kSeriesCoef = [] {
    std::array<std::array<double, kMediumTerms + 1>, kMediumTerms + 1> c{};
    double fact = 1.0;
    for (int n = 1; n <= kMediumTerms; ++n) {
        fact *= n;
        double binom = 1.0;
        for (int j = 0; j <= n; ++j) {
            c[std::size_t(j)][std::size_t(n - j)] = (n % 2 ? 1.0 : -1.0) * binom / (fact * double(n + j + 1));
            binom = binom * double(n - j) / double(j + 1);
        }
    }
    return c;
}();

template <int Terms>
double one_minus_j_series(double A, double B)
{
    double w = 0.0;
#pragma GCC unroll 12
    for (int j = Terms; j >= 0; --j) {
        const auto& c = kSeriesCoef[std::size_t(j)];
        double p = 0.0;
#pragma GCC unroll 12
        for (int m = Terms - j; m >= 0; --m) p = p * A + c[std::size_t(m)];
        w = w * B + p;
    }
    return w;
}

// Eight pieces at once in two sets of AVX2 lanes, every lane's S below kThinDepth (Terms = kThinTerms) or below
// kMediumDepth (kMediumTerms), the two sets' chains interleaved: the operations of opacity_of_depth,
// one_minus_j_series and integrate_linear_piece in the same order, one IEEE operation per lane for each scalar one (no
// fused multiply-add: the target is AVX2 alone), hence the same bits. Inputs and outputs are arrays of kPieceLanes; c0,
// c1 and out by channel.
constexpr std::size_t kPieceLanes = 8;
template <int Terms>
__attribute__((target("avx2"))) void pieces_avx2(const double* A, const double* B, const double* depth,
                                                 const double* c0, const double* c1, double* out)
{
    constexpr int kSets = int(kPieceLanes / 4);
    __m256d a[kSets], b[kSets], alpha[kSets], w0[kSets];
#pragma GCC unroll 2
    for (int h = 0; h < kSets; ++h) {
        a[h] = _mm256_loadu_pd(A + 4 * h);
        b[h] = _mm256_loadu_pd(B + 4 * h);
        const __m256d d = _mm256_loadu_pd(depth + 4 * h);
        const __m256d d2 = _mm256_mul_pd(d, d), d4 = _mm256_mul_pd(d2, d2);
        const __m256d p01 = _mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(d, _mm256_set1_pd(0.5)));
        const __m256d p23 = _mm256_sub_pd(_mm256_set1_pd(1.0 / 6.0), _mm256_mul_pd(d, _mm256_set1_pd(1.0 / 24.0)));
        const __m256d p45 = _mm256_sub_pd(_mm256_set1_pd(1.0 / 120.0), _mm256_mul_pd(d, _mm256_set1_pd(1.0 / 720.0)));
        const __m256d p67 =
            _mm256_sub_pd(_mm256_set1_pd(1.0 / 5040.0), _mm256_mul_pd(d, _mm256_set1_pd(1.0 / 40320.0)));
        const __m256d low = _mm256_add_pd(_mm256_add_pd(p01, _mm256_mul_pd(d2, p23)),
                                          _mm256_mul_pd(d4, _mm256_add_pd(p45, _mm256_mul_pd(d2, p67))));
        alpha[h] = _mm256_mul_pd(d, low);
        if constexpr (Terms > kThinTerms) {
            // Lanes at depth 1/32 and beyond take the 12-term series (opacity_of_depth).
            const __m256d p89 =
                _mm256_sub_pd(_mm256_set1_pd(1.0 / 362880.0), _mm256_mul_pd(d, _mm256_set1_pd(1.0 / 3628800.0)));
            const __m256d p1011 =
                _mm256_sub_pd(_mm256_set1_pd(1.0 / 39916800.0), _mm256_mul_pd(d, _mm256_set1_pd(1.0 / 479001600.0)));
            const __m256d high = _mm256_mul_pd(
                d,
                _mm256_add_pd(low, _mm256_mul_pd(_mm256_mul_pd(d4, d4), _mm256_add_pd(p89, _mm256_mul_pd(d2, p1011)))));
            const __m256d is_short = _mm256_cmp_pd(d, _mm256_set1_pd(kShortOpacityDepth), _CMP_LT_OQ);
            alpha[h] = _mm256_blendv_pd(high, alpha[h], is_short);
        }
        w0[h] = _mm256_setzero_pd();
    }
#pragma GCC unroll 12
    for (int j = Terms; j >= 0; --j) {
        const auto& c = kSeriesCoef[std::size_t(j)];
        __m256d p[kSets];
#pragma GCC unroll 2
        for (int h = 0; h < kSets; ++h) p[h] = _mm256_setzero_pd();
#pragma GCC unroll 12
        for (int m = Terms - j; m >= 0; --m)
#pragma GCC unroll 2
            for (int h = 0; h < kSets; ++h)
                p[h] = _mm256_add_pd(_mm256_mul_pd(p[h], a[h]), _mm256_set1_pd(c[std::size_t(m)]));
#pragma GCC unroll 2
        for (int h = 0; h < kSets; ++h) w0[h] = _mm256_add_pd(_mm256_mul_pd(w0[h], b[h]), p[h]);
    }
#pragma GCC unroll 2
    for (int h = 0; h < kSets; ++h) {
        const __m256d w1 = _mm256_sub_pd(alpha[h], w0[h]);
        for (int ch = 0; ch < 3; ++ch) {
            const std::size_t at = std::size_t(ch) * kPieceLanes + std::size_t(4 * h);
            const __m256d x = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(c0 + at), w0[h]),
                                            _mm256_mul_pd(_mm256_loadu_pd(c1 + at), w1));
            _mm256_storeu_pd(out + at, x);
        }
        _mm256_storeu_pd(out + 3 * kPieceLanes + std::size_t(4 * h), alpha[h]);
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
    const double S = A + std::fabs(B);
    if (S < kMediumDepth) {
        // w0 + w1 = 1 - e^{-T} = alpha: w1 from the two accurate values loses at most a factor 3 (w1 >= alpha / 3).
        w0 = S < kThinDepth ? one_minus_j_series<kThinTerms>(A, B) : one_minus_j_series<kMediumTerms>(A, B);
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
    // No extinction over the interval: nothing is emitted or absorbed; integrate_linear_piece would give these zeros.
    if (p.tau == 0.0 && p.dtau == 0.0) return glm::dvec4(0.0);
    const glm::dvec3 ca = p.c + p.dc * (sa - p.lo), cb = p.c + p.dc * (sb - p.lo);
    return integrate_linear_piece(ca, cb, p.tau + p.dtau * (sa - p.lo), p.tau + p.dtau * (sb - p.lo), length);
}

glm::dvec4 SegmentIntegrator::integrate(double s_front, double s_back, double length) const
{
    if (!(length > 0.0)) return glm::dvec4(0.0);
    std::size_t k = 0;
    if (const Piece* p = single_piece(s_front, s_back, k)) return integrate_piece(*p, s_front, s_back, length);
    const double ds = s_back - s_front;
    if (s_back >= s_front) {
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
    // Descending: from s_front's interval down.
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
    // The interval of s_front: ascending, seen from above (upper_bound: a breakpoint exactly at s_front belongs to the
    // piece after it); descending, from below (lower_bound: to the piece before it). `k` (integrate_many: the previous
    // segment's) is tried first, as consecutive segments of a ray mostly lie in one interval.
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
    // The thin and medium pieces that lie in one interval of the transfer function, kPieceLanes of a kind at a time:
    // their A, B, depth and end colours exactly as integrate_piece and integrate_linear_piece compute them, by lane.
    struct Lanes {
        double A[kPieceLanes], B[kPieceLanes], depth[kPieceLanes], c0[3 * kPieceLanes], c1[3 * kPieceLanes];
        double result[4 * kPieceLanes];
        std::size_t index[kPieceLanes], m = 0;
        // Adds one piece; true when the lanes are full.
        bool add(double a, double b, double dep, const glm::dvec3& ca, const glm::dvec3& cb, std::size_t i)
        {
            const std::size_t at = m;
            A[at] = a;
            B[at] = b;
            depth[at] = dep;
            for (int ch = 0; ch < 3; ++ch) {
                c0[std::size_t(ch) * kPieceLanes + at] = ca[ch];
                c1[std::size_t(ch) * kPieceLanes + at] = cb[ch];
            }
            index[at] = i;
            m = at + 1;
            return m == kPieceLanes;
        }
    };
    Lanes thin, medium;
    const auto run = [&](Lanes& l, auto kernel) {
        for (std::size_t i = l.m; i < kPieceLanes; ++i) l.A[i] = l.B[i] = l.depth[i] = 0.0;  // idle lanes: zeros
        kernel(l.A, l.B, l.depth, l.c0, l.c1, l.result);
        for (std::size_t i = 0; i < l.m; ++i)
            out[l.index[i]] = {l.result[i], l.result[kPieceLanes + i], l.result[2 * kPieceLanes + i],
                               l.result[3 * kPieceLanes + i]};
        l.m = 0;
    };
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double L = length[i];
        const Piece* p = L > 0.0 ? single_piece(s_front[i], s_back[i], k) : nullptr;
        if (!p) {
            out[i] = integrate(s_front[i], s_back[i], L);
            continue;
        }
        if (p->tau == 0.0 && p->dtau == 0.0) {  // clear: integrate_piece's zeros
            out[i] = glm::dvec4(0.0);
            continue;
        }
        // integrate_piece's and integrate_linear_piece's arithmetic, the same operations in the same order.
        const double sa = s_front[i], sb = s_back[i];
        const glm::dvec3 ca = p->c + p->dc * (sa - p->lo), cb = p->c + p->dc * (sb - p->lo);
        const double tau0 = p->tau + p->dtau * (sa - p->lo), tau1 = p->tau + p->dtau * (sb - p->lo);
        const double a = tau0 * L, b = 0.5 * (tau1 - tau0) * L, S = a + std::fabs(b);
        if (!(S < kMediumDepth)) {
            out[i] = integrate_linear_piece(ca, cb, tau0, tau1, L);
            continue;
        }
        const double dep = 0.5 * (tau0 + tau1) * L;
        if (S < kThinDepth) {
            if (thin.add(a, b, dep, ca, cb, i)) run(thin, pieces_avx2<kThinTerms>);
        } else if (medium.add(a, b, dep, ca, cb, i)) {
            run(medium, pieces_avx2<kMediumTerms>);
        }
    }
    if (thin.m > 0) run(thin, pieces_avx2<kThinTerms>);
    if (medium.m > 0) run(medium, pieces_avx2<kMediumTerms>);
}

}  // namespace uvr
