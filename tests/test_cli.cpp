// The `uvr` program as a user meets it: help, `info --json` on the real data, errors and exit codes.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "reference/image.h"

#include "image_errors.h"
#include "test_support.h"

using uvr::test::CommandResult;
using uvr::test::data_path;
using uvr::test::run_uvr;
using uvr::test::file_contents;
using uvr::test::TempDir;

namespace {

nlohmann::json info_json(const std::string& args)
{
    const CommandResult r = run_uvr("info " + args + " --json");
    INFO("uvr info " << args << "\nstderr: " << r.err);
    REQUIRE(r.exit_code == 0);
    return nlohmann::json::parse(r.out);
}

std::string quoted(const std::string& p) { return "'" + p + "'"; }

}  // namespace

TEST_CASE("uvr --help and every sub-command's --help succeed")
{
    const CommandResult top = run_uvr("--help");
    CHECK(top.exit_code == 0);
    for (const char* cmd : {"info", "render", "compare", "sweep", "bench", "demo"}) {
        INFO(cmd);
        CHECK_THAT(top.out, Catch::Contains(cmd));
        CHECK(run_uvr(std::string(cmd) + " --help").exit_code == 0);
    }
}

TEST_CASE("uvr info --json reports the counts SOURCES.md gives")
{
    SECTION("post.vtk")
    {
        const auto j = info_json(quoted(data_path("vtk-data/post.vtk")));
        CHECK(j["points"] == 2288);
        CHECK(j["tetrahedra"] == 8750);
        CHECK(j["fields"][0]["name"] == "Pressure");
        CHECK(j["faces"]["unique"] == j["faces"]["boundary"].get<int>() + j["faces"]["internal"].get<int>());
    }
    SECTION("tetraMesh.vtk") { CHECK(info_json(quoted(data_path("vtk-data/tetraMesh.vtk")))["tetrahedra"] == 160); }
    SECTION("Tetrahedron.vtu") { CHECK(info_json(quoted(data_path("vtk-data/Tetrahedron.vtu")))["tetrahedra"] == 96); }
    SECTION("Blunt Fin")
    {
        const auto j = info_json(quoted(data_path("vtk-data/bluntfinxyz.bin")) + " --q " +
                                 quoted(data_path("vtk-data/bluntfinq.bin")));
        CHECK(j["points"] == 40960);
        CHECK(j["tetrahedra"] == 187395);
        CHECK(j["fields"].size() == 5);
    }
    SECTION("Oxygen Post")
    {
        const auto j = info_json(quoted(data_path("vtk-data/postxyz.bin")) + " --q " +
                                 quoted(data_path("vtk-data/postq.bin")));
        CHECK(j["tetrahedra"] == 513375);
    }
    SECTION("a volume")
    {
        const auto j = info_json(quoted(data_path("vtk-data/ironProt.vtk")));
        CHECK(j["kind"] == "regular grid");
        CHECK(j["dims"] == nlohmann::json({68, 68, 68}));
    }
    SECTION("the built-in torus is not convex")
    {
        const auto j = info_json("builtin:torus-small");
        CHECK(j["convex"] == false);
        CHECK(j["fields"][0]["name"] == "wave");
    }
}

