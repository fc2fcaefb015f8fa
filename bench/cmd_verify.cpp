// `uvr verify`: the observed order of accuracy of a renderer (docs/verification.md). Either uvr renders an algorithm at
// a sequence of refinements of one parameter and measures each level against the reference, or it reads a sequence
// of images made elsewhere and measures them against a reference image (or against each other).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "bench/budget.h"
#include "bench/commands.h"
#include "bench/report.h"
#include "bench/verify.h"
#include "gpu/raycast/raycast_setup.h"
#include "reference/analytic_field.h"
#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

struct VerifyArgs {
    SceneOptions scene;
    AlgoOptions algo_options;
    std::string algo, refine;
    int levels = 4;
    double from = 0.0;  // the coarsest level: the step in world units, or the table size; 0: the default
    bool isolate = false;
    std::string images, h, reference;
    double expected = std::numeric_limits<double>::quiet_NaN();
    std::string report;
    bool json = false;
};

// What a refinement of an algorithm converges at, per measure, and why (docs/verification.md derives each). The
// largest error is one pixel's, whose ray may meet a kink of the integrand (a voxel face of the trilinear field, a
// table's end, a breakpoint of the transfer function) at a place that moves with h: first order at worst.
struct Expectation {
    double rmse, max_abs;
    std::string derivation;
};

Expectation expected_order(const std::string& algo, const std::string& refine, const AlgoOptions& o)
{
    if (refine == "step") {
        if (algo != "raycast")
            throw InputError("", "--refine step refines the ray caster's sampling distance (--algo raycast); " + algo +
                                     " has no step");
        if (!o.preintegrate)
            return {1.0, 1.0, "post-classification is a left Riemann sum: each sample stands for a whole step"};
        return {2.0, 1.0,
                "pre-integration takes the scalar linear between samples, an error of the second order in the "
                "step (the trilinear field's curvature along the ray)"};
    }
    if (refine == "table") {
        if (algo != "havs" && algo != "vicp" && algo != "raycast")
            throw InputError("", "--refine table refines HAVS's, VICP's or the pre-integrated ray caster's table; " +
                                     algo + " has none");
        if (algo == "raycast" && !o.preintegrate)
            throw InputError("", "--refine table: the ray caster's table is pre-integration's (--preintegrate)");
        const std::string interior =
            "the table is interpolated linearly between texel centres, and the pre-integral "
            "of a piecewise-linear transfer function has bounded second derivatives: an "
            "error of the second order in the texel spacing 1/n";
        if (algo == "raycast") return {2.0, 1.0, interior + " (the table's range is widened by half a texel)"};
        return {2.0, 1.0,
                interior +
                    "; scalars within half a texel of the range's ends read the end texel, a first-order "
                    "error there"};
    }
    if (refine == "mesh")
        return {2.0, 1.0,
                "the mesh samples the analytic field at its points and interpolates it linearly in each tetrahedron: "
                "an error of the second order in the cubes' edge for a smooth field"};
    throw InputError("", "--refine takes step, table or mesh, found '" + refine + "'");
}

// The options of each level: the user's, or with --isolate every other switch exact (uvr budget's baseline), and the
// refined parameter at h.
std::vector<AlgoOptions> level_options(const VerifyArgs& a, const Scene& s, const std::vector<double>& h)
{
    AlgoOptions base = a.algo_options;
    if (a.isolate) {
        if (a.algo == "raycast" && base.step <= 0.0) base.step = gpu::default_raycast_step(s.volume());
        base = budget_baseline(a.algo, base);
        if (a.refine == "step") {
            base.preintegrate = a.algo_options.preintegrate;
            if (!base.preintegrate) base.segment = a.algo_options.segment;  // no segments to integrate exactly
        }
        if (a.refine == "table") base.segment = "table";
    }
    std::vector<AlgoOptions> out;
    for (double x : h) {
        AlgoOptions o = base;
        if (a.refine == "step") o.step = x;
        if (a.refine == "table") o.table_size = int(std::lround(1.0 / x));
        find_algorithm(a.algo).check_options(o);
        out.push_back(o);
    }
    return out;
}

// The refinement's h: steps in world units halving from --from, or 1/n for table sizes n doubling from --from (default
// 16). The default first step is twice the default step (a voxel spacing) for post-classification; pre-integrated, a
// quarter of the spacing: the trilinear field's kinks at voxel faces keep the order below 2 while a segment often holds
// one (docs/verification.md).
std::vector<double> refinement(const VerifyArgs& a, const Scene& s)
{
    if (a.levels < 3 || a.levels > 12) throw InputError("", "--levels takes 3 to 12 levels");
    if (a.refine == "step") {
        const double from = a.from > 0.0                  ? a.from
                            : a.algo_options.preintegrate ? 0.5 * gpu::default_raycast_step(s.volume())
                                                          : 2.0 * gpu::default_raycast_step(s.volume());
        return halving(from, a.levels);
    }
    const int n0 = a.from > 0.0 ? int(std::lround(a.from)) : 16;
    if (n0 < 2 || (int64_t(n0) << (a.levels - 1)) > 1024)
        throw InputError("", "--refine table: table sizes from " + std::to_string(n0) + " over " +
                                 std::to_string(a.levels) + " levels leave 2 to 1024");
    return halving(1.0 / double(n0), a.levels);
}

