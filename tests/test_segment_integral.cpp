// The closed-form segment integral against analytic cases and against the long-double quadrature oracle.
#include <cmath>
#include <cstring>
#include <random>

#include "quadrature_oracle.h"
#include "reference/segment_integral.h"
#include "reference/special_functions.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::oracle_segment;
using uvr::test::Real;

namespace {

// The bar: the closed form and the oracle agree to 1e-10 absolute on every channel.
constexpr double kOracleTolerance = 1e-10;
// erfcx and Dawson against long-double references: a few ulps of the evaluation plus the rounding of the argument
// handling; 1e-14 relative is ~50 ulps.
constexpr double kSpecialRelTolerance = 1e-14;
// Analytic cases evaluated by the same few double operations as the closed form: a few ulps of values <= 1.
constexpr double kAnalyticTolerance = 1e-14;
// A piece's C and alpha relative to their own size, at any optical depth: the thin series and the closed form lose at
// most two digits (segment_integral.cpp, kThinDepth): measured 1.5e-14 at worst over the cases below (it prints it).
constexpr double kThinRelTolerance = 1e-13;

TransferFunction constant_tf(glm::dvec3 c, double tau)
{
    TransferFunction tf;
    tf.color = {{0.0, c}};
    tf.extinction = {{0.0, tau}};
    return tf;
}

}  // namespace

TEST_CASE("erfcx matches exp(x^2) erfc(x) computed in long double")
{
    for (double x = 0.0; x < 100.0; x += 0.01 + x * 0.01) {
        const Real ref = std::exp(Real(x) * Real(x)) * std::erfc(Real(x));
        INFO("x = " << x);
        CHECK(std::fabs(erfcx(x) - double(ref)) <= kSpecialRelTolerance * double(ref));
    }
}

TEST_CASE("Dawson's integral matches its defining integral computed in long double")
{
    for (double x = 0.0; x < 80.0; x += 0.013 + x * 0.02) {
        const Real ref = uvr::test::integrate_adaptive(
            [x](Real s) { return std::exp(-s * (2 * Real(x) - s)); }, 0, Real(x), 1e-22L, 2 * Real(x));
        INFO("x = " << x);
        CHECK(std::fabs(dawson(x) - double(ref)) <= kSpecialRelTolerance * double(ref) + 1e-300);
    }
}

TEST_CASE("the mean transmittance J is right in every regime of A and B")
{
    // A >= 0 and A + 2B >= 0; includes B near zero on both sides of the series threshold, and huge depths.
    const double As[] = {0.0, 1e-12, 1e-6, 0.3, 1.0, 4.0, 4.0001, 17.0, 300.0, 1e5};
    const double Bs[] = {-1e4, -50.0, -2.0, -0.4, -1.1e-3, -0.9e-3, -1e-9, 0.0, 1e-9, 0.9e-3, 1.1e-3, 0.5, 3.0, 80.0,
                         1e6};
    for (double A : As)
        for (double B : Bs) {
            if (A + 2.0 * B < 0.0) continue;
            const Real ref = uvr::test::integrate_adaptive(
                [&](Real u) { return std::exp(-(Real(A) * u + Real(B) * u * u)); }, 0, 1, 1e-20L,
                Real(A) + 2 * std::fabs(Real(B)));
            INFO("A = " << A << ", B = " << B);
            CHECK(std::fabs(depth_average_transmittance(A, B) - double(ref)) <= 1e-14);
        }
}

TEST_CASE("homogeneous segments follow Beer-Lambert exactly")
{
    const glm::dvec3 c(0.2, 0.5, 0.9);
    for (double tau : {0.0, 1e-9, 0.5, 3.0, 1e4})
        for (double D : {0.0, 1e-7, 0.25, 2.0}) {
            const SegmentIntegrator seg(constant_tf(c, tau));
            const glm::dvec4 r = seg.integrate(0.3, 0.7, D);
            const double alpha = 1.0 - std::exp(-tau * D);
            INFO("tau = " << tau << ", D = " << D);
            CHECK(std::fabs(r.a - alpha) <= kAnalyticTolerance);
            for (int k = 0; k < 3; ++k) CHECK(std::fabs(r[k] - c[k] * alpha) <= kAnalyticTolerance);
        }
}

TEST_CASE("a zero-length segment contributes nothing, whatever the transfer function")
{
    const SegmentIntegrator seg(constant_tf({1, 1, 1}, 1e9));
    CHECK(seg.integrate(0.0, 1.0, 0.0) == glm::dvec4(0.0));
}

