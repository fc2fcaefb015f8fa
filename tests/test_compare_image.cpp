// `uvr compare --image`: an image made elsewhere, measured against the reference of the same scene like an algorithm's
//. The expected measures are computed here from the perturbation, pixel by pixel.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <ImfRgbaFile.h>
#include <nlohmann/json.hpp>

#include "reference/image.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::run_uvr;
using uvr::test::TempDir;

namespace {

// metrics.json prints doubles with 17 significant digits; the measures are sums in double in pixel order, as here.
// Only the last bits of the square root may differ: 1e-12 relative.
constexpr double kMeasureRelative = 1e-12;

constexpr const char* kScene = "builtin:torus-small --size 40x32 --view 30,50";

struct Expected {
    double rmse = 0, max_abs = 0, visible = 0, covered_left_empty = 0;
};

// docs/spec.md §4 over `channels` channels (4, or 3: colour against the reference's premultiplied colour).
Expected expected(const Image& a, const Image& ref, int channels)
{
    Expected e;
    double sum = 0;
    std::size_t visible = 0, covered = 0, empty = 0, n = std::size_t(a.width) * std::size_t(a.height);
    for (std::size_t p = 0; p < n; ++p) {
        double worst = 0;
        int zeros = 0;
        for (int c = 0; c < channels; ++c) {
            const double d = std::fabs(double(a.rgba[4 * p + std::size_t(c)]) - double(ref.rgba[4 * p + std::size_t(c)]));
            sum += d * d;
            worst = std::max(worst, d);
            zeros += a.rgba[4 * p + std::size_t(c)] == 0.0f ? 1 : 0;
        }
        e.max_abs = std::max(e.max_abs, worst);
        visible += worst > 1.0 / 255.0 ? 1 : 0;
        if (double(ref.rgba[4 * p + 3]) > 1.0 / 255.0) {  // covered: alpha above 1/255
            ++covered;
            empty += zeros == channels ? 1 : 0;
        }
    }
    e.rmse = std::sqrt(sum / double(std::size_t(channels) * n));
    e.visible = double(visible) / double(n);
    e.covered_left_empty = double(empty) / double(covered);
    return e;
}

// An RGB half-float EXR, as many renderers write them: no alpha, so colour only, rounded to half by OpenEXR here.
void write_half_rgb_exr(const std::string& path, const Image& im, Image& as_half)
{
    std::vector<Imf::Rgba> px(std::size_t(im.width) * std::size_t(im.height));
    as_half = im;
    for (std::size_t p = 0; p < px.size(); ++p) {
        px[p] = Imf::Rgba(im.rgba[4 * p], im.rgba[4 * p + 1], im.rgba[4 * p + 2]);
        as_half.rgba[4 * p] = float(px[p].r);
        as_half.rgba[4 * p + 1] = float(px[p].g);
        as_half.rgba[4 * p + 2] = float(px[p].b);
        as_half.rgba[4 * p + 3] = 1.0f;
    }
    Imf::RgbaOutputFile out(path.c_str(), im.width, im.height, Imf::WRITE_RGB);
    out.setFrameBuffer(px.data(), 1, std::size_t(im.width));
    out.writePixels(im.height);
}

void write_pfm(const std::string& path, const Image& im)
{
    std::ofstream out(path, std::ios::binary);
    out << "PF\n" << im.width << " " << im.height << "\n-1.0\n";
    for (int y = im.height - 1; y >= 0; --y)  // PFM stores the bottom row first
        for (int x = 0; x < im.width; ++x) out.write(reinterpret_cast<const char*>(im.pixel(x, y)), 12);
}

const nlohmann::json& result(const nlohmann::json& m, const std::string& label)
{
    for (const auto& r : m["results"])
        if (r["label"] == label) return r;
    FAIL("no result labelled " << label);
    return m;
}

void check_measures(const nlohmann::json& r, const Expected& e)
{
    INFO(r.dump());
    CHECK(r["rmse"].get<double>() == Approx(e.rmse).epsilon(kMeasureRelative));
    CHECK(r["max_abs"].get<double>() == Approx(e.max_abs).epsilon(kMeasureRelative));
    CHECK(r["visible_fraction"].get<double>() == Approx(e.visible).epsilon(kMeasureRelative));
    CHECK(r["covered_left_empty"].get<double>() == Approx(e.covered_left_empty).epsilon(kMeasureRelative));
}

}  // namespace

