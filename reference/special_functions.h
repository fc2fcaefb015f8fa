// Special functions the closed-form segment integral needs, in double precision with no overflow anywhere.
#pragma once

namespace uvr {

// Scaled complementary error function erfcx(x) = exp(x^2) erfc(x), for x >= 0 (the only range the segment integral
// uses). Relative error a few ulps: exp(x^2) is evaluated as exp(hi) * exp(lo) with x^2 = hi + lo split exactly by
// fma, so the argument's rounding is not amplified; beyond x = 26, where erfc underflows, a continued fraction.
double erfcx(double x);

// Dawson's integral D(x) = exp(-x^2) * integral_0^x exp(t^2) dt, for x >= 0. Rybicki's exponentially convergent sum
// with step h = 0.2 (truncation error about exp(-(pi / 2h)^2) = 2e-27), a Taylor series near 0 and the asymptotic
// series beyond x = 50. Relative error about 1e-15.
double dawson(double x);

}  // namespace uvr
