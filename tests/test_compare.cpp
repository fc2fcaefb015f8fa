// docs/spec.md §4's error measures and `uvr compare`'s report.
#include <cmath>
#include <algorithm>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "reference/error_measures.h"
#include "image_errors.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::run_uvr;
using uvr::test::TempDir;

namespace {

// sweep.csv prints with %.9g: nine significant digits, a relative rounding of at most 5e-9.
constexpr double kCsvRelative = 5e-9;

std::vector<std::string> split_csv(const std::string& line)
{
    std::vector<std::string> out(1);
    for (char c : line) {
        if (c == ',')
            out.emplace_back();
        else
            out.back().push_back(c);
    }
    return out;
}

}  // namespace

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
        const test::ImageErrors e = test::image_errors(read_npy(dir + "/" + label + ".npy"), ref);
        CHECK(res["rmse"].get<double>() == Approx(e.rmse).margin(1e-15));
        CHECK(res["max_abs"].get<double>() == Approx(e.max_abs).margin(1e-15));
        CHECK(res["visible_fraction"].get<double>() == Approx(e.visible_fraction));
        if (label != "reference") CHECK(std::filesystem::exists(dir + "/" + res["error_map"].get<std::string>()));
    }
    const std::string page = uvr::test::file_contents(dir + "/index.html");
    CHECK_THAT(page, Catch::Contains("havs-emu-k6.png") && Catch::Contains("havs-emu-k6-error.png") &&
                         Catch::Contains("metrics.json"));
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr compare --interpolation gpu,exact shows HAVS and VICP in both modes side by side")
{
    TempDir tmp("compare-modes");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string dir = tmp.file("report");
    const auto r = run_uvr("compare builtin:torus-small --algos havs,vicp --interpolation gpu,exact --size 48x40 "
                           "--report '" + dir + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto m = nlohmann::json::parse(uvr::test::file_contents(dir + "/metrics.json"));
    // The reference, HAVS twice, VICP twice.
    REQUIRE(m["results"].size() == 5);
    CHECK(m["results"][1]["label"] == "havs-emu-k6");
    CHECK(m["results"][1]["stats"]["interpolation"] == "gpu");
    CHECK(m["results"][2]["label"] == "havs-emu-k6-exact-interpolation");
    CHECK(m["results"][2]["stats"]["interpolation"] == "exact");
    CHECK(m["results"][3]["label"] == "vicp-emu-mpvonc");
    CHECK(m["results"][3]["stats"]["interpolation"] == "gpu");
    CHECK(m["results"][4]["label"] == "vicp-emu-mpvonc-exact-interpolation");
    CHECK(m["results"][4]["stats"]["interpolation"] == "exact");
    // The two modes are different images of one scene.
    CHECK(read_npy(dir + "/havs-emu-k6.npy").rgba != read_npy(dir + "/havs-emu-k6-exact-interpolation.npy").rgba);
    CHECK(read_npy(dir + "/vicp-emu-mpvonc.npy").rgba !=
          read_npy(dir + "/vicp-emu-mpvonc-exact-interpolation.npy").rgba);
    const auto bad = run_uvr("compare builtin:torus-small --algos havs --interpolation gpu,linear --size 48x40 "
                             "--report '" + tmp.file("bad") + "'");
    CHECK(bad.exit_code != 0);
    CHECK_THAT(bad.err, Catch::Contains("--interpolation"));
    CHECK_FALSE(std::filesystem::exists(tmp.file("bad")));
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr compare --interpolation gpu,exact shows the ray caster in both modes side by side")
{
    TempDir tmp("compare-raycast-modes");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string dir = tmp.file("report");
    const auto r = run_uvr("compare builtin:torus-volume --algos raycast --interpolation gpu,exact --size 48x40 "
                           "--report '" + dir + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto m = nlohmann::json::parse(uvr::test::file_contents(dir + "/metrics.json"));
    REQUIRE(m["results"].size() == 3);  // the reference, the published passes, the exact ray
    CHECK(m["results"][1]["label"] == "raycast-emu-post");
    CHECK(m["results"][1]["stats"]["interpolation"] == "gpu");
    CHECK(m["results"][1]["stats"]["box"]["triangles"].get<int>() >= 12);
    CHECK(m["results"][1]["stats"]["box"]["overlaps"] == 0);
    CHECK(m["results"][2]["label"] == "raycast-emu-post-exact-interpolation");
    CHECK(m["results"][2]["stats"]["interpolation"] == "exact");
    CHECK_FALSE(m["results"][2]["stats"].contains("box"));
    CHECK(read_npy(dir + "/raycast-emu-post.npy").rgba != read_npy(dir + "/raycast-emu-post-exact-interpolation.npy").rgba);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr sweep's CSV holds the numbers its images give, the table-size sweep included")
{
    TempDir tmp("sweep-csv");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string dir = tmp.file("report");
    const auto r = run_uvr("sweep builtin:torus-small --size 48x40 --k 1,4 --views 2 --table-sizes 16,64 --report '" +
                           dir + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    std::istringstream csv(uvr::test::file_contents(dir + "/sweep.csv"));
    std::string line;
    std::getline(csv, line);
    const std::vector<std::string> header = split_csv(line);
    REQUIRE(header.size() == 13);
    auto col = [&](const std::string& name) {
        return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
    };
    std::size_t rows = 0, table_rows = 0;
    while (std::getline(csv, line)) {
        const std::vector<std::string> f = split_csv(line);
        REQUIRE(f.size() == header.size());
        const std::string view = f[col("view")], k = f[col("k")], mode = f[col("mode")];
        INFO(line);
        // The run's image, and what it is measured against: the reference, or for the table-size runs the exact run at
        // the largest k.
        std::string image = "v" + view + "-k" + k + "-" + mode, against = "v" + view + "-reference";
        if (mode == "table-vs-exact") {
            image = "v" + view + "-k" + k + "-table" + f[col("table_size")];
            against = "v" + view + "-k" + k + "-exact";
            ++table_rows;
        } else {
            ++rows;
        }
        const test::ImageErrors e = test::image_errors(read_npy(dir + "/runs/" + image + ".npy"), read_npy(dir + "/runs/" + against + ".npy"));
        CHECK(std::stod(f[col("rmse")]) == Approx(e.rmse).epsilon(kCsvRelative).margin(1e-300));
        CHECK(std::stod(f[col("max_abs")]) == Approx(e.max_abs).epsilon(kCsvRelative).margin(1e-300));
        CHECK(std::stod(f[col("visible_fraction")]) == Approx(e.visible_fraction).epsilon(kCsvRelative));
    }
    CHECK(rows == 2 * 2 * 2);    // views x k x (exact, table)
    CHECK(table_rows == 2 * 2);  // views x table sizes
    CHECK(std::filesystem::exists(dir + "/table_error_vs_size.png"));
    CHECK_THAT(uvr::test::file_contents(dir + "/index.html"), Catch::Contains("table_error_vs_size.png"));
    unsetenv("UVR_CACHE_DIR");
}
