// Pre-integration tables (gpu/pipeline/preintegration_table.h): the 3D table's texels against the exact segment
// integral, its coordinate conventions, its error in table mode as the resolution grows, and Moreland's Ψ table.
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "gpu/pipeline/preintegration_table.h"
#include "gpu/pipeline/segment.h"
#include "quadrature_oracle.h"
#include "reference/transfer_function.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

const LlvmpipeCpu kCpu{true, true};  // x86-64 with FMA3, as the OSMesa recordings (the table tests need no host)

// The default transfer function over [0, 1] for a unit diagonal: a ray of length 1 at the largest extinction has
// optical depth 4, so segments up to max_length = 1 range from transparent to nearly opaque.
TransferFunction test_tf() { return default_transfer_function({0.0, 1.0}, 1.0); }

PreintegrationConfig small_config(TexelFormat f)
{
    PreintegrationConfig c;
    c.scalar_resolution = 8;
    c.length_resolution = 5;
    c.max_length = 1.0;
    c.format = f;
    return c;
}

// Half a quantum of an n-bit unorm, plus the rounding of the value to float before the conversion (2^-24 relative)
// and of the float product x * (2^n - 1) (2^-24 relative): 1e-6 of a quantum covers both.
double half_quantum(TexelFormat f)
{
    const double q = f == TexelFormat::u8 ? 1.0 / 255.0 : 1.0 / 65535.0;
    return 0.5 * q * (1.0 + 1e-6);
}

// A float32 texel is the double integral rounded once: half an ulp, 2^-24 of its value.
constexpr double kHalfFloatUlp = 0x1p-24;
// The closed-form integral that the texels round against the quadrature: the bar (kOracleTolerance of
// tests/test_segment_integral.cpp, 1e-10 absolute).
constexpr double kClosedFormTolerance = 1e-10;

struct ErrorStats {
    double max = 0.0, sum_sq = 0.0;
    long n = 0;
    void add(double e)
    {
        max = std::max(max, std::fabs(e));
        sum_sq += e * e;
        ++n;
    }
    double rms() const { return std::sqrt(sum_sq / double(n)); }
};

}  // namespace

TEST_CASE("table texels hold the segment integral at their centres, by an independent quadrature")
{
    // The texels against the long-double quadrature of docs/spec.md §1's integrals (tests/quadrature_oracle.h), which
    // shares nothing with the segment integrator that builds the table: a wrong integrator makes a wrong table, and
    // this test sees it.
    const TransferFunction tf = test_tf();
    const SegmentIntegrator seg(tf);
    for (TexelFormat f : {TexelFormat::f32, TexelFormat::u16, TexelFormat::u8}) {
        SECTION(texel_format_name(f))
        {
            const PreintegrationTable table(seg, {0.0, 1.0}, small_config(f));
            REQUIRE(table.size_bytes() == 8u * 8u * 5u * 4u * std::size_t(texel_channel_bytes(f)));
            for (int l = 0; l < 5; ++l)
                for (int j = 0; j < 8; ++j)
                    for (int i = 0; i < 8; ++i) {
                        const glm::dvec4 ref = test::oracle_segment(tf, table.texel_scalar(i), table.texel_scalar(j),
                                                                    table.texel_length(l));
                        const glm::vec4 got = table.texel(i, j, l);
                        for (int c = 0; c < 4; ++c) {
                            INFO("texel (" << i << ", " << j << ", " << l << ") channel " << c << ": " << got[c]
                                           << " vs the quadrature's " << ref[c]);
                            const double bar = f == TexelFormat::f32 ? kHalfFloatUlp * std::fabs(ref[c]) : half_quantum(f);
                            REQUIRE(std::fabs(double(got[c]) - ref[c]) <= bar + kClosedFormTolerance);
                        }
                    }
        }
    }
}

TEST_CASE("zero-length segments give zero")
{
    const SegmentIntegrator seg(test_tf());
    for (TexelFormat f : {TexelFormat::f32, TexelFormat::u16, TexelFormat::u8}) {
        SECTION(texel_format_name(f))
        {
            PreintegrationConfig c = small_config(f);
            c.length_resolution = 8;  // a power of two: the coordinate of d = 0 is exactly texel 0's centre
            const PreintegrationTable table(seg, {0.0, 1.0}, c);
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) REQUIRE(table.texel(i, j, 0) == glm::vec4(0.0f));
            std::mt19937 rng(1);
            std::uniform_real_distribution<double> u(-0.2, 1.2);
            for (int k = 0; k < 1000; ++k) {
                const double sf = u(rng), sb = u(rng);
                INFO("s_front = " << sf << ", s_back = " << sb);
                REQUIRE(table.lookup(sf, sb, 0.0, kCpu) == glm::vec4(0.0f));
            }
        }
    }
}