TEST_CASE("compare --image measures an outside image exactly as the test computes it, in every format")
{
    TempDir tmp("cimg");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const auto base = run_uvr(std::string("compare ") + kScene + " --algos reference --report '" + tmp.file("ref") + "'");
    INFO(base.err);
    REQUIRE(base.exit_code == 0);
    const Image ref = read_npy(tmp.file("ref/reference.npy"));
    // The perturbation: +0.01 on the red of every 7th pixel, -0.003 on the alpha of every 5th, 0.5 on one pixel's
    // green: visible on some pixels, not on others.
    Image bent = ref;
    for (std::size_t p = 0; p < std::size_t(ref.width) * std::size_t(ref.height); ++p) {
        if (p % 7 == 0) bent.rgba[4 * p] += 0.01f;
        if (p % 5 == 0) bent.rgba[4 * p + 3] -= 0.003f;
    }
    bent.rgba[4 * 333 + 1] += 0.5f;
    for (std::size_t p = 3; p < std::size_t(ref.width) * std::size_t(ref.height); p += 11)  // dropped fragments
        for (int c = 0; c < 4; ++c) bent.rgba[4 * p + std::size_t(c)] = 0.0f;
    write_npy(tmp.file("bent.npy"), bent);
    write_pfm(tmp.file("bent.pfm"), bent);
    write_png(tmp.file("bent.png"), bent, glm::dvec3(0.0));
    write_exr(tmp.file("bent.exr"), bent);
    Image bent_half;
    write_half_rgb_exr(tmp.file("bent-half.exr"), bent, bent_half);
    const auto r = run_uvr(std::string("compare ") + kScene + " --algos reference --image '" + tmp.file("bent.npy") +
                           "' --image '" + tmp.file("bent.pfm") + "' --image '" + tmp.file("bent.png") +
                           "' --image '" + tmp.file("bent.exr") + "' --image '" + tmp.file("bent-half.exr") +
                           "' --label npy --label pfm --label png --label exr --label exr-half --report '" +
                           tmp.file("out") + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto m = nlohmann::json::parse(test::file_contents(tmp.file("out/metrics.json")));
    SECTION("a .npy (premultiplied RGBA): all four channels")
    {
        check_measures(result(m, "npy"), expected(bent, ref, 4));
        CHECK(result(m, "npy")["colour_only"] == false);
        CHECK(std::filesystem::exists(tmp.file("out/npy-error.png")));
    }
    SECTION("an .exr with alpha (float RGBA): all four channels, as the .npy")
    {
        check_measures(result(m, "exr"), expected(bent, ref, 4));
        CHECK(result(m, "exr")["colour_only"] == false);
    }
    SECTION("an .exr without alpha (half RGB): the colour as half floats hold it")
    {
        check_measures(result(m, "exr-half"), expected(bent_half, ref, 3));
        CHECK(result(m, "exr-half")["colour_only"] == true);
    }
    SECTION("a .pfm (colour, rows from the bottom): the colour, as the test wrote it")
    {
        check_measures(result(m, "pfm"), expected(bent, ref, 3));
        CHECK(result(m, "pfm")["colour_only"] == true);
    }
    SECTION("a .png (8 bits over black): the colour in steps of 1/255")
    {
        Image quantized = bent;
        for (std::size_t p = 0; p < std::size_t(bent.width) * std::size_t(bent.height); ++p)
            for (int c = 0; c < 3; ++c) {
                const double v = double(bent.rgba[4 * p + std::size_t(c)]) + (1.0 - double(bent.rgba[4 * p + 3])) * 0.0;
                quantized.rgba[4 * p + std::size_t(c)] =
                    float(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)) / 255.0f;
            }
        check_measures(result(m, "png"), expected(quantized, ref, 3));
        CHECK(test::file_contents(tmp.file("out/index.html")).find("colour only") != std::string::npos);
    }
    SECTION("the unperturbed reference as an image measures zero")
    {
        const auto z = run_uvr(std::string("compare ") + kScene + " --algos reference --image '" +
                               tmp.file("ref/reference.npy") + "' --label same --json --report '" + tmp.file("z") + "'");
        REQUIRE(z.exit_code == 0);
        const auto mz = nlohmann::json::parse(z.out);
        CHECK(result(mz, "same")["rmse"].get<double>() == 0.0);
        CHECK(result(mz, "same")["max_abs"].get<double>() == 0.0);
    }
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("compare --image refuses a wrong size or a malformed file, naming it, and writes nothing")
{
    TempDir tmp("cimg-bad");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    write_npy(tmp.file("small.npy"), Image(41, 32));
    {
        std::ofstream(tmp.file("trunc.npy"), std::ios::binary) << "\x93NUMPY\x01\x00";
        std::ofstream(tmp.file("bad.pfm"), std::ios::binary) << "PF\n40 x\n-1\n";
        std::ofstream(tmp.file("short.pfm"), std::ios::binary) << "PF\n40 32\n-1.0\n" << std::string(100, '\0');
        std::ofstream(tmp.file("fake.png"), std::ios::binary) << "not a png at all";
        std::ofstream(tmp.file("x.exr"), std::ios::binary) << "v/1";
    }
    struct Case {
        std::string file, phrase;
    };
    for (const Case& c : {Case{"small.npy", "is 41x32, the scene is 40x32"}, Case{"trunc.npy", ".npy"},
                          Case{"bad.pfm", "malformed PFM header"}, Case{"short.pfm", "data bytes, expected"},
                          Case{"fake.png", "not a readable PNG"}, Case{"x.exr", "OpenEXR"}}) {
        const std::string dir = tmp.file("out-" + c.file);
        const auto r = run_uvr(std::string("compare ") + kScene + " --algos reference --image '" + tmp.file(c.file) +
                               "' --report '" + dir + "'");
        INFO(c.file << ": " << r.err);
        CHECK(r.exit_code != 0);
        CHECK_THAT(r.err, Catch::Contains(c.file));
        CHECK_THAT(r.err, Catch::Contains(c.phrase));
        CHECK(!std::filesystem::exists(dir));
    }
    const auto labels = run_uvr(std::string("compare ") + kScene + " --algos reference --image '" +
                                tmp.file("small.npy") + "' --label a --label b --report '" + tmp.file("l") + "'");
    CHECK(labels.exit_code != 0);
    CHECK_THAT(labels.err, Catch::Contains("one --label per --image"));
    CHECK(!std::filesystem::exists(tmp.file("l")));
    unsetenv("UVR_CACHE_DIR");
}
