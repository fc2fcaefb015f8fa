// The emulation of llvmpipe's texture sampling (gpu/pipeline/texture_sampling.h): its building blocks, what GL_NEAREST and
// GL_LINEAR with CLAMP_TO_EDGE must return, and values recorded from OSMesa 22.3.6 that it reproduces bit for bit.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "gpu/pipeline/texture_sampling.h"
#include "test_support.h"

using namespace uvr::gpu;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();

// The CPU the recorded values come from (x86-64 with FMA3, Mesa 22.3.6): fused float lerps, rounding 8-bit lerps.
constexpr LlvmpipeCpu kRecordedCpu{true, true};

// Same bits (distinguishes -0 from +0, compares NaNs equal to themselves).
bool same_bits(const glm::vec4& a, const glm::vec4& b) { return std::memcmp(&a[0], &b[0], sizeof(float) * 4) == 0; }

// A texture of random contents in every format; u16 and u8 texels are whole integers, f32 texels floats in [0, 1].
struct TestTexture {
    std::vector<float> f32;
    std::vector<uint16_t> u16;
    std::vector<uint8_t> u8;
    TextureView view;
    TestTexture(TexelFormat format, int channels, int w, int h, int d, uint32_t seed)
    {
        std::mt19937 rng(seed);
        const std::size_t n = std::size_t(w) * std::size_t(h) * std::size_t(d) * std::size_t(channels);
        for (std::size_t i = 0; i < n; ++i) {
            const uint32_t k = rng();
            f32.push_back(float(k % 100003u) / 100003.0f);
            u16.push_back(uint16_t(k));
            u8.push_back(uint8_t(k));
        }
        const void* data = format == TexelFormat::f32   ? static_cast<const void*>(f32.data())
                           : format == TexelFormat::u16 ? static_cast<const void*>(u16.data())
                                                        : static_cast<const void*>(u8.data());
        view = TextureView{format, channels, w, h, d, data};
    }
};

const TexelFormat kFormats[] = {TexelFormat::f32, TexelFormat::u16, TexelFormat::u8};

}  // namespace

TEST_CASE("x86 float-to-int conversions truncate or round to even and overflow to the integer indefinite")
{
    SECTION("truncation goes toward zero")
    {
        CHECK(x86_cvtt(2.9f) == 2);
        CHECK(x86_cvtt(-2.9f) == -2);
        CHECK(x86_cvtt(-0.5f) == 0);
    }
    SECTION("rounding sends halves to the even neighbour")
    {
        CHECK(x86_cvt_rne(0.5f) == 0);
        CHECK(x86_cvt_rne(1.5f) == 2);
        CHECK(x86_cvt_rne(2.5f) == 2);
        CHECK(x86_cvt_rne(-2.5f) == -2);
        CHECK(x86_cvt_rne(2.5000002f) == 3);
    }
    SECTION("rounding agrees with the C library's nearest-even rounding on every float of [-2^24, 2^24] in a sweep")
    {
        // Every 97th float bit pattern up from 0 to 2^24 and its negative: halves, quarters, near-integers and large
        // integers alike; std::nearbyint rounds in the default mode, to nearest, ties to even.
        int differ = 0;
        for (uint32_t bits = 0; bits <= 0x4b800000u; bits += 97) {
            float x;
            std::memcpy(&x, &bits, sizeof x);
            for (const float v : {x, -x})
                if (x86_cvt_rne(v) != static_cast<int32_t>(std::nearbyint(v))) ++differ;
        }
        CHECK(differ == 0);
    }
    SECTION("NaN, infinities and values beyond 2^31 give 0x80000000")
    {
        for (float x : {kNaN, kInf, -kInf, 2147483648.0f, -2147483904.0f, 1e10f}) {
            INFO("x = " << x);
            CHECK(x86_cvtt(x) == std::numeric_limits<int32_t>::min());
            CHECK(x86_cvt_rne(x) == std::numeric_limits<int32_t>::min());
        }
        CHECK(x86_cvtt(-2147483648.0f) == std::numeric_limits<int32_t>::min());  // in range, and the same bits
    }
}