TEST_CASE("the length coordinate puts texel l's length on texel l's centre")
{
    // d * sz.z + sz.w = (l + 0.5) / L for d = l * max_len / (L - 1): checked in float for awkward sizes.
    const SegmentIntegrator seg(test_tf());
    for (int nl : {2, 5, 37, 128}) {
        PreintegrationConfig c = small_config(TexelFormat::f32);
        c.length_resolution = nl;
        c.max_length = 2.7;
        const PreintegrationTable table(seg, {0.0, 1.0}, c);
        CHECK(table.length_coordinate(0.0f) == table.length_bias());
        for (int l = 0; l < nl; ++l) {
            const float tz = table.length_coordinate(static_cast<float>(table.texel_length(l)));
            INFO("L = " << nl << ", l = " << l << ", t.z = " << tz);
            // Three float roundings (sz.z, the product, the sum) of values below 1: a few 1e-7 in texel units.
            CHECK(std::fabs(double(tz) * nl - (l + 0.5)) < 1e-5);
            CHECK(wrap_nearest_soa(tz, nl) == l);
        }
    }
}

TEST_CASE("nearest lookups at texel scalars and lengths return those texels")
{
    const SegmentIntegrator seg(test_tf());
    PreintegrationConfig c = small_config(TexelFormat::u16);
    c.scalar_resolution = 13;
    c.length_resolution = 6;
    const PreintegrationTable table(seg, {-3.0, 5.0}, c);
    for (int l = 0; l < 6; ++l)
        for (int j = 0; j < 13; ++j)
            for (int i = 0; i < 13; ++i) {
                INFO("texel (" << i << ", " << j << ", " << l << ")");
                REQUIRE(table.lookup(table.texel_scalar(i), table.texel_scalar(j), table.texel_length(l), kCpu,
                                     TextureFilter::nearest) == table.texel(i, j, l));
            }
}

TEST_CASE("table mode error against exact integration shrinks as the scalar resolution grows")
{
    // Random segments with the lengths of the length texels (L = 16), so only the two scalar axes interpolate;
    // same segments for every N. Measured (200,000 segments, default transfer function, max_length 1): RMS 4.8e-4,
    // 1.6e-4, 5.6e-5 and max 0.071, 0.033, 0.013 for N = 64, 128, 256 (docs/tables.md).
    const SegmentIntegrator seg(test_tf());
    double previous_rms = 1.0, previous_max = 1.0;
    for (int n : {64, 128, 256}) {
        PreintegrationConfig c;
        c.scalar_resolution = n;
        c.length_resolution = 16;
        c.max_length = 1.0;
        const PreintegrationTable table(seg, {0.0, 1.0}, c);
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        ErrorStats err;
        for (int k = 0; k < 20000; ++k) {
            const double sf = u(rng), sb = u(rng), d = table.texel_length(int(rng() % 16));
            const glm::vec4 got = table.lookup(sf, sb, d, kCpu);
            const glm::dvec4 exact = seg.integrate(sf, sb, d);
            for (int ch = 0; ch < 4; ++ch) err.add(double(got[ch]) - exact[ch]);
        }
        INFO("N = " << n << ": max " << err.max << ", RMS " << err.rms());
        // Piecewise-linear transfer functions put kinks in the integral, so the order is between 1 and 2: require at
        // least a factor 1.5 per doubling (measured 2.9 and 2.9 on the RMS, 2.1 and 2.5 on the maximum).
        CHECK(err.rms() < previous_rms / 1.5);
        CHECK(err.max < previous_max / 1.5);
        previous_rms = err.rms();
        previous_max = err.max;
    }
}