TEST_CASE("bad input makes uvr exit non-zero with a message naming the file, never crash")
{
    SECTION("missing file")
    {
        const CommandResult r = run_uvr("info /nonexistent/mesh.vtk");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("/nonexistent/mesh.vtk") && Catch::Contains("cannot open"));
        CHECK(r.out.empty());
    }
    SECTION("unknown field")
    {
        const CommandResult r = run_uvr("info " + quoted(data_path("vtk-data/post.vtk")) + " --field nope");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("post.vtk") && Catch::Contains("no field 'nope'"));
    }
    SECTION("unknown format")
    {
        const CommandResult r = run_uvr("info " + quoted(data_path("SOURCES.md")));
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("unknown file format"));
    }
    SECTION("usage error")
    {
        const CommandResult r = run_uvr("info");
        CHECK(r.exit_code == 2);
    }
    SECTION("a built-in mesh that does not exist, or a size out of range")
    {
        for (const char* path : {"builtin:cube", "builtin:torus-50", "builtin:torus-9x", "builtin:torus-"}) {
            const CommandResult r = run_uvr(std::string("info ") + path);
            INFO(path << ": " << r.err);
            CHECK(r.exit_code == 1);
            CHECK_THAT(r.err, Catch::Contains(path) && Catch::Contains("builtin:torus-N"));
        }
    }
    SECTION("uvr gpu-check with a --gpu it does not know: refused before its directory is made")
    {
        uvr::test::TempDir tmp("gpu-check");
        const CommandResult r = run_uvr("gpu-check builtin:torus-small --gpu nvidia --out '" + tmp.file("check") + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("--gpu must be auto or llvmpipe, not 'nvidia'"));
        CHECK_FALSE(std::filesystem::exists(tmp.file("check")));
    }
    SECTION("--camera and --view together")
    {
        uvr::test::TempDir tmp("camview");
        const std::string cam = tmp.write("cam.json", R"({"eye": [0,0,5], "target": [0,0,0]})");
        const CommandResult r =
            run_uvr("render builtin:torus-small --camera '" + cam + "' --view 10,10 --out '" + tmp.file("a.npy") + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("either --camera or --view"));
        CHECK_FALSE(std::filesystem::exists(tmp.file("a.npy")));
    }
    SECTION("an output that cannot be written leaves nothing behind")
    {
        uvr::test::TempDir tmp("unwritable");
        const CommandResult r = run_uvr("render builtin:torus-small --size 8x8 --no-cache --out '" +
                                        tmp.file("no/such/dir/a.npy") + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("no/such/dir/a.npy") && Catch::Contains("cannot write"));
        CHECK(std::filesystem::is_empty(tmp.file("")));
    }
    SECTION("the ray caster refuses a tetrahedral mesh, naming it")
    {
        const CommandResult r = run_uvr("render builtin:torus-small --algo raycast --out /tmp/uvr-never-written.npy");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("is a tetrahedral mesh"));
        CHECK(!std::filesystem::exists("/tmp/uvr-never-written.npy"));
    }
}

