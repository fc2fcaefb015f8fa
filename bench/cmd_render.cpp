// `uvr render MESH --algo ... --out FILE`: one image from one algorithm (SPEC §3).
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/progress.h"
#include "bench/scene.h"
#include "reference/error.h"
#include "reference/image_cache.h"
#include "reference/io_util.h"
#include "reference/reference_renderer.h"

namespace uvr::cli {

namespace {

struct RenderArgs {
    SceneOptions scene;
    std::string algo = "reference";
    std::string backend = "emu";
    std::string out;
    bool json = false;
    bool no_cache = false;
};

// The reference image of a scene, from the cache when it is there.
Image reference_image(const Scene& s, bool use_cache, ReferenceStats& stats, bool& cached)
{
    const std::string key = reference_cache_key(s.mesh(), s.field, s.tf, s.camera, s.width, s.height);
    if (use_cache) {
        if (auto img = cache_load(key, s.width, s.height)) {
            cached = true;
            return *img;
        }
    }
    cached = false;
    const RayIntegrator integrator(s.mesh(), *s.topology, s.field, s.tf);
    ProgressBar bar("reference");
    Image img = render_reference(integrator, s.camera, s.width, s.height, stats,
                                 [&](double f) { bar.update(f); });
    bar.finish();
    if (stats.failures)
        throw InputError(s.mesh().source, std::to_string(stats.failures) +
                                              " rays were abandoned by the walk's guards; the image would be wrong");
    if (use_cache) cache_store(key, img);
    return img;
}

}  // namespace

void register_render(CLI::App& app)
{
    auto* cmd = app.add_subcommand("render", "Render a mesh with one algorithm and write the image");
    auto a = std::make_shared<RenderArgs>();
    add_scene_options(*cmd, a->scene);
    cmd->add_option("--algo", a->algo, "reference | havs | vicp | raycast")->capture_default_str();
    cmd->add_option("--backend", a->backend, "emu | gl")->capture_default_str();
    cmd->add_option("--out", a->out, "Output image (.npy float32 RGBA, or .png)")->required();
    cmd->add_flag("--json", a->json, "Print one JSON object on stdout");
    cmd->add_flag("--no-cache", a->no_cache, "Do not read or write the reference image cache");
    cmd->callback([a] {
        if (a->algo != "reference")
            throw InputError("", "--algo " + a->algo + " is not available yet: only the reference has landed "
                                 "(docs/status.md)");
        // Fail on an unwritable or unknown output before spending time on the render.
        const std::string ext = file_extension(a->out);
        if (ext != ".npy" && ext != ".png") throw InputError(a->out, "unsupported image extension (use .npy or .png)");
        const Scene s = setup_scene(a->scene);
        ReferenceStats stats;
        bool cached = false;
        const Image img = reference_image(s, !a->no_cache, stats, cached);
        write_image(a->out, img);
        if (a->json) {
            nlohmann::json j;
            j["algo"] = "reference";
            j["backend"] = "cpu";
            j["out"] = a->out;
            j["width"] = s.width;
            j["height"] = s.height;
            j["cached"] = cached;
            if (!cached) {
                j["seconds"] = stats.seconds;
                j["rays"] = stats.rays;
                j["segments"] = stats.segments;
                j["entries"] = stats.entries;
            }
            std::printf("%s\n", j.dump(1).c_str());
        }
    });
}

}  // namespace uvr::cli
