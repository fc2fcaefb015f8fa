#include "reference/special_functions.h"

#include <array>
#include <cmath>

namespace uvr {

namespace {
constexpr double kInvSqrtPi = 0.56418958354775628695;

// exp(x * x) without amplifying the rounding of x * x: hi + lo == x * x exactly.
double exp_square(double x)
{
    const double hi = x * x;
    const double lo = std::fma(x, x, -hi);
    return std::exp(hi) * std::exp(lo);
}
}  // namespace

double erfcx(double x)
{
    if (x < 26.0) return exp_square(x) * std::erfc(x);
    // Continued fraction erfcx(x) = (1/sqrt(pi)) / (x + (1/2)/(x + 1/(x + (3/2)/(x + 2/(x + ...))))), evaluated
    // bottom-up; at x >= 26 forty levels are far more than double precision needs.
    double f = x;
    for (int k = 40; k >= 1; --k) f = x + (0.5 * k) / f;
    return kInvSqrtPi / f;
}

double dawson(double x)
{
    if (x < 0.2) {
        // D(x) = sum_n (-1)^n 2^n x^(2n+1) / (1 * 3 * ... * (2n+1)); at x < 0.2 twelve terms reach 1e-20 relative.
        const double x2 = x * x;
        double term = x, sum = x;
        for (int n = 1; n < 12; ++n) {
            term *= -2.0 * x2 / (2 * n + 1);
            sum += term;
        }
        return sum;
    }
    if (x > 50.0) {
        // D(x) ~ 1/(2x) * sum_n (2n-1)!! / (2x^2)^n; at x > 50 six terms leave 1e-20.
        const double y = 1.0 / (2.0 * x * x);
        double term = 1.0, sum = 1.0;
        for (int n = 1; n < 6; ++n) {
            term *= (2 * n - 1) * y;
            sum += term;
        }
        return sum / (2.0 * x);
    }
    // Rybicki: D(x) = (1/sqrt(pi)) * sum over odd n of exp(-(x - n h)^2) / n, as h -> 0. With x0 = 2 n0 h the even
    // multiple of h nearest x and xp = x - x0, the terms are exp(-(xp - m h)^2) / (m + 2 n0) over odd m, which is
    // exp(-xp^2) * exp(2 xp h m) * exp(-(m h)^2): two geometric factors, so only three exponentials are needed.
    constexpr double h = 0.2;
    constexpr int kTerms = 18;  // m h up to 7: exp(-(7 - 0.2)^2) is below 1e-20
    const int n0 = 2 * static_cast<int>(std::lround(0.5 * x / h));
    const double xp = x - n0 * h;
    const double e1 = std::exp(2.0 * xp * h);
    const double e2 = e1 * e1;
    double d1 = n0 + 1, d2 = d1 - 2.0;
    double up = e1, down = 1.0 / e1;  // exp(2 xp h m) for m = +1, and exp(-2 xp h m) for m = +1
    static const auto c = [] {
        std::array<double, kTerms> t{};
        for (int i = 0; i < kTerms; ++i) t[std::size_t(i)] = std::exp(-((2 * i + 1) * h) * ((2 * i + 1) * h));
        return t;
    }();
    double sum = 0.0;
    for (int i = 0; i < kTerms; ++i) {
        sum += c[std::size_t(i)] * (up / d1 + down / d2);
        d1 += 2.0;
        d2 -= 2.0;
        up *= e2;
        down /= e2;
    }
    return kInvSqrtPi * std::exp(-xp * xp) * sum;
}

}  // namespace uvr
