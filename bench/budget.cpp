// `uvr budget`'s computation (docs/spec.md §7, docs/budget.md): the baseline with every switch exact, one run per
// factor, the total, each measured against the reference; the command is bench/cmd_budget.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>
#include <tbb/parallel_invoke.h>

#include "bench/algorithms.h"
#include "bench/budget.h"
#include "bench/progress.h"
#include "bench/report.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

// The switches a run sets, as the JSON records them (the test of "only that switch differs" reads them), and the key
// by which a run already rendered is found again (BudgetRunCache): every option a budget's runs differ by.
nlohmann::json switches_json(const std::string& algo, const AlgoOptions& o)
{
    nlohmann::json j = {{"segment", o.segment},
                        {"table_size", o.table_size},
                        {"table_format", o.table_format},
                        {"interpolation", o.interpolation},
                        {"coverage", o.coverage},
                        {"threshold", o.threshold},
                        {"backend", o.backend}};
    if (algo == "havs") {
        j["k"] = k_json(o.k);
        j["ties"] = o.ties;
    }
    if (algo == "vicp") j["order"] = o.order;
    if (o.parts > 1) {
        j["parts"] = o.parts;
        j["partition"] = o.partition;
    }
    if (algo == "raycast") {
        j["step"] = o.step;
        j["preintegrate"] = o.preintegrate;
        j["volume_format"] = o.volume_format;
        j.erase("coverage");  // the ray caster has no exact-coverage variant (docs/budget.md)
    }
    return j;
}

// docs/spec.md §4's RMSE and largest error over the pixels whose `mask` is 0 (all four channels), and their count.
nlohmann::json measures_outside(const Image& image, const Image& ref, const std::vector<uint32_t>& mask)
{
    double sum = 0.0, largest = 0.0;
    std::size_t pixels = 0;
    for (std::size_t p = 0; p < mask.size(); ++p) {
        if (mask[p]) continue;
        ++pixels;
        for (int c = 0; c < 4; ++c) {
            const double d = double(image.rgba[4 * p + std::size_t(c)]) - double(ref.rgba[4 * p + std::size_t(c)]);
            sum += d * d;
            largest = std::max(largest, std::abs(d));
        }
    }
    return {{"rmse", pixels ? std::sqrt(sum / (4.0 * double(pixels))) : 0.0}, {"max_abs", largest}, {"pixels", pixels}};
}

// A per-pixel count as an image (.npy): the count in red, alpha 1, as `uvr render --diagnostics` writes them.
Image count_image(const std::vector<uint32_t>& counts, int width, int height)
{
    Image im(width, height);
    for (std::size_t p = 0; p < counts.size(); ++p) {
        im.rgba[4 * p] = float(counts[p]);
        im.rgba[4 * p + 3] = 1.0f;
    }
    return im;
}

// One run of a budget: its name (baseline, a factor's, total) and options.
struct Run {
    std::string name;
    AlgoOptions o;
};

// A budget already written to `dir` for these runs (uvr sweep --budget resuming): its budget.json when it parses, is
// for this algorithm and image size, and every run in it has the switches of `runs` and its image on disk; its runs
// then join `cache`, so that later budgets copy them as they would have.
std::optional<nlohmann::json> finished_budget(const std::string& dir, const std::string& algo, const Scene& s,
                                              const std::vector<Run>& runs, BudgetRunCache& cache)
{
    nlohmann::json b;
    try {
        if (!std::filesystem::exists(dir + "/budget.json")) return std::nullopt;
        b = nlohmann::json::parse(read_file_bytes(dir + "/budget.json"));
        if (b.value("algo", "") != algo || b.value("width", -1) != s.width || b.value("height", -1) != s.height)
            return std::nullopt;
        for (const Run& r : runs) {
            const nlohmann::json& j =
                r.name == "baseline" || r.name == "total" ? b.at(r.name) : b.at("factors").at(r.name);
            if (j.at("switches") != switches_json(algo, r.o) ||
                !std::filesystem::exists(dir + "/" + j.at("image").get<std::string>()))
                return std::nullopt;
        }
    } catch (const std::exception&) {
        return std::nullopt;  // a damaged or partial report is made again
    }
    for (const Run& r : runs) {
        const nlohmann::json& j = r.name == "baseline" || r.name == "total" ? b[r.name] : b["factors"][r.name];
        cache.runs.try_emplace(j["switches"].dump(), dir + "/runs/" + r.name, j);
    }
    return b;
}

}  // namespace