TEST_CASE("uvr render --algo reference writes the image and reuses the cache")
{
    uvr::test::TempDir tmp("render");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string out = tmp.file("ref.npy");
    const CommandResult first = run_uvr("render builtin:torus-small --algo reference --size 40x30 --json --out '" + out + "'");
    INFO(first.err);
    REQUIRE(first.exit_code == 0);
    const auto j = nlohmann::json::parse(first.out);
    CHECK(j["cached"] == false);
    CHECK(j["rays"] == 40 * 30);
    const uvr::Image img = uvr::read_npy(out);
    CHECK(img.width == 40);
    CHECK(img.height == 30);
    float alpha_max = 0.0f;
    for (std::size_t k = 3; k < img.rgba.size(); k += 4) alpha_max = std::max(alpha_max, img.rgba[k]);
    CHECK(alpha_max > 0.1f);  // the torus is in the picture
    const CommandResult second = run_uvr("render builtin:torus-small --size 40x30 --json --out '" + out + "'");
    CHECK(nlohmann::json::parse(second.out)["cached"] == true);
    CHECK(uvr::read_npy(out).rgba == img.rgba);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("the reference of a regular grid is cached under a key of its samples")
{
    TempDir tmp("render-volume-cache");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const auto write_volume = [&](unsigned char centre) {
        std::string raw;
        for (int k = 0; k < 6; ++k)
            for (int j = 0; j < 6; ++j)
                for (int i = 0; i < 6; ++i) raw += char(i == 3 && j == 3 && k == 3 ? centre : 10 * (i + j + k));
        tmp.write("v.raw", raw);
        return tmp.write("v.mhd",
                         "NDims = 3\nDimSize = 6 6 6\nElementSpacing = 1 1 1\nElementType = MET_UCHAR\n"
                         "ElementDataFile = v.raw\n");
    };
    const std::string mhd = write_volume(250);
    const auto render = [&](const std::string& out) {
        const CommandResult r =
            run_uvr("render '" + mhd + "' --algo reference --size 24x20 --json --out '" + tmp.file(out) + "'");
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        return nlohmann::json::parse(r.out);
    };
    CHECK(render("a.npy")["cached"] == false);
    CHECK(render("b.npy")["cached"] == true);
    CHECK(uvr::read_npy(tmp.file("b.npy")).rgba == uvr::read_npy(tmp.file("a.npy")).rgba);
    write_volume(0);  // one sample changed: another key, another picture
    CHECK(render("c.npy")["cached"] == false);
    CHECK(uvr::read_npy(tmp.file("c.npy")).rgba != uvr::read_npy(tmp.file("a.npy")).rgba);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr bench times HAVS without counting fragments and prints no fragment rate for it")
{
    // A timed frame runs without per-pixel diagnostics (so the emulation and GL do the same work): no fragment count,
    // so no rate, rather than a rate of 0.
    const std::string args = "bench builtin:torus-small --size 48x40 --algos havs --backend emu,gl --repeat 1 --warmup 0";
    const CommandResult j = run_uvr(args + " --json");
    INFO(j.err);
    REQUIRE(j.exit_code == 0);
    const auto rows = nlohmann::json::parse(j.out)["results"];
    REQUIRE(rows.size() == 2);
    for (const auto& row : rows) {
        INFO(row.dump());
        CHECK(row["diagnostics"] == false);
        CHECK_FALSE(row.contains("fragments_per_s"));
        CHECK(row["frame_ms"].get<double>() > 0.0);
    }
    const CommandResult t = run_uvr(args);
    INFO(t.out << t.err);
    REQUIRE(t.exit_code == 0);
    CHECK(t.out.find("raster+fragment") != std::string::npos);
    CHECK(t.out.find("Mfragments/s") == std::string::npos);
}

TEST_CASE("uvr render with the camera inside the mesh: HAVS and VICP render it on both backends with the same bits")
{
    // VTK's post.vtk seen from a point inside its flow region (docs/havs.md "Views that cut the mesh").
    uvr::test::TempDir tmp("inside");
    const std::string mesh = quoted(data_path("vtk-data/post.vtk"));
    const std::string cam = tmp.write(
        "cam.json", R"({"eye": [0.0, 1.5, 0.5], "target": [1.0, 2.5, 0.6], "up": [0, 0, 1], "fovy_deg": 80})");
    for (const char* algo : {"havs", "vicp"}) {
        std::vector<uvr::Image> images;
        for (const char* backend : {"emu", "gl"}) {
            INFO(algo << " " << backend);
            const std::string out = tmp.file(std::string(algo) + backend + ".npy");
            const CommandResult r = run_uvr("render " + mesh + " --algo " + algo + " --backend " + backend +
                                            " --camera '" + cam + "' --size 48x40 --json --out '" + out + "'");
            INFO(r.err);
            REQUIRE(r.exit_code == 0);
            const auto j = nlohmann::json::parse(r.out);
            CHECK(j["clip"]["near_sections"].get<int>() >= 1);
            CHECK(j["clip"][std::string(algo) == "havs" ? "clipped_faces" : "clipped_cells"].get<int>() > 0);
            CHECK(j["clip"]["gpu_clipped"] == 0);
            images.push_back(uvr::read_npy(out));
            float alpha_max = 0.0f;
            for (std::size_t k = 3; k < images.back().rgba.size(); k += 4)
                alpha_max = std::max(alpha_max, images.back().rgba[k]);
            CHECK(alpha_max > 0.1f);
        }
        CHECK(images[0].rgba == images[1].rgba);
    }
}

TEST_CASE("uvr demo shows the whole lab, each GL image with its emulated twin's bits")
{
    // At 192 x 192 rather than the default 512 x 512 (96 x 96 under the sanitizers): every step and page runs the same
    // code at any size, in a third of the time (docs/robustness.md, "What the suite costs").
    uvr::test::TempDir tmp("demo");
    const std::string size = uvr::test::sanitized() ? "96x96" : "192x192";
    const CommandResult r = run_uvr("demo --size " + size + " --out '" + tmp.file("d") + "'");
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(std::filesystem::exists(tmp.file("d/index.html")));
    for (const char* part : {"compare", "compare-gl", "compare-paper-entries", "compare-arb", "raycast", "raycast-gl",
                             "sweep", "budget-havs", "budget-vicp"})
        CHECK(std::filesystem::exists(tmp.file(std::string("d/") + part + "/index.html")));
    CHECK(std::filesystem::exists(tmp.file("d/compare/havs-emu-k6-error.png")));
    CHECK(std::filesystem::exists(tmp.file("d/sweep/sweep.csv")));
    CHECK(nlohmann::json::parse(uvr::test::file_contents(tmp.file("d/compare/metrics.json")))["results"].size() == 3);
    // One progress line a step, and the bit-for-bit marks of every GL and ARB image.
    CHECK_THAT(r.out, Catch::Contains("uvr demo [8/8] the landing page"));
    for (const char* mark : {"havs-gl-k6 ", "vicp-gl-mpvonc ", "havs-arb-k6 ", "raycast-gl-post "}) {
        const std::size_t at = r.out.find(mark);
        REQUIRE(at != std::string::npos);
        CHECK(r.out.substr(at, r.out.find('\n', at) - at).find("same bits as") != std::string::npos);
    }
    CHECK_THAT(r.out, !Catch::Contains("join as they land"));
    // The landing page shows, not only links: images at 256 px, the error-against-k plot and the budget charts
    // inline (python3-matplotlib is one of the packages scripts/install-deps.sh installs).
    const std::string index = uvr::test::file_contents(tmp.file("d/index.html"));
    CHECK_THAT(index, Catch::Contains("same bits") && Catch::Contains("img{width:256px;"));
    for (const char* plot : {"sweep/error_vs_k.png", "budget-havs/budget.svg", "budget-vicp/budget.svg"}) {
        CHECK_THAT(index, Catch::Contains(std::string("src=\"") + plot + "\""));
        CHECK(std::filesystem::exists(tmp.file(std::string("d/") + plot)));
    }
    // The error maps' colour bar places each tick itself (inline style), so that its labels do not run together on a
    // page whose style sheet has no rule for them, as the budget page's has none.
    const std::string budget = uvr::test::file_contents(tmp.file("d/budget-havs/index.html"));
    CHECK_THAT(budget,
               Catch::Contains("<span style=\"position: absolute; left: 0.00%; transform: translateX(-50%)\">1e-"));
    CHECK_THAT(budget, !Catch::Contains("(<div class=\"legend\""));  // not inside a paragraph's text
}

TEST_CASE("an interrupted sweep resumed from disk gives the same numbers as one uninterrupted")
{
    uvr::test::TempDir tmp("sweep");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const std::string args = "sweep builtin:torus-small --k 1,3,8 --views 2 --size 48x48 --json --report ";
    const CommandResult whole = run_uvr(args + "'" + tmp.file("a") + "'");
    INFO(whole.err);
    REQUIRE(whole.exit_code == 0);
    // Interrupt: a second sweep whose run files are partly gone (one removed, one truncated as a kill would leave a
    // temporary file, never a half-written run file).
    const CommandResult first = run_uvr(args + "'" + tmp.file("b") + "'");
    REQUIRE(first.exit_code == 0);
    std::filesystem::remove(tmp.file("b/runs/v1-k3-table.json"));
    std::filesystem::remove(tmp.file("b/runs/v0-k1-exact.json"));
    const CommandResult resumed = run_uvr(args + "'" + tmp.file("b") + "'");
    REQUIRE(resumed.exit_code == 0);
    auto a = nlohmann::json::parse(whole.out), b = nlohmann::json::parse(resumed.out);
    CHECK(b["resumed_runs"] == 10);
    for (auto* j : {&a, &b}) {
        (*j).erase("resumed_runs");
        for (auto& r : (*j)["rows"]) r.erase("ms");
    }
    CHECK(a == b);
    // The CSV holds the JSON's numbers.
    const std::string csv = uvr::test::file_contents(tmp.file("b/sweep.csv"));
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 2 * 3 * 2);
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr render --algo vicp renders the reference's image with exact segments and refuses what it lacks")
{
    TempDir tmp("cli-vicp");
    const std::string scene = "render builtin:torus-small --size 64x48 --view 30,20 --no-cache ";
    SECTION("exact segments and MPVONC: the reference's image, and the order's figures in the JSON")
    {
        const CommandResult ref = run_uvr(scene + "--algo reference --out '" + tmp.file("ref.npy") + "'");
        const CommandResult vicp = run_uvr(scene + "--algo vicp --segment exact --interpolation exact --order mpvonc --json --diagnostics '" +
                                           tmp.file("diag") + "' --out '" + tmp.file("vicp.npy") + "'");
        INFO(ref.err << vicp.err);
        REQUIRE(ref.exit_code == 0);
        REQUIRE(vicp.exit_code == 0);
        const uvr::test::ImageErrors e =
            uvr::test::image_errors(uvr::read_npy(tmp.file("vicp.npy")), uvr::read_npy(tmp.file("ref.npy")));
        INFO("RMSE " << e.rmse << ", max " << e.max_abs);
        CHECK(e.rmse <= 1e-5);  // the bar (tests/test_vicp.cpp)
        const auto j = nlohmann::json::parse(vicp.out);
        CHECK(j["algo"] == "vicp");
        CHECK(j["ordering_errors"] == 0);
        CHECK(j["cycle_breaks"] == 0);
        CHECK(j["bytes_sent_per_tet"].get<double>() > 20.0);
        CHECK(std::filesystem::exists(tmp.file("diag/ordering_errors.npy")));
    }
    SECTION("--backend gl: the emulation's image, bit for bit, and its diagnostics")
    {
        for (const char* order : {"mpvonc", "centroid"}) {
            const std::string args = scene + "--algo vicp --order " + order + " --diagnostics '" + tmp.file(order);
            const CommandResult emu = run_uvr(args + "-emu' --out '" + tmp.file("emu.npy") + "'");
            const CommandResult gl = run_uvr(args + "-gl' --backend gl --gl osmesa --json --out '" +
                                             tmp.file("gl.npy") + "'");
            INFO(order << ": " << emu.err << gl.err);
            REQUIRE(emu.exit_code == 0);
            REQUIRE(gl.exit_code == 0);
            CHECK(file_contents(tmp.file("gl.npy")) == file_contents(tmp.file("emu.npy")));
            for (const char* d : {"fragments.npy", "ordering_errors.npy"})
                CHECK(file_contents(tmp.file(order) + "-gl/" + d) == file_contents(tmp.file(order) + "-emu/" + d));
            const auto j = nlohmann::json::parse(gl.out);
            CHECK_THAT(j["gl"].get<std::string>(), Catch::Contains("llvmpipe"));
            // The published pipeline by default: ProjectTet's 132 bytes a face, for the faces that make fragments
            // (--send covered; the published 528 a cell with --send all); the wrong-exit diagnostic is the emulation's
            // alone (null on GL).
            CHECK(j["interpolation"] == "gpu");
            CHECK(j["send"] == "covered");
            CHECK(j["sent_faces"].get<double>() > 0.0);
            CHECK(j["sent_faces"].get<double>() < 2.0 * j["drawn_cells"].get<double>());
            CHECK(j["bytes_sent_per_tet"].get<double>() ==
                  132.0 * j["sent_faces"].get<double>() / j["cells"].get<double>());
            CHECK(j["wrong_exits"].is_null());
        }
    }
    SECTION("refusals: exact segments on GL, an unknown order")
    {
        for (const auto& [args, phrase] :
             {std::pair<std::string, std::string>{"--backend gl --segment exact",
                                                  "--segment exact runs only in the emulation"},
              {"--order painter", "--order must be centroid or mpvonc"}}) {
            const std::string out = tmp.file("never.npy");
            const CommandResult r = run_uvr(scene + "--algo vicp " + args + " --out '" + out + "'");
            INFO(args << ": " << r.err);
            CHECK(r.exit_code == 1);
            CHECK(r.err.find(phrase) != std::string::npos);
            CHECK(!std::filesystem::exists(out));
        }
    }
}

TEST_CASE("uvr render --algo havs --backend gl writes the emulation's image and refuses what GL cannot do")
{
    TempDir tmp("cli-gl");
    const std::string scene = "render builtin:torus-small --algo havs --size 48x40 --view 30,20 ";
    SECTION("the GL image has the emulation's bits, and its diagnostics")
    {
        const CommandResult emu = run_uvr(scene + "--backend emu --out '" + tmp.file("emu.npy") + "'");
        const CommandResult gl =
            run_uvr(scene + "--backend gl --gl osmesa --json --diagnostics '" + tmp.file("diag") + "' --out '" +
                    tmp.file("gl.npy") + "'");
        INFO(emu.err << gl.err);
        REQUIRE(emu.exit_code == 0);
        REQUIRE(gl.exit_code == 0);
        CHECK(file_contents(tmp.file("gl.npy")) == file_contents(tmp.file("emu.npy")));
        CHECK(gl.out.find("\"backend\": \"gl\"") != std::string::npos);
        CHECK(gl.out.find("llvmpipe") != std::string::npos);
        CHECK(std::filesystem::exists(tmp.file("diag/fragments.npy")));
    }
    SECTION("refusals: exact segments, diagnostics without a free draw buffer, an unknown platform")
    {
        struct Case {
            std::string args, phrase;
        };
        for (const Case& c : {Case{"--backend gl --segment exact", "--segment exact runs only in the emulation"},
                              Case{"--backend gl --k 14 --diagnostics '" + tmp.file("d") + "'", "needs a free draw buffer"},
                              Case{"--backend gl --k 15", "--k must be between 1 and 14"},
                              Case{"--backend gl --gl glx", "--gl must be osmesa or egl"},
                              Case{"--backend vulkan", "--backend must be one of emu, gl, arb with --algo havs"}}) {
            const std::string out = tmp.file("never.npy");
            const CommandResult r = run_uvr(scene + c.args + " --out '" + out + "'");
            INFO(c.args << ": " << r.err);
            CHECK(r.exit_code != 0);
            CHECK(r.err.find(c.phrase) != std::string::npos);
            CHECK(!std::filesystem::exists(out));
        }
    }
    SECTION("a sweep on GL refuses a k its draw buffers cannot hold before running any")
    {
        const CommandResult r = run_uvr("sweep builtin:torus-small --size 32x32 --backend gl --k 2,16 --report '" +
                                        tmp.file("sweep") + "'");
        INFO(r.err);
        CHECK(r.exit_code == 1);
        CHECK(r.err.find("--k must be between 1 and 14") != std::string::npos);
        CHECK(!std::filesystem::exists(tmp.file("sweep")));
    }
}

TEST_CASE("no GL context: --backend gl fails with a clear error and writes nothing, never crashes")
{
    TempDir tmp("cli-nogl");
    const std::string out = tmp.file("never.npy");
    const std::string args = "render builtin:torus-small --algo havs --backend gl --size 32x32 --out '" + out + "' ";
    // Runs `args + extra` with the environment variable `name` set to `value` for the child only.
    auto run_with = [&](const char* name, const char* value, const std::string& extra) {
        setenv(name, value, 1);
        const CommandResult r = run_uvr(args + extra);
        unsetenv(name);
        return r;
    };
    SECTION("EGL without a vendor library (glvnd finds no driver)")
    {
        const CommandResult r = run_with("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/vendor.json", "--gl egl");
        INFO(r.err);
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("EGL: cannot create an OpenGL 4.5 core-profile context"));
    }
    SECTION("OSMesa asked for a driver it does not have (Mesa 22.3 itself would crash)")
    {
        const CommandResult r = run_with("GALLIUM_DRIVER", "nonexistent", "--gl osmesa");
        INFO(r.err);
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("GALLIUM_DRIVER=nonexistent"));
    }
    CHECK(!std::filesystem::exists(out));
}

