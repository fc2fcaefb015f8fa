// `uvr render MESH --algo ... --out FILE`: one image from one algorithm (docs/spec.md §3).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/algorithms.h"
#include "bench/commands.h"
#include "bench/render_parallel.h"
#include "distributed/mpi_runtime.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

struct RenderArgs {
    SceneOptions scene;
    AlgoOptions algo_options;
    std::string algo = "reference";
    std::string out;
    std::string diagnostics;  // directory for the per-pixel diagnostic images
    bool json = false;
};

// A diagnostic count image: the counts scaled to the largest, as a grey-level PNG, plus the raw counts as .npy (in
// the red channel, alpha 1).
void write_counts(const std::string& base, const std::vector<uint32_t>& counts, int width, int height)
{
    uint32_t top = 1;
    for (uint32_t c : counts) top = std::max(top, c);
    std::vector<unsigned char> rgb(counts.size() * 3);
    Image raw(width, height);
    for (std::size_t p = 0; p < counts.size(); ++p) {
        const auto g = static_cast<unsigned char>(std::lround(255.0 * double(counts[p]) / double(top)));
        rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = g;
        raw.rgba[4 * p] = float(counts[p]);
        raw.rgba[4 * p + 3] = 1.0f;
    }
    write_png_rgb8(base + ".png", width, height, rgb);
    write_npy(base + ".npy", raw);
}

}  // namespace

void register_render(CLI::App& app)
{
    auto* cmd = app.add_subcommand("render", "Render a mesh with one algorithm and write the image");
    auto a = std::make_shared<RenderArgs>();
    add_scene_options(*cmd, a->scene);
    add_algo_options(*cmd, a->algo_options);
    cmd->add_option("--algo", a->algo, "reference | havs | vicp | raycast")->capture_default_str();
    cmd->add_option("--out", a->out, "Output image (.npy float32 RGBA, .exr float RGBA, or .png)")->required();
    cmd->add_option("--diagnostics", a->diagnostics,
                    "HAVS: directory for per-pixel fragment, held-entry and ordering-error images");
    cmd->add_flag("--json", a->json, "Print one JSON object on stdout");
    cmd->callback([a] {
        // Fail on an unknown output format before spending time on the render.
        const std::string ext = file_extension(a->out);
        if (ext != ".npy" && ext != ".exr" && ext != ".png") {
            const std::string why = "unsupported image extension (use .npy, .exr or .png)";
            // Every rank sees the same arguments: one message from rank 0 and every rank's exit 1, not an abort.
            if (mpi::active()) throw mpi::RanksFailed(a->out, why);
            throw InputError(a->out, why);
        }
        if (mpi::active()) {
            if (a->algo != "reference" && a->algo != "havs" && a->algo != "vicp")
                throw mpi::RanksFailed("", "under mpirun, uvr render runs --algo reference, havs or vicp; --algo " +
                                               a->algo + " runs in one process");
            if (a->algo_options.parts > 1)
                throw mpi::RanksFailed("", "under mpirun the .pvtu's pieces are the parts: --parts is for one process");
            if (a->algo == "reference")
                render_reference_parallel(a->scene, a->out, a->json);
            else
                render_sort_last_parallel(a->scene, a->algo, a->algo_options, a->out, a->json);
            return;
        }
        a->algo_options.require_diagnostics = !a->diagnostics.empty();
        const Scene s = setup_scene(a->scene);
        const AlgoResult r = run_algorithm(s, a->algo, a->algo_options);
        // Which GL device rendered (a hardware one, or Mesa's llvmpipe), also without --json.
        if (r.stats.contains("gl"))
            std::fprintf(stderr, "uvr render: GL: %s\n", r.stats["gl"].get<std::string>().c_str());
        write_image(a->out, r.image);
        if (!a->diagnostics.empty() && !r.fragments.empty()) {
            std::error_code ec;
            std::filesystem::create_directories(a->diagnostics, ec);
            if (ec) throw InputError(a->diagnostics, "cannot create the directory: " + ec.message());
            write_counts(a->diagnostics + "/fragments", r.fragments, s.width, s.height);
            if (!r.max_held.empty()) write_counts(a->diagnostics + "/max_held", r.max_held, s.width, s.height);
            write_counts(a->diagnostics + "/ordering_errors", r.ordering_errors, s.width, s.height);
        }
        if (a->json) {
            nlohmann::json j = r.stats;
            j["algo"] = a->algo;
            j["backend"] = backend_of(find_algorithm(a->algo), a->algo_options);
            j["out"] = a->out;
            j["width"] = s.width;
            j["height"] = s.height;
            if (!r.cached) j["seconds"] = r.ms / 1000.0;
            std::printf("%s\n", j.dump(1).c_str());
        }
    });
}

}  // namespace uvr::cli