namespace {

// The switches of the factors every algorithm has, set on a run (the baseline's options) to the user's values.
void set_table(AlgoOptions& run, const AlgoOptions& user)
{
    run.segment = user.segment;
    run.table_size = user.table_size;
    run.table_format = user.table_format;
}
void set_interpolation(AlgoOptions& run, const AlgoOptions& user)
{
    run.interpolation = user.interpolation;
}
void set_threshold(AlgoOptions& run, const AlgoOptions& user)
{
    run.threshold = user.threshold;
}

// The ray caster's factors (docs/spec.md §7): `step` is the baseline itself, every other switch exact at the user's
// step, against the reference; each other factor sets one switch back at that step and is measured against it.
std::vector<BudgetFactor> raycast_factors()
{
    std::vector<BudgetFactor> factors = {
        {"step", "the step: the ray samples the volume every step and takes the scalar as linear between two samples",
         [](AlgoOptions& run, const AlgoOptions& user) { run.step = user.step; }},
        {"table",
         "the classification: post-classified samples (each step's colour from the transfer function at one "
         "sample) or the pre-integrated table, instead of each segment between two samples integrated exactly",
         [](AlgoOptions& run, const AlgoOptions& user) {
             set_table(run, user);
             run.preintegrate = user.preintegrate;
         }},
        {"texture",
         "the volume's texture: texels kept in the data's own format and filtered as the GPU filters that format "
         "(8-bit data with 8-bit weights on llvmpipe) instead of as float",
         [](AlgoOptions& run, const AlgoOptions& user) { run.volume_format = user.volume_format; }},
        {"interpolation",
         "the published passes: each ray's entry and exit from the box's faces as the rasterizer interpolates "
         "their texture coordinates, instead of the ray against the box in double",
         set_interpolation},
        {"termination", "early termination: the march stops once the opacity passes the threshold", set_threshold}};
    for (BudgetFactor& f : factors)
        if (f.name != "step") f.against = BudgetAgainst::step;
    return factors;
}

// HAVS's and VICP's: the sort, the table, the rasterizer's interpolation and coverage, sort-last's parts where the
// user asks for them, and early termination.
std::vector<BudgetFactor> projection_factors(const std::string& algo, const AlgoOptions& user)
{
    std::vector<BudgetFactor> f;
    if (algo == "havs")
        f.push_back({"sort",
                     "the k-buffer of k entries: fragments the object-space face sort leaves more than k - 1 "
                     "places out of order are composited out of order, and fragments at one distance in the "
                     "k-buffer's order (at a seam whose two faces carry different scalars, not the ray's)",
                     [](AlgoOptions& run, const AlgoOptions& user) {
                         run.k = user.k;
                         run.ties = user.ties;
                     }});
    if (algo == "vicp")
        f.push_back({"sort",
                     "the cell order: cells composited out of visibility order (MPVONC's broken cycles, or "
                     "the centroid order's mistakes)",
                     [](AlgoOptions& run, const AlgoOptions& user) { run.order = user.order; }});
    f.push_back({"table",
                 "the pre-integrated table: the segment's colour looked up, filtered, from a table of finite "
                 "size instead of integrated exactly",
                 set_table});
    f.push_back({"interpolation",
                 "the rasterizer's interpolation: the fragment's values from the published interpolated "
                 "varyings (float, perspective-correct) instead of computed in double from the pixel's "
                 "ray",
                 set_interpolation});
    f.push_back({"coverage",
                 "the rasterizer's coverage: pixels chosen by the snapped (fixed-point) triangle instead of "
                 "by the ray through the pixel centre crossing the primitive",
                 [](AlgoOptions& run, const AlgoOptions& user) { run.coverage = user.coverage; }});
    if (user.parts > 1)
        f.push_back({"partition",
                     "sort-last compositing: the mesh in parts, each rendered on its own and the images blended "
                     "back to front in the order of the parts' boxes, instead of the whole mesh in one pass",
                     [](AlgoOptions& run, const AlgoOptions& u) {
                         run.parts = u.parts;
                         run.partition = u.partition;
                     }});
    f.push_back({"termination", "early termination: a pixel stops compositing once its opacity passes the threshold",
                 set_threshold});
    return f;
}

}  // namespace

