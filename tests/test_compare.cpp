// SPEC §4's error measures and `uvr compare`'s report.
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "reference/error_measures.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::run_uvr;
using uvr::test::TempDir;

TEST_CASE("error measures on images whose errors are known")
{
    Image ref(2, 1), img(2, 1);
    // Pixel 0 off by 0.1 in red only; pixel 1 off by 0.001 in every channel.
    img.pixel(0, 0)[0] = 0.1f;
    for (int c = 0; c < 4; ++c) img.pixel(1, 0)[c] = 0.001f;
    const ErrorMeasures e = measure_errors(img, ref);
    const double expected_rmse = std::sqrt((double(0.1f) * double(0.1f) + 4.0 * double(0.001f) * double(0.001f)) / 8.0);
    CHECK(e.rmse == Approx(expected_rmse).epsilon(1e-12));
    CHECK(e.max_abs == Approx(0.1).epsilon(1e-7));
    CHECK(e.psnr == Approx(20.0 * std::log10(1.0 / expected_rmse)).epsilon(1e-12));
    CHECK(e.visible_fraction == 0.5);  // 0.001 < 1/255 < 0.1
    CHECK(std::isinf(measure_errors(ref, ref).psnr));
    Image other(3, 1);
    uvr::test::require_input_error([&] { measure_errors(other, ref); }, {"cannot compare"});
}

TEST_CASE("uvr compare writes the images, error maps, metrics.json and a page whose numbers the images give")
{
    TempDir tmp("compare");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string dir = tmp.file("report");
    const auto r = run_uvr("compare builtin:torus-small --algos reference,havs --size 48x40 --report '" + dir + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto m = nlohmann::json::parse(uvr::test::file_contents(dir + "/metrics.json"));
    REQUIRE(m["results"].size() == 2);
    const Image ref = read_npy(dir + "/reference.npy");
    for (const auto& res : m["results"]) {
        const std::string label = res["label"];
        INFO(label);
        CHECK(std::filesystem::exists(dir + "/" + res["image"].get<std::string>()));
        const Image img = read_npy(dir + "/" + label + ".npy");
        // Recomputed here, independently of reference/error_measures.cpp.
        double sum = 0.0, worst = 0.0;
        std::size_t visible = 0;
        for (std::size_t p = 0; p < img.rgba.size() / 4; ++p) {
            double pw = 0.0;
            for (int c = 0; c < 4; ++c) {
                const double d = std::fabs(double(img.rgba[4 * p + c]) - double(ref.rgba[4 * p + c]));
                sum += d * d;
                pw = std::max(pw, d);
            }
            worst = std::max(worst, pw);
            visible += pw > 1.0 / 255.0;
        }
        CHECK(res["rmse"].get<double>() == Approx(std::sqrt(sum / double(img.rgba.size()))).margin(1e-15));
        CHECK(res["max_abs"].get<double>() == Approx(worst).margin(1e-15));
        CHECK(res["visible_fraction"].get<double>() == Approx(double(visible) / double(img.rgba.size() / 4)));
        if (label != "reference") CHECK(std::filesystem::exists(dir + "/" + res["error_map"].get<std::string>()));
    }
    const std::string page = uvr::test::file_contents(dir + "/index.html");
    CHECK_THAT(page, Catch::Contains("havs-emu-k6.png") && Catch::Contains("havs-emu-k6-error.png") &&
                         Catch::Contains("metrics.json"));
    unsetenv("UVR_CACHE_DIR");
}