TEST_CASE("unorm values convert to float by a multiply with the rounded reciprocal, and back by rounding")
{
    SECTION("8-bit: both ends exact, every value within 1.5 ulp of i / 255, and the round trip is the identity")
    {
        // The error: the constant's rounding (relative 2^-24, times i / 255 <= 1) plus the product's (half an ulp,
        // at most 2^-25 below 1): 1.5 * 2^-24 in all. It is not i / 255.0f: 126 of the 256 values differ from it.
        CHECK(unorm8_to_float(0) == 0.0f);
        CHECK(unorm8_to_float(255) == 1.0f);
        int differ = 0;
        for (int i = 0; i < 256; ++i) {
            const float f = unorm8_to_float(uint8_t(i));
            INFO("i = " << i);
            CHECK(std::fabs(double(f) - i / 255.0) <= 1.5 * std::ldexp(1.0, -24));
            CHECK(float_to_unorm8(f) == i);
            differ += f != float(i) / 255.0f;
        }
        CHECK(differ == 126);
    }
    SECTION("16-bit: the same")
    {
        CHECK(unorm16_to_float(65535) == 1.0f);
        for (int i = 0; i < 65536; ++i) {
            const float f = unorm16_to_float(uint16_t(i));
            INFO("i = " << i);
            REQUIRE(float_to_unorm16(f) == i);
        }
    }
    SECTION("uploads clamp to [0, 1] and send NaN to 0")
    {
        CHECK(float_to_unorm8(-0.25f) == 0);
        CHECK(float_to_unorm8(1.5f) == 255);
        CHECK(float_to_unorm8(kNaN) == 0);
        CHECK(float_to_unorm16(-1.0f) == 0);
        CHECK(float_to_unorm16(kInf) == 65535);
    }
    SECTION("RGBA16 uploads round ties away from zero (values OSMesa 22.3.6 stored)")
    {
        // x * 65535 rounds (in float) to exactly 50500.5, 17522.5 and 2360.5.
        CHECK(float_to_unorm16(0x1.8a8a8ap-1f) == 50501);
        CHECK(float_to_unorm16(0x1.11cb12p-2f) == 17523);
        CHECK(float_to_unorm16(0x1.271128p-5f) == 2361);
    }
}

TEST_CASE("the lerps of both paths stay between their ends and return v0 at weight zero")
{
    SECTION("float lerp, fused and unfused")
    {
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        for (int k = 0; k < 10000; ++k) {
            const float w = u(rng), v0 = u(rng), v1 = u(rng);
            for (bool fma : {false, true}) {
                const float r = lerp_f32(w, v0, v1, fma);
                INFO("w = " << w << ", v0 = " << v0 << ", v1 = " << v1 << ", fma = " << fma);
                CHECK(r >= std::min(v0, v1));
                CHECK(r <= std::max(v0, v1));
                CHECK(lerp_f32(0.0f, v0, v1, fma) == v0);
            }
        }
    }
    SECTION("8-bit lerp: within half a step of the exact value when rounding, within one step below when truncating")
    {
        for (int w = 0; w < 256; w += 5)
            for (int v0 = 0; v0 < 256; v0 += 3)
                for (int v1 = 0; v1 < 256; v1 += 7) {
                    const double exact = v0 + w * (v1 - v0) / 256.0;
                    const int r = lerp_unorm8(uint32_t(w), uint8_t(v0), uint8_t(v1), true);
                    const int t = lerp_unorm8(uint32_t(w), uint8_t(v0), uint8_t(v1), false);
                    INFO("w = " << w << ", v0 = " << v0 << ", v1 = " << v1);
                    REQUIRE(std::fabs(r - exact) <= 0.5);
                    REQUIRE(t <= exact);
                    REQUIRE(t > exact - 1.0);
                }
    }
}