TEST_CASE("splitting a segment in two and compositing the halves gives the whole")
{
    TransferFunction tf;
    tf.color = {{0.0, {1, 0, 0}}, {0.5, {0, 1, 0}}, {1.0, {0, 0, 1}}};
    tf.extinction = {{0.0, 0.5}, {0.3, 4.0}, {0.3, 1.0}, {1.0, 2.0}};  // a jump at 0.3
    const SegmentIntegrator seg(tf);
    const glm::dvec4 whole = seg.integrate(-0.1, 1.2, 1.7);
    const double t = 0.37;  // split point as a fraction of the length
    const double sm = -0.1 + 1.3 * t;
    const glm::dvec4 two = composite_over(seg.integrate(-0.1, sm, 1.7 * t), seg.integrate(sm, 1.2, 1.7 * (1 - t)));
    for (int k = 0; k < 4; ++k) CHECK(std::fabs(whole[k] - two[k]) <= kAnalyticTolerance);
}

TEST_CASE("the closed form agrees with the quadrature oracle on 200,000 random segments across every regime")
{
    std::mt19937_64 rng(20261121);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto pick = [&](std::initializer_list<double> v) { return *(v.begin() + std::size_t(U(rng) * v.size())); };
    // The regimes are 6 extinction scales x 7 segment lengths x 3 kinds of scalar pair (equal, nearly equal, any):
    // 126, each drawn about 1,600 times here across 800 random transfer functions (jumps, zero and constant
    // extinction among them). The largest difference is 5.1e-15 here and 2.3e-14 on a million segments (the size
    // this test had): both four orders below kOracleTolerance, so the million found nothing the bar can see, at five
    // times the cost (150-190 s, the heaviest test of the suite).
    const int kTransferFunctions = 800, kSegmentsEach = int(test::random_cases(250));  // 200,000 segments
    double worst = 0.0;
    for (int f = 0; f < kTransferFunctions; ++f) {
        TransferFunction tf;
        const int nc = 1 + int(U(rng) * 5), ne = 1 + int(U(rng) * 5);
        double s = U(rng) * 0.2;
        for (int i = 0; i < nc; ++i, s += U(rng) < 0.1 ? 0.0 : U(rng) * 0.3)  // 10 %: a jump
            tf.color.push_back({s, {U(rng), U(rng), U(rng)}});
        // Extinction scale per function: vanishing, ordinary, or huge; some functions constant in tau.
        const double scale = pick({1e-12, 1e-3, 1.0, 10.0, 1e3, 1e5});
        s = U(rng) * 0.2;
        const double tau_const = U(rng) * scale;
        const bool constant_tau = U(rng) < 0.1;
        for (int i = 0; i < ne; ++i, s += U(rng) < 0.1 ? 0.0 : U(rng) * 0.3)
            tf.extinction.push_back({s, constant_tau ? tau_const : (U(rng) < 0.15 ? 0.0 : U(rng) * scale)});
        const SegmentIntegrator seg(tf);
        for (int k = 0; k < kSegmentsEach; ++k) {
            const double sf = -0.2 + 1.6 * U(rng);
            const double kind = U(rng);
            // Equal scalars, nearly equal ones (tau_front ~ tau_back), and arbitrary ones.
            const double sb = kind < 0.1 ? sf : kind < 0.2 ? sf + 1e-9 * (U(rng) - 0.5) : -0.2 + 1.6 * U(rng);
            const double D = pick({0.0, 1e-9, 1e-4, 0.01, 0.3, 1.0, 5.0}) * U(rng);
            const glm::dvec4 got = seg.integrate(sf, sb, D);
            const glm::dvec4 ref = oracle_segment(tf, sf, sb, D);
            double err = 0.0;
            for (int c = 0; c < 4; ++c) err = std::max(err, std::fabs(got[c] - ref[c]));
            worst = std::max(worst, err);
            if (err > kOracleTolerance) {
                INFO("tf " << f << " segment " << k << ": s " << sf << " -> " << sb << ", D " << D << ", scale "
                           << scale << "\n tf " << transfer_function_json(tf) << "\n got " << got.r << " " << got.g << " " << got.b << " " << got.a
                           << "\n ref " << ref.r << " " << ref.g << " " << ref.b << " " << ref.a);
                REQUIRE(err <= kOracleTolerance);
            }
        }
    }
    INFO("largest difference " << worst);
    CHECK(worst <= kOracleTolerance);
}