std::vector<BudgetFactor> budget_factors(const std::string& algo, const AlgoOptions& user)
{
    return algo == "raycast" ? raycast_factors() : projection_factors(algo, user);
}

AlgoOptions budget_baseline(const std::string& algo, const AlgoOptions& user)
{
    AlgoOptions b = user;
    b.backend = "emu";  // exact segments and coverage are the emulation's only
    b.segment = "exact";
    b.interpolation = "exact";
    b.coverage = "exact";
    b.threshold = 1.0;
    b.parts = 1;           // the whole mesh in one pass
    if (algo == "havs") {  // the exact sort: every fragment held, at one distance the cell the ray leaves first
        b.k = gpu::kEveryFragment;
        b.ties = "facing";
    }
    if (algo == "vicp") b.order = "mpvonc";
    if (algo == "raycast") {
        b.coverage = user.coverage;  // no exact variant
        b.preintegrate = true;       // each segment between two samples integrated exactly
        b.volume_format = "f32";     // texels and their filtering in float
        b.step = user.step;          // the march at the user's step: the `step` factor's run
    }
    return b;
}

// The user's options with each per-algorithm default filled in, so that the JSON says what ran.
static AlgoOptions budget_user_options(const Scene& s, const std::string& algo, AlgoOptions user)
{
    if (user.interpolation.empty()) user.interpolation = "gpu";
    if (user.threshold < 0.0) user.threshold = algo == "havs" ? 0.99 : algo == "raycast" ? 0.95 : 1.0;
    if (algo == "raycast" && user.step <= 0.0) user.step = gpu::default_raycast_step(s.volume());
    return user;
}

namespace {

// Every run's options, checked before anything is written: the baseline, one run per factor, the total. A run that GL
// can draw uses it when asked (the bits are the emulation's): the ones with the table and the rasterizer's coverage.
std::vector<Run> budget_runs(const std::string& algo, const AlgoOptions& user, const AlgoOptions& base,
                             const std::vector<BudgetFactor>& factors)
{
    std::vector<Run> runs{{"baseline", base}};
    for (const BudgetFactor& f : factors) {
        AlgoOptions o = base;
        f.apply(o, user);
        runs.push_back({f.name, o});
    }
    runs.push_back({"total", user});
    for (Run& r : runs) {
        if (user.backend == "gl" && r.o.segment != "exact" && r.o.coverage != "exact") r.o.backend = "gl";
        // VICP's published program has no varyings where the rasterizer makes no fragment: its interpolation factor
        // keeps the rasterizer's coverage (docs/budget.md, "Decisions").
        if (algo == "vicp" && r.name == "interpolation" && r.o.interpolation == "gpu") r.o.coverage = "gpu";
        find_algorithm(algo).check_options(r.o);
    }
    return runs;
}

// A run whose switches an earlier run had (a factor whose switch already has the baseline's value: VICP's MPVONC, a
// threshold of 1; or a run of an earlier budget in the cache): its files copied under this run's name, its JSON
// pointing at them.
nlohmann::json copied_run(const std::string& dir, const Run& r, const std::string& from_base, nlohmann::json j)
{
    for (const char* suffix : {".npy", ".png", "-error.png", "-wrong_exits.npy"}) {
        const std::string from = from_base + suffix, to = dir + "/runs/" + r.name + suffix;
        if (std::filesystem::exists(from) && from != to)
            std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing);
    }
    j["image"] = "runs/" + r.name + ".npy";
    j["error_map"] = "runs/" + r.name + "-error.png";
    if (j.contains("without_wrong_exits")) j["without_wrong_exits"]["mask"] = "runs/" + r.name + "-wrong_exits.npy";
    j["same_as"] = from_base.substr(from_base.find_last_of('/') + 1);
    j["ms"] = 0.0;
    return j;
}