TEST_CASE("sampling at texel centres returns the texel values")
{
    // Power-of-two sizes make (i + 0.5) / n * n exact, so the linear weights are exactly 0.
    for (TexelFormat f : kFormats)
        for (TextureFilter filter : {TextureFilter::nearest, TextureFilter::linear}) {
            SECTION(std::string(texel_format_name(f)) + (filter == TextureFilter::linear ? " linear" : " nearest"))
            {
                const TestTexture tex(f, 4, 8, 4, 16, 11);
                for (int z = 0; z < 16; ++z)
                    for (int y = 0; y < 4; ++y)
                        for (int x = 0; x < 8; ++x) {
                            const float s = (x + 0.5f) / 8, t = (y + 0.5f) / 4, r = (z + 0.5f) / 16;
                            const glm::vec4 got = sample_3d(tex.view, s, t, r, filter, kRecordedCpu);
                            INFO("texel (" << x << ", " << y << ", " << z << ")");
                            REQUIRE(same_bits(got, texel_fetch(tex.view, x, y, z)));
                        }
                const TestTexture tex2(f, 1, 4, 8, 1, 12);
                for (int y = 0; y < 8; ++y)
                    for (int x = 0; x < 4; ++x) {
                        const float s = (x + 0.5f) / 4, t = (y + 0.5f) / 8;
                        const glm::vec4 got = sample_2d(tex2.view, s, t, filter, kRecordedCpu);
                        INFO("2D one-channel texel (" << x << ", " << y << ")");
                        REQUIRE(same_bits(got, texel_fetch(tex2.view, x, y)));
                        REQUIRE(got.g == 0.0f);
                        REQUIRE(got.a == 1.0f);
                    }
            }
        }
}

TEST_CASE("nearest picks the texel a coordinate falls in, boundaries belonging to the texel above")
{
    constexpr int n = 16;
    for (int i = 0; i < n; ++i) {
        const float boundary = float(i) / n;  // exact
        INFO("boundary " << i);
        CHECK(wrap_nearest_soa(boundary, n) == i);
        CHECK(wrap_nearest_aos(boundary, n) == i);
        CHECK(wrap_nearest_soa(std::nextafter(boundary, 2.0f), n) == i);
        if (i > 0) {
            CHECK(wrap_nearest_soa(std::nextafter(boundary, -1.0f), n) == i - 1);
            CHECK(wrap_nearest_aos(std::nextafter(boundary, -1.0f), n) == i - 1);
        }
    }
    SECTION("outside [0, 1] the edge texels, but NaN and infinities fall to texel 0 (cvttps2dq overflow)")
    {
        for (float c : {-0.3f, -1e-30f, -5.0f}) CHECK(wrap_nearest_soa(c, n) == 0);
        for (float c : {1.0f, 1.7f, 100.0f}) CHECK(wrap_nearest_soa(c, n) == n - 1);
        for (float c : {kNaN, kInf, -kInf, 1e10f}) {
            INFO("c = " << c);
            CHECK(wrap_nearest_soa(c, n) == 0);
            CHECK(wrap_nearest_aos(c, n) == 0);
        }
    }
}

