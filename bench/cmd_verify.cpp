// `uvr verify`: the observed order of accuracy of a renderer (docs/verification.md). Either uvr renders an algorithm at
// a sequence of refinements of one parameter and measures each level against the reference, or it reads a sequence
// of images made elsewhere and measures them against a reference image (or against each other).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/report.h"
#include "bench/verify.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

struct VerifyArgs {
    SceneOptions scene;
    VerifyRequest request;
    std::string refine;  // kRefinements' spelling, read into request.refine
    std::string images, h, reference;
    double expected = std::numeric_limits<double>::quiet_NaN();
    std::string report;
    bool json = false;
};

std::vector<double> parse_h_list(const std::string& list)
{
    std::vector<double> h;
    for (const std::string& x : split_list(list)) {
        char* end = nullptr;
        const double v = std::strtod(x.c_str(), &end);
        if (x.empty() || *end) throw InputError("", "--h takes numbers, found '" + x + "'");
        h.push_back(v);
    }
    return h;
}

// --images: an outside renderer's sequence, against --reference, the scene's reference, or (neither) each other.
nlohmann::json images_of(const VerifyArgs& a)
{
    const std::vector<std::string> paths = split_list(a.images);
    const std::vector<double> h = parse_h_list(a.h);
    if (paths.size() != h.size())  // before the images are read
        throw InputError("", "--images has " + std::to_string(paths.size()) + " images and --h " +
                                 std::to_string(h.size()) + " values: one h per image");
    std::vector<OutsideImage> images;
    int channels = 4;
    for (const std::string& p : paths) {
        images.push_back(read_outside_image(p));
        if (images.back().colour_only) channels = 3;
        const Image& first = images.front().image;
        if (images.back().image.width != first.width || images.back().image.height != first.height)
            throw InputError(p, "is " + std::to_string(images.back().image.width) + "x" +
                                    std::to_string(images.back().image.height) + ", " + paths.front() + " is " +
                                    std::to_string(first.width) + "x" + std::to_string(first.height));
    }
    const Image& first = images.front().image;
    Image ref;
    std::string against;
    if (!a.reference.empty()) {
        OutsideImage r = read_outside_image(a.reference);
        if (r.image.width != first.width || r.image.height != first.height)
            throw InputError(a.reference, "is " + std::to_string(r.image.width) + "x" + std::to_string(r.image.height) +
                                              ", the images are " + std::to_string(first.width) + "x" +
                                              std::to_string(first.height));
        ref = std::move(r.image);
        against = a.reference;
    } else if (!a.scene.input.path.empty()) {
        SceneOptions so = a.scene;
        so.size = std::to_string(first.width) + "x" + std::to_string(first.height);
        ref = run_algorithm(setup_scene(so), "reference", a.request.options).image;
        against = "the reference of " + a.scene.input.path;
    }
    nlohmann::json j = verify_images(
        [&] {
            std::vector<Image> v;
            for (OutsideImage& im : images) v.push_back(std::move(im.image));
            return v;
        }(),
        h, against.empty() ? nullptr : &ref, channels, a.expected);
    if (against.empty()) against = "successive differences";
    j["mode"] = "images";
    j["images"] = paths;
    j["against"] = against;
    j["channels"] = channels;
    return j;
}

void write_report(const std::string& dir, const nlohmann::json& j)
{
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw InputError(dir, "cannot create the report directory: " + ec.message());
    std::string csv = "h,rmse,max_abs\n";
    std::string rows;
    const auto& r = j["measures"]["rmse"];
    const auto& m = j["measures"]["max_abs"];
    for (std::size_t i = 0; i < r["errors"].size(); ++i) {
        char line[160];
        std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g\n", j["h"][i].get<double>(), r["errors"][i].get<double>(),
                      m["errors"][i].get<double>());
        csv += line;
        std::snprintf(line, sizeof line, "<tr><td>%.6g<td>%.3e<td>%.3e", j["h"][i].get<double>(),
                      r["errors"][i].get<double>(), m["errors"][i].get<double>());
        rows += line;
    }
    write_file_atomically(dir + "/verify.json", j.dump(1) + "\n");
    write_file_atomically(dir + "/verify.csv", csv);
    // The plot by matplotlib (Debian's python3-matplotlib); without it the numbers still stand.
    const std::string plot =
        std::string("/usr/bin/python3 '") + UVR_SOURCE_DIR + "/bench/plots/verify_plots.py' '" + dir + "' 2>&1";
    const bool plotted = std::system(plot.c_str()) == 0;
    if (!plotted) std::fprintf(stderr, "uvr: warning: plot not drawn (needs python3-matplotlib)\n");
    char summary[256];
    std::snprintf(summary, sizeof summary,
                  "<p>Least-squares order: RMSE %.3f, largest error %.3f; expected %s "
                  "(tolerance %.2f): <b>%s</b></p>",
                  r["order"].get<double>(), m["order"].get<double>(), escape_markup(j["expected_order"].dump()).c_str(),
                  kOrderTolerance, j["verdict"].is_null() ? "no verdict" : j["verdict"].get<std::string>().c_str());
    write_file_atomically(dir + "/index.html",
                          "<!doctype html><meta charset=utf-8><title>uvr verify</title><h1>Observed order of "
                          "accuracy</h1>" +
                              std::string(summary) +
                              (plotted ? "<p><img src=\"verify.png\" alt=\"error against h\"></p>" : "") +
                              "<table border=1 cellpadding=4><tr><th>h<th>RMSE<th>largest error" + rows +
                              "</table><p>The numbers: verify.json, verify.csv (docs/verification.md).</p>\n");
}