// A run's measures against `against` (the reference, or the step run), and its error map under DIR/runs/.
nlohmann::json measured(const std::string& dir, const std::string& name, const Image& image, const Image& against)
{
    write_png_rgb8(dir + "/runs/" + name + "-error.png", image.width, image.height,
                   error_heat_map(pixel_errors(image, against)));
    return measures_json(measure_errors(image, against));
}

// A run rendered: its image, PNG and error map under DIR/runs/, its measures against `against`.
nlohmann::json rendered_run(const Scene& s, const std::string& algo, const std::string& dir, const Run& r,
                            const Image& against)
{
    const AlgoResult res = run_algorithm(s, algo, r.o);
    // The files are independent: written side by side (a 512² run's three took as long as its render's third).
    nlohmann::json j;
    tbb::parallel_invoke([&] { write_image(dir + "/runs/" + r.name + ".npy", res.image); },
                         [&] { write_image(dir + "/runs/" + r.name + ".png", res.image); },
                         [&] { j = measured(dir, r.name, res.image, against); });
    j["switches"] = switches_json(algo, r.o);
    j["image"] = "runs/" + r.name + ".npy";
    j["error_map"] = "runs/" + r.name + "-error.png";
    j["ms"] = res.ms;
    j["stats"] = res.stats;
    // VICP's published program: its interpolation's error apart from its wrong exits (docs/vicp.md, "The published
    // pipeline": the exits picked wrongly beside face edges, and the perspective), with the mask kept.
    if (!res.wrong_exits.empty()) {
        const std::string mask = "runs/" + r.name + "-wrong_exits.npy";
        write_image(dir + "/" + mask, count_image(res.wrong_exits, s.width, s.height));
        j["without_wrong_exits"] = measures_outside(res.image, against, res.wrong_exits);
        j["without_wrong_exits"]["mask"] = mask;
    }
    return j;
}

// Whether the ray caster's early termination at `threshold` would stop no ray of the baseline's march: its run is then
// the baseline's, bit for bit. The march stops a ray once its opacity passes the threshold (alpha > threshold, in
// float as the march compares), and a ray's opacity never falls as it composites, so a ray whose final opacity does
// not pass it never stopped.
bool terminates_no_ray(const std::string& dir, const nlohmann::json& baseline, double threshold)
{
    const Image b = read_npy(dir + "/" + baseline.at("image").get<std::string>());
    const float t = float(threshold);  // the march's own (RaycastOptions::threshold)
    for (std::size_t p = 3; p < b.rgba.size(); p += 4)
        if (b.rgba[p] > t) return false;
    return true;
}

// One run of the budget, measured against `against` (named `against_name` in its JSON): copied where an earlier run
// had its switches, and measured again where that run was measured against another image; the ray caster's
// termination copied from the baseline where it stops no ray; rendered otherwise.
nlohmann::json budget_run(const Scene& s, const std::string& algo, const std::string& dir, const Run& r,
                          const Image& against, const std::string& against_name, const nlohmann::json& out,
                          BudgetRunCache& rendered)
{
    const std::string key = switches_json(algo, r.o).dump();
    nlohmann::json j;
    if (const auto same = rendered.runs.find(key); same != rendered.runs.end()) {
        j = copied_run(dir, r, same->second.first, same->second.second);
    } else if (algo == "raycast" && r.name == "termination" &&
               terminates_no_ray(dir, out["baseline"], r.o.threshold)) {
        j = copied_run(dir, r, dir + "/runs/baseline", out["baseline"]);
        j["switches"] = switches_json(algo, r.o);
        j["same_because"] = "no ray of the baseline passes the threshold, so early termination stops none";
    } else {
        j = rendered_run(s, algo, dir, r, against);
    }
    if (j.value("against", "reference") != against_name)
        j.update(measured(dir, r.name, read_npy(dir + "/runs/" + r.name + ".npy"), against));
    j["against"] = against_name;
    if (!j.contains("same_as") || j.contains("same_because")) rendered.runs[key] = {dir + "/runs/" + r.name, j};
    return j;
}