TEST_CASE("linear interpolates between the two taps with the weight the wrap computes")
{
    SECTION("the float path's taps and weight")
    {
        const LinearTaps t = wrap_linear_soa((3 + 0.5f + 0.25f) / 8, 8);
        CHECK(t.i0 == 3);
        CHECK(t.i1 == 4);
        CHECK(t.weight == 0.25f);
    }
    SECTION("the 8-bit path rounds the position to 1/256 of a texel, ties to even")
    {
        const LinearTaps8 t = wrap_linear_aos((3 + 0.5f + 0.25f) / 8, 8);
        CHECK(t.i0 == 3);
        CHECK(t.i1 == 4);
        CHECK(t.weight == 64u);
        // 2048 c = 3 * 256 + 128 + 64.5 -> 64 (even); + 65.5 -> 66.
        CHECK(wrap_linear_aos((3 * 256 + 128 + 64.5f) / 2048, 8).weight == 64u);
        CHECK(wrap_linear_aos((3 * 256 + 128 + 65.5f) / 2048, 8).weight == 66u);
    }
    SECTION("random coordinates: the sample is the lerp tree of the taps' texels")
    {
        for (TexelFormat f : kFormats) {
            const TestTexture tex(f, 4, 5, 7, 1, 21);
            std::mt19937 rng(5);
            std::uniform_real_distribution<float> u(-0.1f, 1.1f);
            for (int k = 0; k < 2000; ++k) {
                const float s = u(rng), t = u(rng);
                const glm::vec4 got = sample_2d(tex.view, s, t, TextureFilter::linear, kRecordedCpu);
                glm::vec4 want;
                if (f == TexelFormat::u8) {
                    const LinearTaps8 x = wrap_linear_aos(s, 5), y = wrap_linear_aos(t, 7);
                    auto b = [&](int i, int j, int c) { return tex.u8[std::size_t((j * 5 + i) * 4 + c)]; };
                    for (int c = 0; c < 4; ++c) {
                        const uint8_t r0 = lerp_unorm8(x.weight, b(x.i0, y.i0, c), b(x.i1, y.i0, c), true);
                        const uint8_t r1 = lerp_unorm8(x.weight, b(x.i0, y.i1, c), b(x.i1, y.i1, c), true);
                        want[c] = unorm8_to_float(lerp_unorm8(y.weight, r0, r1, true));
                    }
                } else {
                    const LinearTaps x = wrap_linear_soa(s, 5), y = wrap_linear_soa(t, 7);
                    auto v = [&](int i, int j, int c) { return texel_fetch(tex.view, i, j)[c]; };
                    for (int c = 0; c < 4; ++c)
                        want[c] = lerp_f32(y.weight, lerp_f32(x.weight, v(x.i0, y.i0, c), v(x.i1, y.i0, c), true),
                                           lerp_f32(x.weight, v(x.i0, y.i1, c), v(x.i1, y.i1, c), true), true);
                }
                INFO(texel_format_name(f) << " at (" << s << ", " << t << ")");
                REQUIRE(same_bits(got, want));
            }
        }
    }
}

TEST_CASE("CLAMP_TO_EDGE returns the edge texels beyond the texture")
{
    for (TexelFormat f : kFormats) {
        SECTION(texel_format_name(f))
        {
            const TestTexture tex(f, 4, 6, 1, 1, 31);
            const glm::vec4 first = texel_fetch(tex.view, 0, 0), last = texel_fetch(tex.view, 5, 0);
            for (float c : {-0.3f, -5.0f, 0.0f, 0.5f / 6}) {
                INFO("coordinate " << c);
                CHECK(same_bits(sample_2d(tex.view, c, 0.5f, TextureFilter::linear, kRecordedCpu), first));
            }
            for (float c : {1.0f, 1.7f, 1e10f, kInf, kNaN}) {
                INFO("coordinate " << c);
                CHECK(same_bits(sample_2d(tex.view, c, 0.5f, TextureFilter::linear, kRecordedCpu), last));
            }
            // Far below: the float path clamps to texel 0, the 8-bit path's iround overflows and wraps to the last
            // texel (as OSMesa does).
            const glm::vec4 far_below = sample_2d(tex.view, -1e10f, 0.5f, TextureFilter::linear, kRecordedCpu);
            CHECK(same_bits(far_below, f == TexelFormat::u8 ? last : first));
        }
    }
}

