// `uvr render MESH --algo ... --out FILE`: one image from one algorithm (SPEC §3).
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include <cmath>

#include "bench/commands.h"
#include "gpu/havs.h"
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
    int k = 6;
    std::string segment = "table";
    std::string gaps = "exact";
    double threshold = -1.0;  // per algorithm default (SPEC §3)
    int table_size = 128;
    std::string table_format = "f32";
    std::string diagnostics;  // directory for the per-pixel diagnostic images
};

gpu::HavsOptions havs_options(const RenderArgs& a)
{
    gpu::HavsOptions o;
    o.k = a.k;
    if (a.segment != "table" && a.segment != "exact") throw InputError("", "--segment must be table or exact");
    o.segment = a.segment == "exact" ? gpu::SegmentMode::exact : gpu::SegmentMode::table;
    if (a.gaps != "exact" && a.gaps != "maxgap") throw InputError("", "--gaps must be exact or maxgap");
    o.gaps = a.gaps == "maxgap" ? gpu::GapMode::maxgap : gpu::GapMode::exact;
    o.threshold = a.threshold < 0.0 ? 0.99f : float(a.threshold);
    if (a.table_size < 2 || a.table_size > 1024) throw InputError("", "--table-size must be between 2 and 1024");
    o.table_size = a.table_size;
    if (a.table_format == "f32")
        o.table_format = gpu::TexelFormat::f32;
    else if (a.table_format == "u16")
        o.table_format = gpu::TexelFormat::u16;
    else if (a.table_format == "u8")
        o.table_format = gpu::TexelFormat::u8;
    else
        throw InputError("", "--table-format must be f32, u16 or u8");
    return o;
}

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
    cmd->add_option("--k", a->k, "HAVS: k-buffer entries")->capture_default_str();
    cmd->add_option("--segment", a->segment, "HAVS: table | exact (emulation only)")->capture_default_str();
    cmd->add_option("--gaps", a->gaps, "HAVS: exact | maxgap (VTK's heuristic)")->capture_default_str();
    cmd->add_option("--threshold", a->threshold, "Early-termination opacity (HAVS 0.99; 1 switches it off)");
    cmd->add_option("--table-size", a->table_size, "HAVS: pre-integration table texels per axis")->capture_default_str();
    cmd->add_option("--table-format", a->table_format, "HAVS: f32 | u16 | u8")->capture_default_str();
    cmd->add_option("--diagnostics", a->diagnostics, "HAVS: directory for per-pixel fragment, held-entry and "
                                                     "ordering-error images");
    cmd->callback([a] {
        if (a->algo == "havs") {
            if (a->backend != "emu")
                throw InputError("", "--backend " + a->backend + " is not available yet for HAVS: only emu (the GL "
                                     "backend is issue 5)");
            const std::string ext = file_extension(a->out);
            if (ext != ".npy" && ext != ".png")
                throw InputError(a->out, "unsupported image extension (use .npy or .png)");
            const Scene s = setup_scene(a->scene);
            const gpu::HavsRenderer havs(s.mesh(), *s.topology, s.field, s.tf, havs_options(*a));
            const gpu::HavsFrame f = havs.render(s.camera, s.width, s.height);
            write_image(a->out, f.image);
            if (!a->diagnostics.empty()) {
                std::error_code ec;
                std::filesystem::create_directories(a->diagnostics, ec);
                if (ec) throw InputError(a->diagnostics, "cannot create the directory: " + ec.message());
                write_counts(a->diagnostics + "/fragments", f.fragments, s.width, s.height);
                write_counts(a->diagnostics + "/max_held", f.max_held, s.width, s.height);
                write_counts(a->diagnostics + "/ordering_errors", f.ordering_errors, s.width, s.height);
            }
            if (a->json) {
                const auto& st = f.stats;
                nlohmann::json j = {{"algo", "havs"}, {"backend", "emu"}, {"out", a->out}, {"width", s.width},
                                    {"height", s.height}, {"k", a->k}, {"segment", a->segment}, {"gaps", a->gaps},
                                    {"faces", st.faces}, {"fragments", st.fragments},
                                    {"max_fragments_per_pixel", st.max_fragments}, {"max_held", st.max_held},
                                    {"ordering_errors", st.ordering_errors},
                                    {"stages_ms", {{"table", st.table_ms}, {"sort", st.sort_ms}, {"setup", st.setup_ms},
                                                   {"raster_fragment", st.raster_fragment_ms},
                                                   {"flush", st.flush_ms}}}};
                std::printf("%s\n", j.dump(1).c_str());
            }
            return;
        }
        if (a->algo != "reference")
            throw InputError("", "--algo " + a->algo + " is not available yet: reference and havs have landed "
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