TEST_CASE("uvr render --algo reference renders a regular grid, and what needs a mesh refuses one before writing")
{
    TempDir tmp("cli-volume");
    const std::string volume = "'" + data_path("vtk-data/hydrogen.vti") + "' --size 48x40 ";
    SECTION("the trilinear reference: finite, not empty")
    {
        const CommandResult r =
            run_uvr("render " + volume + "--algo reference --no-cache --json --out '" + tmp.file("h.npy") + "'");
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        const uvr::Image img = uvr::read_npy(tmp.file("h.npy"));
        std::size_t covered = 0, nonfinite = 0;
        for (std::size_t p = 0; p < img.rgba.size(); ++p) nonfinite += std::isfinite(img.rgba[p]) ? 0 : 1;
        for (std::size_t p = 3; p < img.rgba.size(); p += 4) covered += img.rgba[p] > 0.01f ? 1 : 0;
        CHECK(nonfinite == 0);
        CHECK(covered > 100);
        CHECK(nlohmann::json::parse(r.out)["cell_pieces"].get<uint64_t>() > 1000);
    }
    SECTION("uvr bench times the grid reference; bench with HAVS refuses the grid")
    {
        const CommandResult r = run_uvr("bench " + volume + "--algos reference --repeat 1 --warmup 0 --json");
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        const auto j = nlohmann::json::parse(r.out);
        CHECK(j["voxels"].get<uint64_t>() > 1000);
        CHECK(j["results"][0]["algo"] == "reference");
        CHECK(j["results"][0]["frame_ms"].get<double>() > 0.0);
        const CommandResult h = run_uvr("bench " + volume + "--algos reference,havs --repeat 1");
        CHECK(h.exit_code == 1);
        CHECK(h.err.find("is a regular grid") != std::string::npos);
        CHECK(h.out.empty());
    }
    SECTION("HAVS, a compare with HAVS, a sweep: refused, nothing written")
    {
        for (const std::string& cmd :
             {"render " + volume + "--algo havs --out '" + tmp.file("never.npy") + "'",
              "compare " + volume + "--algos reference,havs --report '" + tmp.file("never") + "'",
              "sweep " + volume + "--k 1,2 --report '" + tmp.file("never") + "'"}) {
            const CommandResult r = run_uvr(cmd);
            INFO(cmd << ": " << r.err);
            CHECK(r.exit_code == 1);
            CHECK(r.err.find("is a regular grid") != std::string::npos);
            CHECK(!std::filesystem::exists(tmp.file("never.npy")));
            CHECK(!std::filesystem::exists(tmp.file("never")));
        }
    }
}