nlohmann::json study_json(const OrderStudy& st, bool judged)
{
    nlohmann::json j = {{"errors", st.errors}, {"orders", st.orders}, {"order", st.fitted}};
    j["verdict"] = judged ? nlohmann::json(st.pass ? "pass" : "fail") : nlohmann::json(nullptr);
    return j;
}

// The orders of both measures, the expected order and the verdict (both measures pass, or fail).
nlohmann::json orders_json(const std::vector<double>& h, const std::vector<ErrorMeasures>& e, double expected_rmse,
                           double expected_max, const std::string& what, std::size_t min_levels = 3)
{
    std::vector<double> rmse, max_abs;
    for (const ErrorMeasures& m : e) {
        rmse.push_back(m.rmse);
        max_abs.push_back(m.max_abs);
    }
    const bool judged = std::isfinite(expected_rmse);
    const OrderStudy r = observed_order(h, rmse, judged ? expected_rmse : 0.0, what, min_levels);
    const OrderStudy m = observed_order(h, max_abs, judged ? expected_max : 0.0, what, min_levels);
    nlohmann::json j;
    j["h"] = h;
    j["measures"] = {{"rmse", study_json(r, judged)}, {"max_abs", study_json(m, judged)}};
    j["expected_order"] =
        judged ? nlohmann::json({{"rmse", expected_rmse}, {"max_abs", expected_max}}) : nlohmann::json(nullptr);
    j["tolerance"] = kOrderTolerance;
    j["verdict"] = judged ? nlohmann::json(r.pass && m.pass ? "pass" : "fail") : nlohmann::json(nullptr);
    return j;
}

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
nlohmann::json verify_images(const VerifyArgs& a)
{
    const std::vector<std::string> paths = split_list(a.images);
    const std::vector<double> h = parse_h_list(a.h);
    if (paths.size() != h.size())
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
        ref = run_algorithm(setup_scene(so), "reference", a.algo_options).image;
        against = "the reference of " + a.scene.input.path;
    }
    nlohmann::json j;
    if (!against.empty()) {
        std::vector<ErrorMeasures> e;
        for (const OutsideImage& im : images) e.push_back(measure_errors(im.image, ref, channels));
        j = orders_json(h, e, a.expected, a.expected, "--images");
    } else {
        // Successive differences d_i = |I_i - I_{i+1}| fall as h_i^p where h halves (or shrinks by any constant
        // ratio) from level to level.
        for (std::size_t i = 2; i < h.size(); ++i)
            if (std::fabs(std::log(h[i - 1] / h[i]) / std::log(h[i - 2] / h[i - 1]) - 1.0) > 1e-9)
                throw InputError("", "--images without a reference: h must shrink by one ratio from level to level");
        std::vector<ErrorMeasures> d;
        for (std::size_t i = 0; i + 1 < images.size(); ++i)
            d.push_back(measure_errors(images[i].image, images[i + 1].image, channels));
        j = orders_json(std::vector<double>(h.begin(), h.end() - 1), d, a.expected, a.expected, "--images", 2);
        j["h"] = h;
        against = "successive differences";
    }
    j["mode"] = "images";
    j["images"] = paths;
    j["against"] = against;
    j["channels"] = channels;
    return j;
}

// The ray integral of the analytic field is computed to this error per channel (analytic_field.h): 1/300 of the
// finest default level's RMSE (builtin:grid-32 from grid-4: 3.0e-4 measured, docs/verification.md), so that it moves
// the observed orders by under 0.01.
constexpr double kAnalyticTolerance = 1e-6;