TEST_CASE("the table is built deterministically and rejects bad configurations")
{
    const SegmentIntegrator seg(test_tf());
    SECTION("two builds give the same bits")
    {
        PreintegrationConfig c = small_config(TexelFormat::f32);
        c.scalar_resolution = 32;
        c.length_resolution = 32;
        const PreintegrationTable a(seg, {0.0, 1.0}, c), b(seg, {0.0, 1.0}, c);
        REQUIRE(a.size_bytes() == b.size_bytes());
        CHECK(std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
    }
    SECTION("texel layout: x is the front scalar, then the back scalar, then the length")
    {
        const PreintegrationTable t(seg, {0.0, 1.0}, small_config(TexelFormat::f32));
        const float* data = static_cast<const float*>(t.data());
        const std::size_t at = ((std::size_t(3) * 8 + 2) * 8 + 5) * 4;  // l = 3, j = 2, i = 5
        CHECK(data[at + 3] == t.texel(5, 2, 3).a);
        const glm::dvec4 exact = seg.integrate(t.texel_scalar(5), t.texel_scalar(2), t.texel_length(3));
        CHECK(data[at + 3] == static_cast<float>(exact.a));
    }
    SECTION("bad resolutions and lengths throw")
    {
        PreintegrationConfig c = small_config(TexelFormat::f32);
        c.scalar_resolution = 1;
        CHECK_THROWS_AS(PreintegrationTable(seg, {0.0, 1.0}, c), std::invalid_argument);
        c = small_config(TexelFormat::f32);
        c.length_resolution = 1;
        CHECK_THROWS_AS(PreintegrationTable(seg, {0.0, 1.0}, c), std::invalid_argument);
        c = small_config(TexelFormat::f32);
        c.max_length = 0.0;
        CHECK_THROWS_AS(PreintegrationTable(seg, {0.0, 1.0}, c), std::invalid_argument);
        CHECK_THROWS_AS(PsiTable(1), std::invalid_argument);
    }
    SECTION("an empty scalar range is widened to one unit")
    {
        const PreintegrationTable t(seg, {2.0, 2.0}, small_config(TexelFormat::f32));
        CHECK(t.scalar_range().hi == 3.0);
        CHECK(t.texel_scalar(0) == 2.0 + 0.5 / 8);
    }
}

TEST_CASE("the Psi table holds the mean transmittance of the two optical depths")
{
    const PsiTable psi(64);
    CHECK(psi.texel(0, 0) == 1.0f);  // no extinction: fully transmitting
    for (int j = 0; j < 64; j += 7)
        for (int i = 0; i < 64; i += 5) {
            const double gf = i / 64.0, gb = j / 64.0;
            const double xf = gf / (1.0 - gf), xb = gb / (1.0 - gb);  // optical depths x = γ / (1 - γ)
            const double want = depth_average_transmittance(xf, 0.5 * (xb - xf));
            INFO("texel (" << i << ", " << j << ")");
            CHECK(psi.texel(i, j) == static_cast<float>(want));
            // Ψ lies between the transmittance of the whole piece and 1.
            CHECK(psi.texel(i, j) >= static_cast<float>(std::exp(-0.5 * (xf + xb))) * (1.0f - 1e-6f));
            CHECK(psi.texel(i, j) <= 1.0f);
        }
}

TEST_CASE("Moreland's Psi reconstruction matches the exact integral of linear pieces")
{
    // Random pieces: colours in [0, 1]^3 at both ends, extinctions in [0, 8], lengths in [0, 1] (optical depths up to
    // 8). Measured over 200,000 pieces: max 6.2e-5, 1.7e-5, 3.8e-6, 9.6e-7 and RMS 7.3e-6, 1.8e-6, 4.6e-7, 1.1e-7
    // for M = 128, 256, 512, 1024: second order, as bilinear interpolation of a smooth Ψ should be.
    double previous = 1.0;
    for (int m : {128, 256, 512}) {
        const PsiTable psi(m);
        std::mt19937_64 rng(17);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        ErrorStats err;
        for (int k = 0; k < 20000; ++k) {
            // Blue first: the statements fix the order of the draws, not the compiler.
            const double cf_b = u(rng), cf_g = u(rng), cf_r = u(rng), cb_b = u(rng), cb_g = u(rng), cb_r = u(rng);
            const glm::dvec3 cf(cf_r, cf_g, cf_b), cb(cb_r, cb_g, cb_b);
            const double tf = 8 * u(rng), tb = 8 * u(rng), d = u(rng);
            const glm::dvec4 got = psi_integrate_piece(psi, cf, cb, tf, tb, d);
            const glm::dvec4 exact = integrate_linear_piece(cf, cb, tf, tb, d);
            for (int ch = 0; ch < 4; ++ch) err.add(got[ch] - exact[ch]);
        }
        INFO("M = " << m << ": max " << err.max << ", RMS " << err.rms());
        // The bound per resolution: the measured maximum with a 50% margin (the sample here is ten times smaller).
        CHECK(err.max < 1.5 * 6.3e-5 * (128.0 / m) * (128.0 / m));
        CHECK(err.max < previous / 3.0);  // second order: about 4 per doubling
        previous = err.max;
        // Alpha needs no table: 1 - exp(-(τ_f + τ_b) D / 2) exactly.
        CHECK(psi_integrate_piece(psi, glm::dvec3(0.3), glm::dvec3(0.6), 2.0, 4.0, 0.5).a == -std::expm1(-1.5));
    }
    SECTION("the emulated GL_LINEAR lookup agrees with the double-precision one to float rounding")
    {
        // The float path's position error, in texels: γ + 0.5 / M rounded (3e-8) and times M rounded (M 2^-25),
        // about 2.3e-5 texel at M = 256, times Ψ's largest step between texels (0.0076), plus three float lerps
        // (3e-8 each): 2.6e-7. Measured 2.5e-7 over 2,000,000 uniform lookups.
        constexpr double kEmulatedLookupTolerance = 4e-7;
        const PsiTable psi(256);
        std::mt19937_64 rng(19);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int k = 0; k < 5000; ++k) {
            const double gf = u(rng), gb = u(rng);
            INFO("gamma = (" << gf << ", " << gb << ")");
            const double emulated = psi.lookup_emulated(float(gf), float(gb), kCpu);
            CHECK(std::fabs(emulated - psi.lookup(gf, gb)) < kEmulatedLookupTolerance);
        }
    }
}

