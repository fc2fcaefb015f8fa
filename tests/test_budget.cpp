// `uvr budget` (docs/spec.md §7): the baseline equals the reference, each factor run differs from the
// baseline by its own switch only, every number is docs/spec.md §4's measure of the kept images, and scenes whose
// answer is known give it.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "reference/error_measures.h"
#include "reference/image.h"
#include "test_support.h"

using uvr::test::CommandResult;
using uvr::test::run_uvr;
using uvr::test::TempDir;

namespace {

// The baseline's bar: bench/budget.h's kBudgetBaselineMax, the float32 precision HAVS and VICP keep with every
// switch exact (at most 9e-7 measured on the hardest views, tests/test_exact_coverage.cpp).
constexpr double kBaselineMax = 2e-6;
// The bar for VICP's interpolation factor where the distances are linear (an orthographic view): float
// rounding, away from the published wrong exits (docs/budget.md says why those are apart).
constexpr double kLinearInterpolationRmse = 1e-6;

const std::string kBluntFin = "'" + uvr::test::data_path("vtk-data/bluntfinxyz.bin") + "' --q '" +
                              uvr::test::data_path("vtk-data/bluntfinq.bin") + "'";

nlohmann::json budget(const std::string& args, const std::string& dir)
{
    const CommandResult r = run_uvr("budget " + args + " --report '" + dir + "' --json");
    INFO("uvr budget " << args << "\n" << r.err);
    REQUIRE(r.exit_code == 0);
    return nlohmann::json::parse(r.out);
}

// The switches of a run that its factor does not own must be the baseline's.
void require_only(const nlohmann::json& run, const nlohmann::json& baseline, std::initializer_list<const char*> own)
{
    for (const auto& [key, value] : baseline["switches"].items()) {
        bool owned = key == "backend";  // a run GL can draw may use it when asked
        for (const char* o : own) owned = owned || key == o;
        INFO(key << ": " << run["switches"][key].dump() << " against the baseline's " << value.dump());
        if (!owned) CHECK(run["switches"][key] == value);
    }
}

// Every measure of `run` recomputed from its kept image and the image it is measured against (the reference's, or,
// for the ray caster's factors other than the step, the step run's: docs/spec.md §7).
void require_measures_of_images(const std::string& dir, const nlohmann::json& run)
{
    const bool against_step = run.value("against", "reference") == "step";
    const uvr::Image ref = uvr::read_npy(dir + (against_step ? "/runs/baseline.npy" : "/runs/reference.npy"));
    const uvr::Image im = uvr::read_npy(dir + "/" + run["image"].get<std::string>());
    const uvr::ErrorMeasures e = uvr::measure_errors(im, ref);
    INFO(run["image"].get<std::string>());
    CHECK(run["rmse"].get<double>() == e.rmse);
    CHECK(run["max_abs"].get<double>() == e.max_abs);
    CHECK(run["visible_fraction"].get<double>() == e.visible_fraction);
    CHECK(run["covered_left_empty"].get<double>() == e.covered_left_empty);
    if (std::isfinite(e.psnr)) CHECK(run["psnr"].get<double>() == e.psnr);
    if (!run.contains("without_wrong_exits")) return;
    // The measures away from the wrong exits, from the kept mask.
    const nlohmann::json& w = run["without_wrong_exits"];
    const uvr::Image mask = uvr::read_npy(dir + "/" + w["mask"].get<std::string>());
    double sum = 0.0, largest = 0.0;
    std::size_t pixels = 0;
    for (std::size_t p = 0; p < std::size_t(im.width) * std::size_t(im.height); ++p) {
        if (mask.rgba[4 * p] != 0.0f) continue;
        ++pixels;
        for (std::size_t c = 0; c < 4; ++c) {
            const double d = double(im.rgba[4 * p + c]) - double(ref.rgba[4 * p + c]);
            sum += d * d;
            largest = std::max(largest, std::abs(d));
        }
    }
    CHECK(w["pixels"].get<std::size_t>() == pixels);
    CHECK(w["max_abs"].get<double>() == largest);
    CHECK(w["rmse"].get<double>() == std::sqrt(sum / (4.0 * double(pixels))));
}

}  // namespace