TEST_CASE("3D linear samples equal the values OSMesa 22.3.6 (llvmpipe, x86-64 with FMA3) returned")
{
    // The texture of the recording: 4 x 3 x 2 RGBA, each channel from a hash of (x, y, z, c); f32 texels are
    // (k mod 100003) / 100003, u16 and u8 texels the low bits of k.
    auto hash = [](int x, int y, int z, int c) {
        uint32_t v = uint32_t(x * 73856093 ^ y * 19349663 ^ z * 83492791 ^ c * 2654435761u);
        v ^= v >> 13;
        v *= 0x5bd1e995u;
        v ^= v >> 15;
        return v;
    };
    std::vector<float> vf;
    std::vector<uint16_t> v16;
    std::vector<uint8_t> v8;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 4; ++x)
                for (int c = 0; c < 4; ++c) {
                    const uint32_t k = hash(x, y, z, c);
                    vf.push_back(float(k % 100003u) / 100003.0f);
                    v16.push_back(uint16_t(k));
                    v8.push_back(uint8_t(k));
                }
    struct Recorded {
        float coord[3];
        float rgba[4];
    };
    const Recorded f32[] = {
        {{0x1.413a92p-2f, 0x1.6a0902p-1f, 0x1.a8240cp-2f},
         {0x1.045536p-1f, 0x1.695a5p-1f, 0x1.25ae5ep-1f, 0x1.d1cf76p-2f}},
        {{0x1.99999ap-5f, 0x1.f0a3d8p-1f, 0x1p-1f},
         {0x1.ce2348p-3f, 0x1.6d2518p-1f, 0x1.2c899cp-1f, 0x1.a889a4p-2f}},
        {{-0x1.99999ap-3f, 0x1.4cccccp+0f, 0x1.0a3d7p-2f},
         {0x1.1a2b12p-3f, 0x1.59cab8p-1f, 0x1.1e0196p-1f, 0x1.0c6dp-2f}},
        {{0x1.f9adp-4f, 0x1.4f032ap-1f, 0x1.ff7ceep-1f},
         {0x1.1d2794p-2f, 0x1.ce2fbcp-2f, 0x1.1e48d4p-1f, 0x1.808568p-1f}},
        {{0x1.3c6efp-1f, 0x1.165a1ap-2f, 0x1.6fc2a2p-1f},
         {0x1.209f2cp-1f, 0x1.a8f884p-2f, 0x1.0ee274p-1f, 0x1.1a7a2p-1f}},
        {{0x1.8p-2f, 0x1p-1f, 0x1.8p-1f},
         {0x1.66d07p-1f, 0x1.7b2a64p-2f, 0x1.c2e7a6p-1f, 0x1.b30c78p-1f}},
    };
    const Recorded u16[] = {
        {{0x1.413a92p-2f, 0x1.6a0902p-1f, 0x1.a8240cp-2f},
         {0x1.69b9p-1f, 0x1.6a882p-1f, 0x1.f5dd62p-2f, 0x1.ea26dp-2f}},
        {{0x1.99999ap-5f, 0x1.f0a3d8p-1f, 0x1p-1f},
         {0x1.547354p-1f, 0x1.50cc5p-1f, 0x1.1bcf1cp-1f, 0x1.92ad94p-1f}},
        {{-0x1.99999ap-3f, 0x1.4cccccp+0f, 0x1.0a3d7p-2f},
         {0x1.8ab2e6p-1f, 0x1.f8f82cp-1f, 0x1.612d76p-1f, 0x1.e098c2p-1f}},
        {{0x1.f9adp-4f, 0x1.4f032ap-1f, 0x1.ff7ceep-1f},
         {0x1.a58382p-2f, 0x1.eba518p-2f, 0x1.3f3b5ap-1f, 0x1.2a4c5p-1f}},
        {{0x1.3c6efp-1f, 0x1.165a1ap-2f, 0x1.6fc2a2p-1f},
         {0x1.60c1cp-1f, 0x1.09dd1ep-2f, 0x1.2a9aa2p-1f, 0x1.d797dap-2f}},
        {{0x1.8p-2f, 0x1p-1f, 0x1.8p-1f},
         {0x1.6b156cp-1f, 0x1.f2b5f2p-2f, 0x1.1aad1ap-2f, 0x1.7ec17ep-5f}},
    };
    const Recorded u8[] = {
        {{0x1.413a92p-2f, 0x1.6a0902p-1f, 0x1.a8240cp-2f},
         {0x1.b5b5b8p-2f, 0x1.636364p-1f, 0x1.5d5d5ep-2f, 0x1.e9e9ecp-2f}},
        {{0x1.99999ap-5f, 0x1.f0a3d8p-1f, 0x1p-1f},
         {0x1.737374p-1f, 0x1.cdcddp-1f, 0x1.9d9dap-2f, 0x1.adadbp-1f}},
        {{-0x1.99999ap-3f, 0x1.4cccccp+0f, 0x1.0a3d7p-2f},
         {0x1.f1f1f4p-2f, 0x1.f7f7fap-1f, 0x1.818184p-5f, 0x1.d5d5d8p-1f}},
        {{0x1.f9adp-4f, 0x1.4f032ap-1f, 0x1.ff7ceep-1f},
         {0x1.cbcbcep-1f, 0x1.f1f1f4p-2f, 0x1.818184p-2f, 0x1.b5b5b8p-2f}},
        {{0x1.3c6efp-1f, 0x1.165a1ap-2f, 0x1.6fc2a2p-1f},
         {0x1.3d3d3ep-2f, 0x1.29292ap-1f, 0x1.4b4b4cp-1f, 0x1.79797ap-2f}},
        {{0x1.8p-2f, 0x1p-1f, 0x1.8p-1f},
         {0x1.151516p-1f, 0x1.5b5b5cp-1f, 0x1.575758p-1f, 0x1.ededfp-1f}},
    };
    auto check = [](const TextureView& view, const Recorded* rec, int n) {
        for (int i = 0; i < n; ++i) {
            const Recorded& r = rec[i];
            const glm::vec4 got =
                sample_3d(view, r.coord[0], r.coord[1], r.coord[2], TextureFilter::linear, kRecordedCpu);
            INFO(texel_format_name(view.format) << " sample " << i << ": got (" << got.r << ", " << got.g << ", "
                                                << got.b << ", " << got.a << ")");
            CHECK(same_bits(got, glm::vec4(r.rgba[0], r.rgba[1], r.rgba[2], r.rgba[3])));
        }
    };
    SECTION("f32") { check(TextureView{TexelFormat::f32, 4, 4, 3, 2, vf.data()}, f32, 6); }
    SECTION("u16") { check(TextureView{TexelFormat::u16, 4, 4, 3, 2, v16.data()}, u16, 6); }
    SECTION("u8") { check(TextureView{TexelFormat::u8, 4, 4, 3, 2, v8.data()}, u8, 6); }
    SECTION("without FMA, two of the float samples round differently")
    {
        const TextureView view{TexelFormat::f32, 4, 4, 3, 2, vf.data()};
        const LlvmpipeCpu no_fma{false, true};
        int differ = 0;
        for (const Recorded& r : f32) {
            const glm::vec4 got = sample_3d(view, r.coord[0], r.coord[1], r.coord[2], TextureFilter::linear, no_fma);
            differ += !same_bits(got, glm::vec4(r.rgba[0], r.rgba[1], r.rgba[2], r.rgba[3]));
        }
        CHECK(differ == 2);
    }
}

