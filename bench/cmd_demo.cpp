// `uvr demo`: the whole lab on the built-in data set, no argument needed: the torus's ground truth beside HAVS
// (compare, with error maps) and a short error-versus-k sweep, each with its HTML page.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/algorithms.h"
#include "bench/commands.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr::cli {

nlohmann::json run_compare(const Scene& s, const std::vector<std::string>& algos, const AlgoOptions& o,
                           const std::string& dir, const std::string& mesh_name);

void register_demo(CLI::App& app)
{
    auto* cmd = app.add_subcommand("demo", "Run the lab on the built-in mesh (a tetrahedralized torus)");
    auto out_dir = std::make_shared<std::string>("uvr-demo");
    cmd->add_option("--out", *out_dir, "Directory for the demo's reports")->capture_default_str();
    cmd->callback([out_dir] {
        const auto t0 = std::chrono::steady_clock::now();
        std::error_code ec;
        std::filesystem::create_directories(*out_dir, ec);
        if (ec) throw InputError(*out_dir, "cannot create the demo directory: " + ec.message());
        SceneOptions so;
        so.input.path = "builtin:torus";
        so.view = "30,50";
        const Scene s = setup_scene(so);
        const TetMesh& mesh = s.mesh();
        std::printf("uvr demo: built-in torus (TetGen): %zu points, %zu tetrahedra, %zu faces (%zu boundary)\n",
                    mesh.points.size(), mesh.tets.size(), s.topology->faces.size(), s.topology->boundary_faces);
        AlgoOptions o;
        const nlohmann::json m = run_compare(s, {"reference", "havs"}, o, *out_dir + "/compare", "builtin:torus");
        for (const auto& r : m["results"])
            std::printf("uvr demo: %-12s RMSE %.3g, largest error %.3g, visible %.4f%s\n",
                        r["label"].get<std::string>().c_str(), r["rmse"].get<double>(), r["max_abs"].get<double>(),
                        r["visible_fraction"].get<double>(), r["cached"].get<bool>() ? " (reference from the cache)" : "");
        std::printf("uvr demo: comparison: %s/compare/index.html\n", out_dir->c_str());
        // A short sweep through the same program, as a user would run it.
        const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
        if (ec || self.empty()) throw InputError("/proc/self/exe", "cannot find the uvr program to run the sweep");
        const std::string sweep = "'" + self + "' sweep builtin:torus-small --k 1,2,4,8,16 --views 3 --size 256x256 "
                                  "--report '" + *out_dir + "/sweep'";
        std::fflush(stdout);  // our lines first, then the child's
        if (std::system(sweep.c_str()) != 0) throw InputError(*out_dir, "the demo's sweep failed");
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("uvr demo: done in %.1f s. Open %s/compare/index.html and %s/sweep/index.html\n", secs,
                    out_dir->c_str(), out_dir->c_str());
        std::printf("uvr demo: VICP, the ray caster and HAVS on the GL backend join as they land (docs/status.md)\n");
    });
}

}  // namespace uvr::cli