TEST_CASE("optically thin and thick pieces keep their relative accuracy, from a depth of 1e-14 to 1e3")
{
    // One linear piece (colour c0 -> c1, extinction tau0 -> tau1 over scalars 0 -> 1) of optical depth `depth`, against
    // the long-double quadrature of its defining integrals, channel by channel relative to the channel's value: an
    // absolute bar would pass a result of 0 for a thin piece. Kinds: homogeneous, the extinction falling to 0 (B = -A/2,
    // the alternating extreme), rising from 0 (A = 0), and a general one with a colour ramp.
    struct Kind {
        const char* name;
        glm::dvec3 c0, c1;
        double tau0, tau1;
    };
    const Kind kinds[] = {{"homogeneous", {0.2, 0.5, 0.9}, {0.2, 0.5, 0.9}, 1.0, 1.0},
                          {"extinction falling to 0", {1.0, 0.0, 0.3}, {0.0, 1.0, 0.3}, 2.0, 0.0},
                          {"extinction rising from 0", {1.0, 0.0, 0.3}, {0.0, 1.0, 0.3}, 0.0, 2.0},
                          {"general", {0.9, 0.1, 0.4}, {0.2, 0.8, 0.5}, 0.3, 1.7}};
    const double depths[] = {1e-14, 1e-12, 1e-9, 1e-6, 1e-3, 0.05, 0.1249, 0.1251, 0.5, 1.0, 3.0, 10.0, 100.0, 1e3};
    double worst_rel = 0.0;
    for (const Kind& kind : kinds)
        for (double depth : depths) {
            // Scale the extinction so that 0.5 (tau0 + tau1) D = depth with D = 0.7.
            const double D = 0.7, scale = depth / (0.5 * (kind.tau0 + kind.tau1) * D);
            TransferFunction tf;
            tf.color = {{0.0, kind.c0}, {1.0, kind.c1}};
            tf.extinction = {{0.0, kind.tau0 * scale}, {1.0, kind.tau1 * scale}};
            const glm::dvec4 got = SegmentIntegrator(tf).integrate(0.0, 1.0, D);
            const glm::dvec4 ref = oracle_segment(tf, 0.0, 1.0, D, 1e-22L * Real(std::min(depth, 1.0)));
            for (int c = 0; c < 4; ++c) {
                INFO(kind.name << ", depth " << depth << ", channel " << c << ": " << got[c] << " against " << ref[c]
                               << ", relative " << std::fabs(got[c] - ref[c]) / std::fabs(ref[c]));
                REQUIRE(ref[c] != 0.0);  // every channel carries colour here: the relative bar means something
                CHECK(std::fabs(got[c] - ref[c]) <= kThinRelTolerance * std::fabs(ref[c]));
                worst_rel = std::max(worst_rel, std::fabs(got[c] - ref[c]) / std::fabs(ref[c]));
            }
        }
    WARN("largest relative error " << worst_rel);
}

TEST_CASE("segments integrated many at once give each segment's own bits")
{
    // integrate_many takes thin pieces eight at a time in AVX2 lanes (where the processor has them) and the rest one by
    // one: every result must be integrate()'s, bit for bit, whatever mix a batch holds. Thin pieces dominate (depths
    // 1e-9 to 1e-2, as on a fine mesh), with thick ones, zero lengths, descending scalars and breakpoint crossings.
    std::mt19937_64 rng(20261128);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::size_t compared = 0, differing = 0;
    for (int f = 0; f < 200; ++f) {
        TransferFunction tf;
        double s = 0.0;
        for (int i = 0; i < 4; ++i, s += U(rng) * 0.4) tf.color.push_back({s, {U(rng), U(rng), U(rng)}});
        s = 0.0;
        const double scale = std::pow(10.0, -2.0 + 4.0 * U(rng));
        for (int i = 0; i < 3; ++i, s += U(rng) * 0.5) tf.extinction.push_back({s, U(rng) * scale});
        const SegmentIntegrator seg(tf);
        for (int batch = 0; batch < 50; ++batch) {
            const std::size_t n = 1 + std::size_t(U(rng) * 20.0);
            std::vector<double> sf(n), sb(n), len(n);
            for (std::size_t i = 0; i < n; ++i) {
                sf[i] = -0.1 + 1.2 * U(rng);
                const double kind = U(rng);
                sb[i] = kind < 0.7 ? sf[i] + 0.02 * (U(rng) - 0.5) : -0.1 + 1.2 * U(rng);
                len[i] = U(rng) < 0.05 ? 0.0 : std::pow(10.0, -9.0 + 9.0 * U(rng)) / scale;
            }
            std::vector<glm::dvec4> many(n);
            seg.integrate_many(n, sf.data(), sb.data(), len.data(), many.data());
            for (std::size_t i = 0; i < n; ++i) {
                const glm::dvec4 one = seg.integrate(sf[i], sb[i], len[i]);
                ++compared;
                if (std::memcmp(&one, &many[i], sizeof one) != 0) ++differing;
            }
        }
    }
    INFO(differing << " of " << compared << " segments differ");
    CHECK(differing == 0);
}