TEST_CASE("the FMA fast path of the float linear filter gives the plain path's bits")
{
    // Texels over the whole float range (random bit patterns, finite, denormals included), not only the table's
    // [0, 1]: the two paths must agree on every rounding, not on typical values.
    const bool fast = host_has_fma();
    INFO("host has FMA3: " << fast << " (without it the fast path is never taken and this checks nothing else)");
    REQUIRE(fast == host_llvmpipe_cpu().fma);
    if (!fast) return;
    std::mt19937 rng(11);
    auto random_float = [&] {
        for (;;) {
            const uint32_t bits = rng();
            float f;
            std::memcpy(&f, &bits, 4);
            if (std::isfinite(f)) return f;
        }
    };
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    const float specials[] = {0.0f, -0.0f, 1.0f, 0.5f, 1e-30f, -1e-30f, 2e-45f, 0.999999f, 1.0000001f,
                              kInf, -kInf, kNaN, 3e9f, -3e9f};
    for (int dims = 2; dims <= 3; ++dims) {
        const int w = 17, h = 9, d = dims == 3 ? 5 : 1;
        std::vector<float> texels(std::size_t(w) * h * d * 4);
        for (float& t : texels) t = random_float();
        const TextureView view{TexelFormat::f32, 4, w, h, d, texels.data()};
        auto check = [&](const float* coord) {
            const glm::vec4 plain = sample_linear_soa(view, coord, dims, kRecordedCpu);
            const glm::vec4 fma = sample_linear_f32x4_fma(view, coord, dims);
            INFO(dims << "D at (" << coord[0] << ", " << coord[1] << ", " << coord[2] << "): plain (" << plain.r
                      << ", " << plain.g << ", " << plain.b << ", " << plain.a << "), fast (" << fma.r << ", "
                      << fma.g << ", " << fma.b << ", " << fma.a << ")");
            CHECK(same_bits(plain, fma));
        };
        SECTION(std::to_string(dims) + "D: random coordinates and texels")
        {
            for (int i = 0; i < 200000; ++i) {
                const float coord[3] = {u(rng), u(rng), u(rng)};
                check(coord);
            }
        }
        SECTION(std::to_string(dims) + "D: texel centres, edges, NaN, infinities, huge and tiny coordinates")
        {
            for (float a : specials)
                for (float b : specials)
                    for (float c : {0.25f, kNaN, 1.0f}) {
                        const float coord[3] = {a, b, c};
                        check(coord);
                    }
            for (int x = 0; x < w; ++x) {
                const float centre = (float(x) + 0.5f) / float(w);
                const float coord[3] = {centre, centre, centre};
                check(coord);
            }
        }
    }
}