TEST_CASE("uvr budget's baseline equals the reference to float32 precision, for HAVS and VICP")
{
    TempDir tmp("budget-baseline");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    for (const char* algo : {"havs", "vicp"})
        for (const auto& [name, scene] :
             uvr::test::views({std::pair<std::string, std::string>{"torus", "builtin:torus --size 96x96"},
                               {"blunt-fin-front", kBluntFin + " --size 128x96"},
                               {"blunt-fin-above", kBluntFin + " --size 128x96 --view -40,70"}})) {
            const nlohmann::json b = budget(scene + " --algo " + algo, tmp.file(std::string(algo) + "-" + name));
            INFO(algo << ", " << name << ": baseline RMSE " << b["baseline"]["rmse"] << ", max "
                      << b["baseline"]["max_abs"]);
            CHECK(b["algo"] == algo);
            CHECK(b["baseline_ok"] == true);
            CHECK(b["baseline"]["max_abs"].get<double>() <= kBaselineMax);
        }
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("each factor run of uvr budget differs from the baseline by its own switch only, and every number is the "
          "kept images' measure")
{
    TempDir tmp("budget-factors");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    for (const char* algo : {"havs", "vicp"}) {
        const std::string dir = tmp.file(algo);
        const nlohmann::json b = budget("builtin:torus-small --size 64x64 --view 30,20 --algo " + std::string(algo), dir);
        const nlohmann::json& base = b["baseline"]["switches"];
        // The baseline: every switch exact.
        CHECK(base["segment"] == "exact");
        CHECK(base["interpolation"] == "exact");
        CHECK(base["coverage"] == "exact");
        CHECK(base["threshold"] == 1.0);
        // HAVS's baseline holds every fragment of every pixel (--k all) and orders a seam's faces by the cell the ray
        // leaves first (--ties facing); the sort factor sets both back.
        if (std::string(algo) == "havs") {
            CHECK(base["k"] == "all");
            CHECK(base["ties"] == "facing");
            CHECK(b["factors"]["sort"]["switches"]["ties"] == "arrival");
            CHECK(b["baseline"]["stats"]["max_held"] == b["baseline"]["stats"]["max_fragments_per_pixel"]);
        }
        const char* sort_switch = std::string(algo) == "havs" ? "k" : "order";
        REQUIRE(b["factor_order"] ==
                nlohmann::json::array({"sort", "table", "interpolation", "coverage", "termination"}));
        const nlohmann::json& f = b["factors"];
        if (std::string(algo) == "havs")
            require_only(f["sort"], b["baseline"], {sort_switch, "ties"});
        else
            require_only(f["sort"], b["baseline"], {sort_switch});
        require_only(f["table"], b["baseline"], {"segment", "table_size", "table_format"});
        CHECK(f["table"]["switches"]["segment"] == "table");
        // VICP's published program has varyings only on the rasterizer's fragments: its interpolation run takes its
        // coverage too.
        if (std::string(algo) == "vicp") {
            require_only(f["interpolation"], b["baseline"], {"interpolation", "coverage"});
            CHECK(f["interpolation"]["with"] == nlohmann::json::array({"coverage"}));
        } else {
            require_only(f["interpolation"], b["baseline"], {"interpolation"});
        }
        CHECK(f["interpolation"]["switches"]["interpolation"] == "gpu");
        require_only(f["coverage"], b["baseline"], {"coverage"});
        CHECK(f["coverage"]["switches"]["coverage"] == "gpu");
        require_only(f["termination"], b["baseline"], {"threshold"});
        CHECK(f["termination"]["switches"]["threshold"] == (std::string(algo) == "havs" ? 0.99 : 1.0));
        // The total: the defaults.
        CHECK(b["total"]["switches"]["segment"] == "table");
        CHECK(b["total"]["switches"]["interpolation"] == "gpu");
        CHECK(b["total"]["switches"]["coverage"] == "gpu");
        require_measures_of_images(dir, b["baseline"]);
        require_measures_of_images(dir, b["total"]);
        for (const auto& [name, run] : f.items()) require_measures_of_images(dir, run);
    }
    SECTION("--backend gl: the runs GL can draw use it, with the emulation's numbers")
    {
        const nlohmann::json emu = budget("builtin:torus-small --size 64x64 --view 30,20 --algo vicp", tmp.file("e"));
        const nlohmann::json gl =
            budget("builtin:torus-small --size 64x64 --view 30,20 --algo vicp --backend gl", tmp.file("g"));
        CHECK(gl["total"]["switches"]["backend"] == "gl");
        CHECK(gl["baseline"]["switches"]["backend"] == "emu");  // exact segments and coverage: the emulation's only
        CHECK(gl["total"]["rmse"] == emu["total"]["rmse"]);
        CHECK(uvr::test::file_contents(tmp.file("g/runs/total.npy")) ==
              uvr::test::file_contents(tmp.file("e/runs/total.npy")));
    }
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("the ray caster's budget: the step against the reference, each other factor against the step run")
{
    // docs/spec.md §7: the baseline is the step run, every other switch exact at the user's step; the other factors set
    // one switch back at that step and are measured against it; the total against the reference.
    TempDir tmp("budget-raycast");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    for (const char* volume : {"vtk-data/neghip.slc", "vtk-data/hydrogen.vti"}) {
        const std::string dir = tmp.file(std::filesystem::path(volume).stem().string());
        const nlohmann::json b =
            budget("'" + uvr::test::data_path(volume) + "' --size 64x64 --algo raycast --step 0.5", dir);
        INFO(volume << ": step RMSE " << b["factors"]["step"]["rmse"]);
        CHECK(b["baseline_ok"] == true);
        CHECK(b["step_convergence"].get<std::string>().find("--refine step") != std::string::npos);
        const nlohmann::json& base = b["baseline"]["switches"];
        CHECK(base["step"] == 0.5);
        CHECK(base["segment"] == "exact");
        CHECK(base["preintegrate"] == true);
        CHECK(base["volume_format"] == "f32");
        CHECK_FALSE(base.contains("coverage"));
        CHECK(b["not_split"].contains("coverage"));
        REQUIRE(b["factor_order"] == nlohmann::json::array({"step", "table", "texture", "interpolation", "termination"}));
        const nlohmann::json& f = b["factors"];
        // The step factor is the baseline's run, copied, against the reference; the march's error is not zero.
        CHECK(f["step"]["same_as"] == "baseline");
        CHECK(f["step"]["against"] == "reference");
        CHECK(f["step"]["rmse"] == b["baseline"]["rmse"]);
        CHECK(f["step"]["rmse"].get<double>() > 0.0);
        require_only(f["table"], b["baseline"], {"segment", "table_size", "table_format", "preintegrate"});
        CHECK(f["table"]["switches"]["preintegrate"] == false);
        require_only(f["texture"], b["baseline"], {"volume_format"});
        require_only(f["interpolation"], b["baseline"], {"interpolation"});
        require_only(f["termination"], b["baseline"], {"threshold"});
        CHECK(f["termination"]["switches"]["threshold"] == 0.95);
        for (const char* name : {"table", "texture", "interpolation", "termination"}) CHECK(f[name]["against"] == "step");
        CHECK(b["total"]["against"] == "reference");
        // Post-classification at the user's step is its own cause, measured against the march at that step.
        CHECK(f["table"]["rmse"].get<double>() > 0.0);
        for (const auto& [name, run] : f.items()) require_measures_of_images(dir, run);
        require_measures_of_images(dir, b["total"]);
        // No ray of either step run reaches 0.95: the termination run is the baseline's, not rendered again, is what
        // the run itself renders, bit for bit, and so adds nothing against the step run.
        CHECK(f["termination"]["same_as"] == "baseline");
        CHECK(f["termination"]["rmse"] == 0.0);
        const std::string own = tmp.file("termination.npy");
        const CommandResult r = run_uvr("render '" + uvr::test::data_path(volume) +
                                        "' --size 64x64 --algo raycast --step 0.5 --preintegrate --segment exact "
                                        "--volume-format f32 --interpolation exact --threshold 0.95 --out '" +
                                        own + "'");
        REQUIRE(r.exit_code == 0);
        CHECK(uvr::read_npy(own).rgba == uvr::read_npy(dir + "/runs/termination.npy").rgba);
    }
    // A threshold some rays pass: the termination run is rendered, and differs from the step run.
    const std::string dir = tmp.file("stopping");
    const nlohmann::json b = budget(
        "'" + uvr::test::data_path("vtk-data/neghip.slc") + "' --size 64x64 --algo raycast --step 0.5 --threshold 0.5",
        dir);
    CHECK_FALSE(b["factors"]["termination"].contains("same_as"));
    CHECK(b["factors"]["termination"]["rmse"].get<double>() > 0.0);
    require_measures_of_images(dir, b["factors"]["termination"]);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr budget gives the known answers: VICP's interpolation at float rounding where the distances are linear, "
          "HAVS's sort at 0 where no pixel holds more fragments than k")
{
    TempDir tmp("budget-known");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    SECTION("VICP on a convex mesh: orthographic, and a wide-angle close-up")
    {
        // hexa.vtk: a convex grid of 63,888 tetrahedra in [0, 0.957]^3.
        const std::string hexa = "'" + uvr::test::data_path("vtk-data/hexa.vtk") + "' --size 96x96 --algo vicp";
        std::ofstream(tmp.file("ortho.json")) << R"({"eye": [2.1, 1.6, 2.6], "target": [0.478, 0.478, 0.478],
            "projection": "orthographic", "ortho_height": 1.8})";
        std::ofstream(tmp.file("close.json")) << R"({"eye": [1.25, 1.1, 1.35], "target": [0.478, 0.478, 0.478],
            "fovy_deg": 100})";
        const nlohmann::json ortho = budget(hexa + " --camera '" + tmp.file("ortho.json") + "'", tmp.file("ortho"));
        const nlohmann::json close = budget(hexa + " --camera '" + tmp.file("close.json") + "'", tmp.file("close"));
        const nlohmann::json& o = ortho["factors"]["interpolation"]["without_wrong_exits"];
        const nlohmann::json& c = close["factors"]["interpolation"]["without_wrong_exits"];
        INFO("interpolation factor away from the wrong exits: orthographic RMSE " << o["rmse"] << " over " << o["pixels"]
                                                                                  << " pixels, close-up " << c["rmse"]
                                                                                  << " over " << c["pixels"]);
        CHECK(o["rmse"].get<double>() <= kLinearInterpolationRmse);
        CHECK(c["rmse"].get<double>() > 100.0 * kLinearInterpolationRmse);
        require_measures_of_images(tmp.file("ortho"), ortho["factors"]["interpolation"]);
    }
    SECTION("HAVS on one tetrahedron with k = 2")
    {
        std::ofstream(tmp.file("tet.vtk")) << "# vtk DataFile Version 2.0\none tetrahedron\nASCII\n"
                                              "DATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                              "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n"
                                              "POINT_DATA 4\nSCALARS s double 1\nLOOKUP_TABLE default\n0 1 2 3\n";
        const nlohmann::json b = budget("'" + tmp.file("tet.vtk") + "' --size 64x64 --view 20,30 --algo havs --k 2",
                                        tmp.file("tet"));
        INFO("sort factor RMSE " << b["factors"]["sort"]["rmse"] << ", baseline " << b["baseline"]["rmse"]);
        CHECK(b["factors"]["sort"]["switches"]["k"] == 2);
        CHECK(b["factors"]["sort"]["stats"]["max_fragments_per_pixel"].get<int>() <= 2);
        CHECK(uvr::test::file_contents(tmp.file("tet/runs/sort.npy")) ==
              uvr::test::file_contents(tmp.file("tet/runs/baseline.npy")));
    }
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("HAVS's baseline holds every fragment where a pixel has more than 255")
{
    // The Oxygen Post from (120, 30) puts 313 fragments on a pixel (docs/budget.md). Its HAVS baseline still differs
    // from the reference by 8.6e-5 (not understood, docs/budget.md), so the command exits 1 there; the report is
    // written either way, and its counts are what this test reads.
    TempDir tmp("budget-k");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string post = "'" + uvr::test::data_path("vtk-data/postxyz.bin") + "' --q '" +
                             uvr::test::data_path("vtk-data/postq.bin") + "' --field StagnationEnergy";
    const CommandResult r =
        run_uvr("budget " + post + " --size 96x96 --view 120,30 --algo havs --report '" + tmp.file("post") + "'");
    INFO(r.err);
    const nlohmann::json b = nlohmann::json::parse(uvr::test::file_contents(tmp.file("post/budget.json")));
    const int most = b["baseline"]["stats"]["max_fragments_per_pixel"].get<int>();
    INFO("most fragments on a pixel " << most);
    CHECK(b["baseline"]["switches"]["k"] == "all");
    CHECK(most > 255);
    CHECK(b["baseline"]["stats"]["max_held"].get<int>() == most);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr sweep --budget gives HAVS's budget at every k, as uvr budget gives it at that k")
{
    TempDir tmp("budget-sweep");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string scene = "builtin:torus-small --size 64x64 --view 30,20";
    const CommandResult r = run_uvr("sweep " + scene + " --k 1,2,8 --budget --report '" + tmp.file("sweep") + "' --json");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json w = nlohmann::json::parse(r.out);
    REQUIRE(w["budget_rows"].size() == 3);
    CHECK(std::filesystem::exists(tmp.file("sweep/budget_vs_k.png")));
    const nlohmann::json& first = w["budget_rows"][0];
    for (const auto& row : w["budget_rows"]) {
        const int k = row["k"].get<int>();
        INFO("k = " << k << ": " << row.dump());
        CHECK(std::filesystem::exists(tmp.file("sweep/" + row["page"].get<std::string>())));
        // The causes that do not depend on k are the same runs at every k.
        for (const char* f : {"table", "interpolation", "coverage", "termination"}) CHECK(row["factors"][f] == first["factors"][f]);
        CHECK(row["baseline"] == first["baseline"]);
        // Each k's budget is the one uvr budget gives at that k, image for image.
        const std::string alone = tmp.file("alone-k" + std::to_string(k));
        const nlohmann::json b = budget(scene + " --algo havs --k " + std::to_string(k), alone);
        CHECK(b["factors"]["sort"]["rmse"] == row["factors"]["sort"]);
        CHECK(b["total"]["rmse"] == row["total"]);
        const std::string in_sweep = tmp.file("sweep/budget/v0-k" + std::to_string(k) + "/runs/");
        for (const char* run : {"sort", "total", "table"})
            CHECK(uvr::test::file_contents(in_sweep + run + ".npy") ==
                  uvr::test::file_contents(alone + "/runs/" + run + ".npy"));
    }
    // The sort factor falls as k grows (the k-buffer holds more of the fragments out of order).
    CHECK(w["budget_rows"][2]["factors"]["sort"].get<double>() < w["budget_rows"][0]["factors"]["sort"].get<double>());
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("an interrupted uvr sweep --budget goes on from the budgets it finished, and redoes one whose options differ")
{
    TempDir tmp("budget-resume");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string sweep = "sweep builtin:torus-small --size 48x48 --view 30,20 --k 1,2 --budget --json --report '" +
                              tmp.file("sweep") + "'";
    const auto rows = [&](const std::string& extra) {
        const CommandResult r = run_uvr(sweep + extra);
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        return nlohmann::json::parse(r.out)["budget_rows"];
    };
    const nlohmann::json first = rows("");
    const std::string k1 = tmp.file("sweep/budget/v0-k1/runs/total.npy");
    const auto k1_written = std::filesystem::last_write_time(k1);
    // The k = 2 budget interrupted before its budget.json was written; k = 1's finished.
    std::filesystem::remove(tmp.file("sweep/budget/v0-k2/budget.json"));
    const nlohmann::json again = rows("");
    CHECK(again == first);
    CHECK(std::filesystem::last_write_time(k1) == k1_written);  // taken from disk, not rendered again
    CHECK(std::filesystem::exists(tmp.file("sweep/budget/v0-k2/budget.json")));
    // Other options: no finished budget matches, every one is rendered again.
    const nlohmann::json other = rows(" --table-size 32");
    CHECK(std::filesystem::last_write_time(k1) != k1_written);
    CHECK(other[0]["total"] != first[0]["total"]);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr sweep --step --budget gives the ray caster's budget at every step")
{
    TempDir tmp("budget-sweep-step");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string volume = "'" + uvr::test::data_path("vtk-data/hydrogen.vti") + "' --size 48x48";
    const CommandResult r = run_uvr("sweep " + volume + " --step 1,0.5 --budget --report '" + tmp.file("sweep") + "' --json");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json w = nlohmann::json::parse(r.out);
    REQUIRE(w["budget_rows"].size() == 2);
    for (const auto& row : w["budget_rows"]) {
        INFO(row.dump());
        CHECK(row["baseline_ok"] == true);
        CHECK(std::filesystem::exists(tmp.file("sweep/" + row["page"].get<std::string>())));
        const nlohmann::json b = budget(volume + " --algo raycast --step " + std::to_string(row["step"].get<double>()),
                                        tmp.file("alone"));
        CHECK(b["factors"]["step"]["rmse"] == row["factors"]["step"]);
        CHECK(b["total"]["rmse"] == row["total"]);
    }
    // Steps sorted from the longest: the step factor falls as the step shrinks.
    CHECK(w["budget_rows"][1]["factors"]["step"].get<double>() < w["budget_rows"][0]["factors"]["step"].get<double>());
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr budget refuses what it cannot split, before writing anything")
{
    TempDir tmp("budget-refusals");
    for (const auto& [args, phrase] :
         {std::pair<std::string, std::string>{"builtin:torus-small --algo raycast", "renders regular grids"},
          {"builtin:torus-small --algo reference", "--algo must be havs, vicp or raycast"},
          {"builtin:torus-small --algo vicp --order painter", "--order must be centroid or mpvonc"}}) {
        const CommandResult r = run_uvr("budget " + args + " --size 16x16 --report '" + tmp.file("never") + "'");
        INFO(args << ": " << r.err);
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains(phrase));
        CHECK_FALSE(std::filesystem::exists(tmp.file("never")));
    }
}