// --refine mesh: builtin:grid-N refined 1:8 per level, each measured against the ray integral of its analytic field.
nlohmann::json verify_mesh(const VerifyArgs& a, const Expectation& ex)
{
    const int n0 = builtin_grid_cubes(a.scene.input.path);
    if (n0 == 0)
        throw InputError(a.scene.input.path,
                         "--refine mesh refines builtin:grid-N (N cubes along each axis, doubled "
                         "at each level), whose field is analytic");
    if (a.levels < 3 || a.levels > 12 || (int64_t(n0) << (a.levels - 1)) > kBuiltinGridMaxCubes)
        throw InputError(a.scene.input.path, "--refine mesh: " + std::to_string(a.levels) + " levels from " +
                                                 std::to_string(n0) + " cubes pass " +
                                                 std::to_string(kBuiltinGridMaxCubes) + " (3 levels at least)");
    // One transfer function for every level: the default over the analytic field's range, [0, 1], unless given.
    SceneOptions so = a.scene;
    const Bounds box{glm::dvec3(-1.0), glm::dvec3(1.0)};
    if (so.tf_path.empty() && !so.tf) so.tf = default_transfer_function(Range{0.0, 1.0}, glm::length(box.extent()));
    std::vector<double> h;
    std::vector<ErrorMeasures> e;
    nlohmann::json levels = nlohmann::json::array();
    Image exact;
    for (int i = 0; i < a.levels; ++i) {
        const int n = n0 << i;
        so.input.path = "builtin:grid-" + std::to_string(n);
        const Scene s = setup_scene(so);
        if (i == 0)
            exact = render_analytic(builtin_grid_field, box, s.tf, s.camera, s.width, s.height, kAnalyticTolerance);
        const AlgoResult r = run_algorithm(s, a.algo, a.algo_options);
        h.push_back(2.0 / double(n));
        e.push_back(measure_errors(r.image, exact));
        levels.push_back({{"h", h.back()},
                          {"cubes", n},
                          {"tetrahedra", s.mesh().tets.size()},
                          {"rmse", e.back().rmse},
                          {"max_abs", e.back().max_abs},
                          {"ms", r.ms}});
    }
    nlohmann::json j = orders_json(h, e, ex.rmse, ex.max_abs, a.algo + " --refine mesh");
    j["levels"] = levels;
    j["analytic_tolerance"] = kAnalyticTolerance;
    return j;
}

// uvr renders `algo` at each level and measures it against the reference.
nlohmann::json verify_renders(const VerifyArgs& a)
{
    if (a.algo.empty()) throw InputError("", "--algo names the renderer whose order is verified");
    if (a.refine.empty()) throw InputError("", "--refine says what is refined: step, table or mesh");
    if (a.refine == "mesh") {
        nlohmann::json j = verify_mesh(a, expected_order(a.algo, a.refine, a.algo_options));
        j["mode"] = "render";
        j["input"] = a.scene.input.path;
        j["algo"] = a.algo;
        j["refine"] = a.refine;
        j["isolate"] = false;
        j["derivation"] = expected_order(a.algo, a.refine, a.algo_options).derivation;
        return j;
    }
    Scene s = setup_scene(a.scene);
    check_algorithm_scene(s, a.algo);
    const Expectation ex = expected_order(a.algo, a.refine, a.algo_options);
    const std::vector<double> h = refinement(a, s);
    const std::vector<AlgoOptions> opts = level_options(a, s, h);
    const Image ref = run_algorithm(s, "reference", a.algo_options).image;
    std::vector<ErrorMeasures> e;
    nlohmann::json levels = nlohmann::json::array();
    for (std::size_t i = 0; i < h.size(); ++i) {
        const AlgoResult r = run_algorithm(s, a.algo, opts[i]);
        e.push_back(measure_errors(r.image, ref));
        nlohmann::json l = {{"h", h[i]}, {"rmse", e.back().rmse}, {"max_abs", e.back().max_abs}, {"ms", r.ms}};
        l[a.refine == "step" ? "step" : "table_size"] = a.refine == "step" ? opts[i].step : double(opts[i].table_size);
        levels.push_back(l);
    }
    nlohmann::json j = orders_json(h, e, ex.rmse, ex.max_abs, a.algo + " --refine " + a.refine);
    j["mode"] = "render";
    j["input"] = a.scene.input.path;
    j["algo"] = a.algo;
    j["refine"] = a.refine;
    j["isolate"] = a.isolate;
    j["derivation"] = ex.derivation;
    j["levels"] = levels;
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
    add_algo_options(*cmd, a->algo_options, false);
    cmd->add_option("--algo", a->algo, "The renderer: raycast, havs or vicp (and reference with --refine mesh)");
    cmd->add_option("--refine", a->refine,
                    "What is refined: step (the ray caster's sampling distance) | table (the pre-integration "
                    "table's size n, h = 1/n) | mesh (builtin:grid-N, against its analytic field's integral)");
    cmd->add_option("--levels", a->levels, "Levels, each halving h")->capture_default_str();
    cmd->add_option("--from", a->from,
                    "The coarsest level: the step in world units (default twice the default "
                    "step), or the table size (default 16)");
    cmd->add_flag("--isolate", a->isolate,
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
        if (!a->images.empty() && (!a->algo.empty() || !a->refine.empty()))
            throw InputError("", "--images verifies images made elsewhere: --algo and --refine are for renders");
        if (a->images.empty() && (std::isfinite(a->expected) || !a->h.empty() || !a->reference.empty()))
            throw InputError("",
                             "--expected, --h and --reference go with --images (a render's expected order is "
                             "derived: docs/verification.md)");
        const nlohmann::json j = a->images.empty() ? verify_renders(*a) : verify_images(*a);
        if (!a->report.empty()) write_report(a->report, j);
        if (a->json)
            std::printf("%s\n", j.dump(1).c_str());
        else
            print_summary(j);
    });
}

}  // namespace uvr::cli