TEST_CASE("a one-channel 8-bit volume samples as the red channel of the same texels in RGBA8")
{
    // sample_3d takes its own path for R8 volumes (the ray caster's); the RGBA8 copy goes through the general AoS
    // filter, channel by channel. Both rounding variants of the 8-bit lerp, random and special coordinates.
    std::mt19937 rng(23);
    const int w = 13, h = 7, d = 6;
    std::vector<uint8_t> r8(std::size_t(w) * h * d), rgba8(4 * r8.size());
    for (std::size_t i = 0; i < r8.size(); ++i) {
        r8[i] = uint8_t(rng() & 0xffu);
        rgba8[4 * i] = r8[i];
        rgba8[4 * i + 3] = 255;
    }
    const TextureView one{TexelFormat::u8, 1, w, h, d, r8.data()};
    const TextureView four{TexelFormat::u8, 4, w, h, d, rgba8.data()};
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    const float specials[] = {0.0f, -0.0f, 1.0f, 0.5f, 1.0f / 26.0f, 1e-30f, 0.999999f, kInf, -kInf, kNaN, 3e9f, -3e9f};
    for (const bool rounds : {true, false}) {
        LlvmpipeCpu cpu = kRecordedCpu;
        cpu.lerp8_rounds = rounds;
        int differ = 0, checked = 0;
        auto check = [&](float s, float t, float r) {
            const glm::vec4 a = sample_3d(one, s, t, r, TextureFilter::linear, cpu);
            const glm::vec4 b = sample_3d(four, s, t, r, TextureFilter::linear, cpu);
            const glm::vec4 expected(b.r, unorm8_to_float(0), unorm8_to_float(0), unorm8_to_float(255));
            ++checked;
            if (!same_bits(a, expected)) ++differ;
        };
        for (int i = 0; i < 100000; ++i) check(u(rng), u(rng), u(rng));
        for (float a : specials)
            for (float b : specials)
                for (float c : specials) check(a, b, c);
        INFO((rounds ? "rounding" : "truncating") << " lerp: " << differ << " of " << checked << " samples differ");
        CHECK(differ == 0);
    }
}