TEST_CASE("partial pre-integration of whole segments matches the segment integrator")
{
    // Segments of the default transfer function split at its nodes: measured max 1.0e-6, RMS 1.0e-7 with M = 512
    // over 200,000 segments (docs/tables.md); the bound leaves a factor 3.
    const TransferFunction tf = test_tf();
    const SegmentIntegrator seg(tf);
    const PsiTable psi(512);
    const PsiSegmentIntegrator partial(tf, psi);
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(-0.1, 1.1);
    ErrorStats err;
    for (int k = 0; k < 20000; ++k) {
        const double sf = u(rng), sb = u(rng), d = std::fabs(u(rng));
        const glm::dvec4 got = partial.integrate(sf, sb, d), exact = seg.integrate(sf, sb, d);
        for (int ch = 0; ch < 4; ++ch) err.add(got[ch] - exact[ch]);
    }
    INFO("max " << err.max << ", RMS " << err.rms());
    CHECK(err.max < 3e-6);
    CHECK(partial.integrate(0.2, 0.7, 0.0) == glm::dvec4(0.0));
    CHECK(partial.integrate(0.4, 0.4, 0.3).a == Approx(seg.integrate(0.4, 0.4, 0.3).a).margin(1e-12));
}

TEST_CASE("a segment table is built once for the same inputs and again when any input differs")
{
    const TransferFunction tf = test_tf();
    const Range range{0.0, 1.0};
    double ms = 0.0;
    const auto first = build_segment_table(SegmentIntegrator(tf), range, 8, TexelFormat::f32, 1.0, ms);
    const std::size_t built = segment_tables_built();
    double again_ms = -1.0;
    const auto again = build_segment_table(SegmentIntegrator(tf), range, 8, TexelFormat::f32, 1.0, again_ms);
    CHECK(again == first);
    CHECK(again_ms == ms);
    CHECK(segment_tables_built() == built);

    // Each input alone changed by the least step it can take: a new table, and it holds what a table built from
    // those inputs holds.
    auto next_up = [](double x) { return std::nextafter(x, INFINITY); };
    struct Variant {
        const char* what;
        TransferFunction tf;
        Range range;
        int size;
        TexelFormat format;
        double max_length;
    };
    std::vector<Variant> variants;
    auto add = [&](const char* what) {
        return &variants.emplace_back(Variant{what, tf, range, 8, TexelFormat::f32, 1.0});
    };
    add("a colour node's scalar")->tf.color[1].s = next_up(tf.color[1].s);
    add("a colour node's green")->tf.color[2].rgb.g = next_up(tf.color[2].rgb.g);
    add("an extinction node's scalar")->tf.extinction[1].s = next_up(tf.extinction[1].s);
    add("an extinction node's value")->tf.extinction[1].tau = next_up(tf.extinction[1].tau);
    add("one more colour node")->tf.color.push_back({2.0, tf.color.back().rgb});
    add("the range's low end")->range.lo = -1e-300;
    add("the range's high end")->range.hi = next_up(1.0);
    add("the resolution")->size = 9;
    add("the texel format")->format = TexelFormat::u16;
    add("the longest length")->max_length = next_up(1.0);
    for (const Variant& v : variants) {
        INFO(v.what);
        const std::size_t before = segment_tables_built();
        const auto table = build_segment_table(SegmentIntegrator(v.tf), v.range, v.size, v.format, v.max_length, ms);
        CHECK(segment_tables_built() == before + 1);
        PreintegrationConfig c;
        c.scalar_resolution = c.length_resolution = v.size;
        c.format = v.format;
        c.max_length = v.max_length;
        const PreintegrationTable fresh(SegmentIntegrator(v.tf), v.range, c);
        REQUIRE(table->size_bytes() == fresh.size_bytes());
        CHECK(std::memcmp(table->data(), fresh.data(), fresh.size_bytes()) == 0);
        // Back to the first inputs: built again, as the process keeps only the most recent table.
        build_segment_table(SegmentIntegrator(tf), range, 8, TexelFormat::f32, 1.0, ms);
        CHECK(segment_tables_built() == before + 2);
    }
}