TEST_CASE("uvr render, compare and sweep run the ray caster on a regular grid and refuse bad options")
{
    TempDir tmp("cli-raycast");
    const std::string volume = "'" + data_path("vtk-data/neghip.slc") + "' --size 40x32 ";
    SECTION("emulated and GL images are the same bits")
    {
        const CommandResult emu = run_uvr("render " + volume + "--algo raycast --json --out '" + tmp.file("e.npy") + "'");
        const CommandResult gl =
            run_uvr("render " + volume + "--algo raycast --backend gl --gl osmesa --json --out '" + tmp.file("g.npy") + "'");
        INFO(emu.err << gl.err);
        REQUIRE(emu.exit_code == 0);
        REQUIRE(gl.exit_code == 0);
        const auto j = nlohmann::json::parse(emu.out);
        CHECK(j["volume_format"] == "u8");
        CHECK(j["step"].get<double>() == 0.5);  // half the smallest spacing (1)
        CHECK(j["samples"].get<uint64_t>() > 0);
        const uvr::Image a = uvr::read_npy(tmp.file("e.npy")), b = uvr::read_npy(tmp.file("g.npy"));
        CHECK(a.rgba == b.rgba);
    }
    SECTION("compare and sweep --step measure against the reference")
    {
        const CommandResult c = run_uvr("compare " + volume + "--algos raycast --preintegrate --json --report '" +
                                        tmp.file("c") + "'");
        INFO(c.err);
        REQUIRE(c.exit_code == 0);
        const auto j = nlohmann::json::parse(c.out);
        CHECK(j["results"][1]["label"] == "raycast-emu-preint");
        CHECK(std::filesystem::exists(tmp.file("c/raycast-emu-preint-error.png")));
        const CommandResult sw =
            run_uvr("sweep " + volume + "--step 1,0.5 --threshold 1 --json --report '" + tmp.file("s") + "'");
        INFO(sw.err);
        REQUIRE(sw.exit_code == 0);
        const auto rows = nlohmann::json::parse(sw.out)["rows"];
        REQUIRE(rows.size() == 4u);  // two steps, post-classified and pre-integrated
        CHECK(rows[1]["rmse"].get<double>() < rows[0]["rmse"].get<double>());
        CHECK(std::filesystem::exists(tmp.file("s/sweep.csv")));
    }
    SECTION("bad options: a clear error, nothing written")
    {
        for (const std::string& args : {std::string("--step 0"), std::string("--step 1e-9"),
                                        std::string("--light 1,2"), std::string("--volume-format u4"),
                                        std::string("--segment exact"), std::string("--threshold 2")}) {
            const std::string out = tmp.file("never.npy");
            const CommandResult r = run_uvr("render " + volume + "--algo raycast " + args + " --out '" + out + "'");
            INFO(args << ": " << r.err);
            CHECK(r.exit_code == 1);
            CHECK(!r.err.empty());
            CHECK(!std::filesystem::exists(out));
        }
        const CommandResult m = run_uvr("sweep builtin:torus-small --step 1 --report '" + tmp.file("never") + "'");
        CHECK(m.exit_code == 1);
        CHECK_THAT(m.err, Catch::Contains("is a tetrahedral mesh"));
        CHECK(!std::filesystem::exists(tmp.file("never")));
    }
}
