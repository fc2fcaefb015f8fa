// The independent check of the closed-form segment integral: adaptive Gauss-Legendre quadrature in long double of the
// defining integrals of docs/spec.md §1, used only by tests. It shares nothing with reference/segment_integral.cpp but
// the transfer function's own evaluation (color_at, tau_at).
#pragma once

#include <array>
#include <cmath>
#include <algorithm>
#include <functional>
#include <limits>
#include <vector>

#include <glm/vec4.hpp>

#include "reference/transfer_function.h"

namespace uvr::test {

using Real = long double;

// 20-point Gauss-Legendre nodes and weights on [-1, 1], computed once by Newton's method in long double.
inline const std::array<std::array<Real, 2>, 20>& gauss_legendre20()
{
    static const auto table = [] {
        std::array<std::array<Real, 2>, 20> t{};
        const int n = 20;
        for (int i = 0; i < n; ++i) {
            Real x = std::cos(3.14159265358979323846264338327950288L * (i + 0.75L) / (n + 0.5L));
            Real dp = 0;
            for (int it = 0; it < 100; ++it) {
                Real p0 = 1, p1 = x;
                for (int k = 2; k <= n; ++k) {
                    const Real p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (x * p1 - p0) / (x * x - 1);
                const Real dx = p1 / dp;
                x -= dx;
                if (std::fabs(dx) < 1e-30L) break;
            }
            t[std::size_t(i)] = {x, 2 / ((1 - x * x) * dp * dp)};
        }
        return t;
    }();
    return table;
}

using Vec3R = std::array<Real, 3>;

// Adaptive integration of a smooth (vector-valued) function on [a, b]: a 20-point rule on the interval against the
// sum over its halves, bisecting until they agree to `tol` in every component.
inline Vec3R integrate_adaptive3(const std::function<Vec3R(Real)>& f, Real a, Real b, Real tol, int depth = 0)
{
    auto gl = [&](Real lo, Real hi) {
        const Real c = (lo + hi) / 2, h = (hi - lo) / 2;
        Vec3R s{0, 0, 0};
        for (const auto& nw : gauss_legendre20()) {
            const Vec3R v = f(c + h * nw[0]);
            for (int k = 0; k < 3; ++k) s[k] += nw[1] * v[k];
        }
        for (auto& x : s) x *= h;
        return s;
    };
    const Real m = (a + b) / 2;
    const Vec3R whole = gl(a, b), left = gl(a, m), right = gl(m, b);
    Vec3R halves;
    Real diff = 0, size = 0;
    for (int k = 0; k < 3; ++k) {
        halves[k] = left[k] + right[k];
        diff = std::max(diff, std::fabs(whole[k] - halves[k]));
        size = std::max(size, std::fabs(halves[k]));
    }
    // Stop at the absolute tolerance, or where the two estimates agree to 64 ulps of long double (about 7e-18
    // relative): no tighter agreement is reachable, and insisting would bisect to the depth limit everywhere.
    if (diff <= tol || diff <= 64 * std::numeric_limits<Real>::epsilon() * size || depth > 40) return halves;
    const Vec3R l = integrate_adaptive3(f, a, m, tol / 2, depth + 1), r = integrate_adaptive3(f, m, b, tol / 2, depth + 1);
    return {l[0] + r[0], l[1] + r[1], l[2] + r[2]};
}

// Every integrand here decays like exp(-depth), fastest at the start of its interval, where a boundary layer as thin
// as 1e-5 of the interval can hide between the quadrature nodes of the first estimate (both estimates then agree on
// ~0). Pre-splitting [a, b] at a + (b - a) 2^-i, i = 1..levels, puts nodes into any layer down to 2^-levels of the
// interval; `rate` bounds the decay rate (the largest extinction), so levels = log2(rate (b - a)) + 4 reaches a
// sixteenth of the thinnest layer.
inline Vec3R integrate_layered3(const std::function<Vec3R(Real)>& f, Real a, Real b, Real tol, Real rate)
{
    const int levels = std::clamp(int(std::ceil(std::log2(1 + rate * (b - a)))) + 4, 1, 80);
    Vec3R sum{0, 0, 0};
    Real hi = b;
    for (int i = 1; i <= levels; ++i) {
        const Real lo = a + (b - a) * std::ldexp(Real(1), -i);
        const Vec3R part = integrate_adaptive3(f, lo, hi, tol / (levels + 1));
        for (int k = 0; k < 3; ++k) sum[k] += part[k];
        hi = lo;
    }
    const Vec3R last = integrate_adaptive3(f, a, hi, tol / (levels + 1));
    for (int k = 0; k < 3; ++k) sum[k] += last[k];
    return sum;
}

inline Real integrate_adaptive(const std::function<Real(Real)>& f, Real a, Real b, Real tol, Real rate)
{
    return integrate_layered3([&](Real t) { return Vec3R{f(t), 0, 0}; }, a, b, tol, rate)[0];
}

// C and alpha of a segment by the definitions: C = int_0^D c(s(t)) tau(s(t)) exp(-T(t)) dt, alpha = 1 - exp(-T(D)),
// with T(t) accumulated exactly over the pieces where tau is linear in t (trapezoids are exact for linear tau), and
// the outer integral by quadrature over the whole segment at once (no compositing of pieces).
inline glm::dvec4 oracle_segment(const TransferFunction& tf, double sf, double sb, double D, Real tol = 1e-14L)
{
    if (!(D > 0)) return glm::dvec4(0.0);
    auto s_at = [&](Real t) { return Real(sf) + (Real(sb) - Real(sf)) * t / Real(D); };
    // Kinks of the integrand: where s crosses a node.
    std::vector<Real> ts{0};
    for (double b : tf.breakpoints()) {
        if (sf == sb) break;
        const Real t = (Real(b) - sf) / (Real(sb) - sf) * D;
        if (t > 0 && t < D) ts.push_back(t);
    }
    ts.push_back(D);
    std::sort(ts.begin(), ts.end());
    // On each piece colour and extinction are linear in t. Their end values are extrapolated from evaluations at the
    // piece's 1/3 and 2/3 points (exact for linear functions), so no evaluation lands on a node, where a jump would
    // be taken from the wrong side.
    struct Piece {
        Real a, b, ta, tb;
        Vec3R ca, cb;
    };
    std::vector<Piece> pieces;
    for (std::size_t k = 1; k < ts.size(); ++k) {
        const Real a = ts[k - 1], b = ts[k];
        const double s1 = double(s_at(a + (b - a) / 3)), s2 = double(s_at(a + 2 * (b - a) / 3));
        const Real t1 = tf.tau_at(s1), t2 = tf.tau_at(s2);
        const glm::dvec3 c1 = tf.color_at(s1), c2 = tf.color_at(s2);
        Piece p{a, b, 2 * t1 - t2, 2 * t2 - t1, {}, {}};
        for (int ch = 0; ch < 3; ++ch) {
            p.ca[ch] = 2 * Real(c1[ch]) - Real(c2[ch]);
            p.cb[ch] = 2 * Real(c2[ch]) - Real(c1[ch]);
        }
        pieces.push_back(p);
    }
    // Optical depth at each kink: trapezoids are exact for linear extinction.
    std::vector<Real> depth_at{0};
    for (const Piece& p : pieces) depth_at.push_back(depth_at.back() + (p.ta + p.tb) / 2 * (p.b - p.a));
    Real C[3] = {0, 0, 0};
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        const Piece& p = pieces[k];
        auto f = [&](Real t) {
            const Real w = (t - p.a) / (p.b - p.a);
            const Real tau = p.ta + (p.tb - p.ta) * w;
            const Real depth = depth_at[k] + (p.ta + tau) / 2 * (t - p.a);
            const Real e = tau * std::exp(-depth);
            return Vec3R{(p.ca[0] + (p.cb[0] - p.ca[0]) * w) * e, (p.ca[1] + (p.cb[1] - p.ca[1]) * w) * e,
                         (p.ca[2] + (p.cb[2] - p.ca[2]) * w) * e};
        };
        const Vec3R piece = integrate_layered3(f, p.a, p.b, tol, std::max(p.ta, p.tb));
        for (int ch = 0; ch < 3; ++ch) C[ch] += piece[ch];
    }
    return {double(C[0]), double(C[1]), double(C[2]), double(-std::expm1(-depth_at.back()))};
}

}  // namespace uvr::test