void print_summary(const nlohmann::json& j)
{
    const auto& r = j["measures"]["rmse"];
    const auto& m = j["measures"]["max_abs"];
    for (std::size_t i = 0; i < r["errors"].size(); ++i)
        std::printf("h %-10.6g RMSE %.3e  largest %.3e\n", j["h"][i].get<double>(), r["errors"][i].get<double>(),
                    m["errors"][i].get<double>());
    std::printf("order: RMSE %.3f, largest %.3f; expected %s: %s\n", r["order"].get<double>(), m["order"].get<double>(),
                j["expected_order"].dump().c_str(),
                j["verdict"].is_null() ? "no verdict (--expected)" : j["verdict"].get<std::string>().c_str());
}

}  // namespace

void register_verify(CLI::App& app)
{
    auto* cmd = app.add_subcommand("verify",
                                   "The observed order of accuracy: a renderer's error as one "
                                   "discretization parameter is refined, against the order it promises");
    auto a = std::make_shared<VerifyArgs>();
    add_scene_options(*cmd, a->scene);
    cmd->get_option("MESH")->required(false);
    add_algo_options(*cmd, a->request.options);
    cmd->add_option("--algo", a->request.algo,
                    "The renderer: raycast, havs or vicp (and reference with --refine mesh)");
    cmd->add_option("--refine", a->refine, "What is refined: " + choices_help(kRefinements));
    cmd->add_option("--levels", a->request.levels, "Levels, each halving h")->capture_default_str();
    cmd->add_option("--from", a->request.from,
                    "The coarsest level: the step in world units (default twice the default "
                    "step), or the table size (default 16)");
    cmd->add_flag("--isolate", a->request.isolate,
                  "Every other switch exact (uvr budget's baseline), so that only the "
                  "refined parameter's error remains");
    cmd->add_option("--images", a->images,
                    "Comma-separated images of an outside renderer, coarsest first (any "
                    "format compare --image reads)");
    cmd->add_option("--h", a->h, "With --images: the h of each image, comma-separated, decreasing");
    cmd->add_option("--reference", a->reference,
                    "With --images: the reference image (else the scene's reference, "
                    "given MESH, else the images' successive differences)");
    cmd->add_option("--expected", a->expected, "With --images: the order the renderer should reach (the verdict)");
    cmd->add_option("--report", a->report, "Directory for verify.json, verify.csv and index.html");
    cmd->add_flag("--json", a->json, "Print the JSON on stdout");
    cmd->callback([a] {
        if (a->images.empty() && a->scene.input.path.empty())
            throw InputError("", "uvr verify takes MESH (uvr renders the levels) or --images (an outside renderer's)");
        if (!a->refine.empty()) a->request.refine = parse_choice("--refine", kRefinements, a->refine);
        if (!a->images.empty() && (!a->request.algo.empty() || a->request.refine))
            throw InputError("", "--images verifies images made elsewhere: --algo and --refine are for renders");
        if (a->images.empty() && (std::isfinite(a->expected) || !a->h.empty() || !a->reference.empty()))
            throw InputError("",
                             "--expected, --h and --reference go with --images (a render's expected order is "
                             "derived: docs/verification.md)");
        if (!a->report.empty()) a->request.images_dir = a->report + "/runs";
        const nlohmann::json j = a->images.empty() ? verify_refinement(a->scene, a->request) : images_of(*a);
        if (!a->report.empty()) write_report(a->report, j);
        if (a->json)
            std::printf("%s\n", j.dump(1).c_str());
        else
            print_summary(j);
    });
}

}  // namespace uvr::cli
