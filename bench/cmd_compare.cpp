// `uvr compare MESH --algos LIST [--image FILE --label NAME ...] --report DIR`: every algorithm on one scene, and any
// image made elsewhere of the same scene, each measured against the reference (docs/spec.md §4): images, error heat
// maps, metrics.json and an HTML page.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/algorithms.h"
#include "bench/commands.h"
#include "bench/report.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

struct CompareArgs {
    SceneOptions scene;
    AlgoOptions algo_options;
    std::string algos = "reference,havs";
    std::string report;
    std::vector<std::string> images, labels;  // --image FILE, --label NAME (one per image, or none)
    bool json = false;
};

}  // namespace

nlohmann::json run_compare(const Scene& s, const std::vector<std::string>& algos, const AlgoOptions& o,
                           const std::string& dir, const std::string& mesh_name, const std::vector<LabelledImage>& images)
{
    for (const auto& algo : algos) check_algorithm_scene(s, algo);  // refused before any output
    // Outside images: read and checked against the scene's size before any output.
    std::vector<OutsideImage> outside;
    for (const LabelledImage& li : images) {
        outside.push_back(read_outside_image(li.path));
        const Image& im = outside.back().image;
        if (im.width != s.width || im.height != s.height)
            throw InputError(li.path, "is " + std::to_string(im.width) + "x" + std::to_string(im.height) +
                                          ", the scene is " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                          " (--size)");
    }
    const std::vector<std::string> listed_modes = split_list(o.interpolation);
    for (const std::string& mode : listed_modes)
        if (listed_modes.size() > 1 && mode != "gpu" && mode != "exact")
            throw InputError("", "--interpolation takes gpu, exact or the list gpu,exact");
    // Each algorithm's options in each of its modes, before any output.
    const auto modes_of = [&](const std::string& algo) {
        return (algo == "havs" || algo == "vicp" || algo == "raycast") && listed_modes.size() > 1
                   ? listed_modes
                   : std::vector<std::string>{listed_modes.size() > 1 ? std::string() : o.interpolation};
    };
    for (const auto& algo : algos)
        for (const std::string& mode : modes_of(algo)) {
            AlgoOptions om = o;
            om.interpolation = mode;
            find_algorithm(algo).check_options(om);
        }
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw InputError(dir, "cannot create the report directory: " + ec.message());
    const AlgoResult ref = run_algorithm(s, "reference", o);
    nlohmann::json m;
    m["mesh"] = mesh_name;
    m["field"] = s.field_name();
    m["width"] = s.width;
    m["height"] = s.height;
    m["results"] = nlohmann::json::array();
    auto add = [&](const std::string& algo, const AlgoResult& r, const std::string& label) {
        write_image(dir + "/" + label + ".png", r.image);
        write_image(dir + "/" + label + ".npy", r.image);
        nlohmann::json j = measures_json(measure_errors(r.image, ref.image));
        j["algo"] = algo;
        j["backend"] = backend_of(find_algorithm(algo), o);
        j["label"] = label;
        j["image"] = label + ".png";
        j["ms"] = r.ms;
        j["cached"] = r.cached;
        j["stats"] = r.stats;
        if (&r != &ref) {
            write_png_rgb8(dir + "/" + label + "-error.png", s.width, s.height,
                           error_heat_map(pixel_errors(r.image, ref.image)));
            j["error_map"] = label + "-error.png";
        }
        m["results"].push_back(j);
    };
    add("reference", ref, "reference");
    for (const auto& algo : algos) {
        if (algo == "reference") continue;
        // --interpolation gpu,exact renders HAVS, VICP and the ray caster once per mode, side by side; the reference
        // has none.
        for (const std::string& mode : modes_of(algo)) {
            AlgoOptions om = o;
            om.interpolation = mode;
            const AlgoResult r = run_algorithm(s, algo, om);
            // The label names what sets the image apart: HAVS's backend, k and interpolation, VICP's backend and cell
            // order, the ray caster's backend and classification.
            add(algo, r, find_algorithm(algo).label(om));
        }
    }
    // Each outside image: measured like an algorithm's, over colour alone when it has no alpha (the page says so).
    for (std::size_t i = 0; i < images.size(); ++i) {
        const Image& im = outside[i].image;
        const int channels = outside[i].colour_only ? 3 : 4;
        const std::string& label = images[i].label;
        write_image(dir + "/" + label + ".png", im);
        nlohmann::json j = measures_json(measure_errors(im, ref.image, channels));
        j["algo"] = "image";
        j["backend"] = "outside";
        j["label"] = label;
        j["source"] = images[i].path;
        j["colour_only"] = outside[i].colour_only;
        j["image"] = label + ".png";
        j["ms"] = 0.0;
        j["cached"] = false;
        write_png_rgb8(dir + "/" + label + "-error.png", s.width, s.height,
                       error_heat_map(pixel_errors(im, ref.image, channels)));
        j["error_map"] = label + "-error.png";
        m["results"].push_back(j);
    }
    write_file_atomically(dir + "/metrics.json", m.dump(1) + "\n");
    write_compare_page(dir, m);
    return m;
}

void register_compare(CLI::App& app)
{
    auto* cmd = app.add_subcommand("compare", "Render with several algorithms and measure each against the reference");
    auto a = std::make_shared<CompareArgs>();
    add_scene_options(*cmd, a->scene);
    add_algo_options(*cmd, a->algo_options);
    cmd->add_option("--algos", a->algos, "Comma-separated algorithms")->capture_default_str();
    cmd->add_option("--report", a->report, "Directory for images, error maps, metrics.json, index.html")->required();
    cmd->add_option("--image", a->images,
                    "An image of the same scene made elsewhere (.npy float32 premultiplied RGBA, row 0 on top; .exr; "
                    ".pfm; .png: colour only), measured against the reference like the algorithms; repeatable");
    cmd->add_option("--label", a->labels, "The name of each --image on the page (default: the file's name)");
    cmd->add_flag("--json", a->json, "Print metrics.json's object on stdout");
    cmd->callback([a] {
        const auto algos = split_list(a->algos);
        if (algos.empty()) throw InputError("", "--algos is empty");
        for (const auto& x : algos) run_algorithm_check(x);
        if (!a->labels.empty() && a->labels.size() != a->images.size())
            throw InputError("", "give one --label per --image (" + std::to_string(a->images.size()) + " images, " +
                                     std::to_string(a->labels.size()) + " labels), or none");
        std::vector<LabelledImage> images;
        for (std::size_t i = 0; i < a->images.size(); ++i) {
            std::string label = a->labels.empty() ? std::filesystem::path(a->images[i]).stem().string() : a->labels[i];
            for (char& c : label)  // the label names files in the report
                if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
            for (const auto& x : algos)
                if (label == x || label == "reference")
                    throw InputError(a->images[i], "its label '" + label + "' is taken by an algorithm; give --label");
            images.push_back({a->images[i], label});
        }
        const Scene s = setup_scene(a->scene);
        const nlohmann::json m = run_compare(s, algos, a->algo_options, a->report, a->scene.input.path, images);
        if (a->json) {
            std::printf("%s\n", m.dump(1).c_str());
            return;
        }
        for (const auto& r : m["results"])
            std::printf("%-16s RMSE %-10.3g max %-10.3g visible %-8.4f %s\n", r["label"].get<std::string>().c_str(),
                        r["rmse"].get<double>(), r["max_abs"].get<double>(), r["visible_fraction"].get<double>(),
                        r["cached"].get<bool>() ? "(cached)" : "");
        std::printf("report: %s/index.html\n", a->report.c_str());
    });
}

}  // namespace uvr::cli