// The baseline's check, budget.json, the chart and the page.
void finish_budget(const std::string& algo, const std::string& dir, nlohmann::json& out)
{
    const nlohmann::json& b = out["baseline"];
    if (algo == "raycast") {
        // The baseline is the step run: its error is the march's, which no finer run inside the budget checks; its
        // convergence is uvr verify's (docs/verification.md).
        out["baseline_ok"] = true;
        out["step_convergence"] = "uvr verify VOLUME --algo raycast --refine step --isolate --preintegrate";
        out["not_split"] = {{"coverage", "the published box passes have no exact-coverage variant (docs/budget.md)"}};
    } else {
        out["baseline_ok"] = b["max_abs"].get<double>() <= kBudgetBaselineMax;
    }
    write_file_atomically(dir + "/budget.json", out.dump(1) + "\n");
    write_budget_chart(dir, out);
    write_budget_page(dir, out);
}

}  // namespace

nlohmann::json run_budget(const Scene& s, const std::string& algo, const AlgoOptions& options, const std::string& dir,
                          const std::string& mesh_name, BudgetRunCache* cache, bool resume)
{
    if (algo != "havs" && algo != "vicp" && algo != "raycast")
        throw InputError("", "--algo must be havs, vicp or raycast");
    check_algorithm_scene(s, algo);
    const AlgoOptions user = budget_user_options(s, algo, options);
    const AlgoOptions base = budget_baseline(algo, user);
    const std::vector<BudgetFactor> factors = budget_factors(algo, user);
    const std::vector<Run> runs = budget_runs(algo, user, base, factors);
    BudgetRunCache local;
    BudgetRunCache& rendered = cache ? *cache : local;
    if (resume) {
        if (const std::optional<nlohmann::json> done = finished_budget(dir, algo, s, runs, rendered)) return *done;
    }
    std::error_code ec;
    std::filesystem::create_directories(dir + "/runs", ec);
    if (ec) throw InputError(dir, "cannot create the report directory: " + ec.message());

    ProgressBar progress("budget");
    const AlgoResult ref = run_algorithm(s, "reference", user);
    write_image(dir + "/runs/reference.npy", ref.image);
    write_image(dir + "/runs/reference.png", ref.image);
    nlohmann::json out = {{"algo", algo},
                          {"mesh", mesh_name},
                          {"field", s.field_name()},
                          {"width", s.width},
                          {"height", s.height},
                          {"reference", {{"image", "runs/reference.npy"}, {"cached", ref.cached}}},
                          {"factors", nlohmann::json::object()},
                          {"factor_order", nlohmann::json::array()}};  // the order the page and the chart show
    for (const BudgetFactor& f : factors) out["factor_order"].push_back(f.name);
    Image step_image;  // the step run's (the ray caster's baseline), for the factors measured against it
    for (std::size_t i = 0; i < runs.size(); ++i) {
        progress.update(double(i) / double(runs.size()));
        const Run& r = runs[i];
        const BudgetFactor* factor = nullptr;
        for (const BudgetFactor& f : factors)
            if (f.name == r.name) factor = &f;
        const bool against_step = factor && factor->against == BudgetAgainst::step;
        nlohmann::json j = budget_run(s, algo, dir, r, against_step ? step_image : ref.image,
                                      against_step ? "step" : "reference", out, rendered);
        if (r.name == "baseline" && algo == "raycast") step_image = read_npy(dir + "/runs/baseline.npy");
        if (r.name == "baseline" || r.name == "total") {
            out[r.name] = std::move(j);
            continue;
        }
        j["what"] = factor->what;
        if (algo == "vicp" && r.name == "interpolation" && r.o.coverage != base.coverage)
            j["with"] = nlohmann::json::array({"coverage"});
        out["factors"][r.name] = std::move(j);
    }
    progress.finish();
    finish_budget(algo, dir, out);
    return out;
}

nlohmann::json budget_summary(const nlohmann::json& b, const std::string& page)
{
    nlohmann::json row = {{"page", page},
                          {"baseline_ok", b["baseline_ok"]},
                          {"baseline", b["baseline"]["rmse"]},
                          {"total", b["total"]["rmse"]},
                          {"factors", nlohmann::json::object()}};
    std::string dominant;
    for (const auto& n : b["factor_order"]) {
        const std::string name = n.get<std::string>();
        const double e = b["factors"][name]["rmse"].get<double>();
        row["factors"][name] = e;
        if (dominant.empty() || e > row["factors"][dominant].get<double>()) dominant = name;
    }
    row["dominant"] = dominant;
    return row;
}

}  // namespace uvr::cli
