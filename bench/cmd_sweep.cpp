// `uvr sweep MESH --k LIST [--views N] [--table-sizes LIST] --report DIR`: HAVS's error against the k-buffer size k,
// per view, split into what the sort costs (exact segment integration) and what the table costs (table against exact
// at the largest k), with the ordering-error counts; optionally the table's error against its size; CSV and JSON of
// every number, plots, and an HTML page. Each run leaves its image (.npy) and its numbers (.json) under DIR/runs/,
// written atomically, so an interrupted sweep resumes from what is on disk and every number can be checked against
// the images. The exact-segment runs use the emulation whatever --backend says (a GPU has only the table; the GL frame
// is bit-identical to the emulated one, docs/gl-backend.md); the table runs use --backend.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/algorithms.h"
#include "bench/budget.h"
#include "bench/commands.h"
#include "bench/progress.h"
#include "bench/report.h"
#include "bench/runs_parallel.h"
#include "bench/sweep_step.h"
#include "distributed/mpi_runtime.h"
#include "gpu/havs/gl_havs.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

struct SweepArgs {
    SceneOptions scene;
    AlgoOptions algo_options;
    std::string ks = "1,2,4,6,8,12,16";
    std::string steps;  // regular grids: the ray caster's steps (empty: the default list)
    std::string table_sizes;  // empty: no table-size sweep
    int views = 1;
    std::string report;
    bool budget = false;  // HAVS: the error budget at every k (uvr budget's runs, shared across k)
    bool json = false;
};

struct View {
    int index;
    double azimuth, elevation;
};

// View 0 is the scene's own camera (the default, or --view/--camera); the others orbit the default camera evenly in
// azimuth, alternating 25 degrees above and below.
std::vector<View> sweep_views(int n)
{
    std::vector<View> v{{0, 0.0, 0.0}};
    for (int i = 1; i < n; ++i) v.push_back({i, 360.0 * i / n, i % 2 ? 25.0 : -25.0});
    return v;
}

std::vector<int> parse_int_list(const std::string& option, const std::string& list, int lo, int hi)
{
    std::vector<int> out;
    for (const auto& x : split_list(list)) {
        char* end = nullptr;
        const long v = std::strtol(x.c_str(), &end, 10);
        if (*end || v < lo || v > hi)
            throw InputError("", option + " takes integers from " + std::to_string(lo) + " to " + std::to_string(hi) +
                                     ", found '" + x + "'");
        out.push_back(int(v));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

bool load_json(const std::string& path, nlohmann::json& j)
{
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return false;
    try {
        j = nlohmann::json::parse(read_file_bytes(path));
        return true;
    } catch (const std::exception&) {
        return false;  // a damaged run file is recomputed
    }
}

// A run finished by an earlier sweep: both of its files under DIR/runs/ (`base` is their path without extension).
bool stored_run(const std::string& base, nlohmann::json& row)
{
    std::error_code ec;
    return load_json(base + ".json", row) && std::filesystem::exists(base + ".npy", ec);
}

Camera view_camera(const Scene& s, const Camera& scene_camera, const View& v)
{
    return v.index == 0 ? scene_camera
                        : default_camera(mesh_bounds(s.mesh()), double(s.width) / s.height, v.azimuth, v.elevation);
}

// The runs of a view, named as their files under DIR/runs/: the reference, HAVS at k with exact segments ("exact",
// the emulation's alone) or the table ("table", --backend), and the table of size n at the largest k.
std::string reference_tag(const View& v)
{
    return "v" + std::to_string(v.index) + "-reference";
}
std::string k_tag(const View& v, int k, const std::string& mode)
{
    return "v" + std::to_string(v.index) + "-k" + std::to_string(k) + "-" + mode;
}
std::string table_tag(const View& v, int kmax, int n)
{
    return "v" + std::to_string(v.index) + "-k" + std::to_string(kmax) + "-table" + std::to_string(n);
}
AlgoOptions k_options(const SweepArgs& a, int k, const std::string& mode)
{
    AlgoOptions o = a.algo_options;
    o.k = k;
    o.segment = mode;
    if (mode == "exact") o.backend = "emu";
    return o;
}
AlgoOptions table_options(const SweepArgs& a, int kmax, int n)
{
    AlgoOptions o = a.algo_options;
    o.k = kmax;
    o.table_size = n;
    return o;
}

// What a mesh sweep runs over: the k list and the table sizes.
struct SweepLists {
    std::vector<int> ks, table_sizes;
};

// Every run of a mesh sweep, in the order one process renders them.
std::vector<PlannedRun> planned_runs(const SweepArgs& a, const Scene& s, const SweepLists& l)
{
    std::vector<PlannedRun> runs;
    for (const View& v : sweep_views(a.views)) {
        const Camera cam = view_camera(s, s.camera, v);
        runs.push_back({reference_tag(v), "reference", cam, a.algo_options});
        for (const std::string mode : {"exact", "table"})
            for (int k : l.ks) runs.push_back({k_tag(v, k, mode), "havs", cam, k_options(a, k, mode)});
        for (int n : l.table_sizes)
            runs.push_back({table_tag(v, l.ks.back(), n), "havs", cam, table_options(a, l.ks.back(), n)});
    }
    return runs;
}

// A regular grid sweeps the ray caster's step (bench/sweep_step.cpp); prints its rows unless --json.
void sweep_volume(const SweepArgs& a, Scene& s, const std::vector<double>& steps, bool k_given)
{
    if (k_given)
        throw InputError(s.volume().source,
                         "is a regular grid: --k sweeps HAVS, which takes a tetrahedral mesh (--step "
                         "sweeps the ray caster)");
    raycast_options(a.algo_options);  // reject bad options before any work
    const nlohmann::json out = run_step_sweep(s, a.algo_options, steps, a.views, a.report, a.budget);
    if (a.json) {
        std::printf("%s\n", out.dump(1).c_str());
        return;
    }
    for (const auto& r : out["rows"])
        std::printf("view %d, %s, step %g: RMSE %.3g, max %.3g, visible %.4f\n", r["view"].get<int>(),
                    r["classification"].get<std::string>().c_str(), r["step"].get<double>(), r["rmse"].get<double>(),
                    r["max_abs"].get<double>(), r["visible_fraction"].get<double>());
    std::printf("report: %s/index.html\n", a.report.c_str());
}

// The k list, checked with every other option before any work: on GL, a k its draw buffers cannot hold is refused
// now, not after the smaller ones have run.
std::vector<int> checked_k_list(const SweepArgs& a)
{
    const std::vector<int> ks = parse_int_list("--k", a.ks, 1, std::numeric_limits<int>::max());
    if (ks.empty()) throw InputError("", "--k is empty");
    havs_options(a.algo_options);
    if (a.algo_options.backend == "gl") {
        const gpu::GlContext ctx(gpu::parse_gl_platform(a.algo_options.gl));
        const int kmax = gpu::GlHavsRenderer::max_k(ctx.info(), false);
        if (ks.back() > kmax)
            throw InputError("", "--k must be between 1 and " + std::to_string(kmax) + " with --backend gl on " +
                                     ctx.info().renderer + " (" + std::to_string(ctx.info().max_draw_buffers) +
                                     " draw buffers); the list has " + std::to_string(ks.back()));
    }
    return ks;
}

// One sweep over a mesh: its runs are files under DIR/runs/ (a run already there is taken from disk), its numbers
// the JSON `out`.
class KSweep {
public:
    // `rendered`: runs already rendered (by the ranks under mpirun), by tag; the others are rendered here.
    KSweep(const SweepArgs& a, Scene& s, const SweepLists& l, std::map<std::string, AlgoResult> rendered = {})
        : a_(a),
          s_(s),
          ks_(l.ks),
          table_sizes_(l.table_sizes),
          runs_(a.report + "/runs"),
          rendered_(std::move(rendered)),
          bar_("sweep")
    {
    }

    nlohmann::json run()
    {
        std::error_code ec;
        std::filesystem::create_directories(runs_, ec);
        if (ec) throw InputError(a_.report, "cannot create the report directory: " + ec.message());
        const auto views = sweep_views(a_.views);
        out_ = {{"mesh", a_.scene.input.path},
                {"field", s_.field_name()},
                {"width", s_.width},
                {"height", s_.height},
                {"k", ks_},
                {"table_sizes", table_sizes_},
                {"backend", a_.algo_options.backend}};
        for (const char* list : {"rows", "table_rows", "views", "budget_rows"}) out_[list] = nlohmann::json::array();
        total_ = views.size() * (ks_.size() * 2 + table_sizes_.size());
        const Camera scene_camera = s_.camera;
        double floor_sum = 0.0;
        for (const View& v : views) {
            s_.camera = view_camera(s_, scene_camera, v);
            floor_sum += sweep_view(v);
        }
        bar_.finish();
        out_["table_floor_rmse"] = floor_sum / double(views.size());
        out_["resumed_runs"] = resumed_;
        return out_;
    }

private:
    const SweepArgs& a_;
    Scene& s_;
    const std::vector<int> ks_, table_sizes_;
    const std::string runs_;
    std::map<std::string, AlgoResult> rendered_;
    ProgressBar bar_;
    nlohmann::json out_;
    std::size_t total_ = 0, done_ = 0, resumed_ = 0;

    void step() { bar_.update(double(++done_) / double(total_)); }

    AlgoResult render(const std::string& tag, const std::string& algo, const AlgoOptions& o)
    {
        const auto it = rendered_.find(tag);
        if (it == rendered_.end()) return run_algorithm(s_, algo, o);
        AlgoResult r = std::move(it->second);
        rendered_.erase(it);
        return r;
    }

    // One HAVS run: its row from disk when both files are there, else rendered, measured and stored.
    nlohmann::json havs_run(const std::string& tag, const AlgoOptions& o, const Image& against, nlohmann::json row)
    {
        nlohmann::json stored;
        const std::string base = runs_ + "/" + tag;
        if (stored_run(base, stored)) {
            ++resumed_;
            return stored;
        }
        const AlgoResult r = render(tag, "havs", o);
        const ErrorMeasures e = measure_errors(r.image, against);
        row["backend"] = o.backend;
        row["rmse"] = e.rmse;
        row["max_abs"] = e.max_abs;
        row["psnr"] = std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json(nullptr);
        row["visible_fraction"] = e.visible_fraction;
        if (!r.ordering_errors.empty()) {
            std::size_t err_pixels = 0;
            for (uint32_t c : r.ordering_errors) err_pixels += c ? 1 : 0;
            row["ordering_errors"] = r.stats["ordering_errors"];
            row["ordering_error_pixel_fraction"] = double(err_pixels) / double(r.ordering_errors.size());
            row["max_fragments_per_pixel"] = r.stats["max_fragments_per_pixel"];
        }
        row["ms"] = r.ms;
        write_npy(base + ".npy", r.image);
        write_file_atomically(base + ".json", row.dump() + "\n");
        return row;
    }

    // Every k with exact segments (the sort's error; the emulation's alone) and with the table (--backend); returns
    // the view's JSON with the smallest k without visible error in each mode.
    nlohmann::json k_runs(const View& v, const Image& ref)
    {
        nlohmann::json vj = {{"view", v.index}, {"azimuth", v.azimuth}, {"elevation", v.elevation}};
        for (const std::string mode : {"exact", "table"}) {
            int smallest = -1;
            for (int k : ks_) {
                const nlohmann::json row = havs_run(k_tag(v, k, mode), k_options(a_, k, mode), ref,
                                                    {{"view", v.index}, {"k", k}, {"mode", mode}});
                if (smallest < 0 && row["visible_fraction"].get<double>() == 0.0) smallest = k;
                out_["rows"].push_back(row);
                step();
            }
            vj["smallest_k_without_visible_error_" + mode] =
                smallest < 0 ? nlohmann::json(nullptr) : nlohmann::json(smallest);
        }
        return vj;
    }

    // One view: the reference, the k runs, the table sizes against exact at the largest k, the budget per k. Returns
    // the table's error floor (table against exact at the largest k).
    double sweep_view(const View& v)
    {
        const Image ref = render(reference_tag(v), "reference", a_.algo_options).image;
        write_npy(runs_ + "/" + reference_tag(v) + ".npy", ref);
        nlohmann::json vj = k_runs(v, ref);
        const int kmax = ks_.back();
        const Image top[2] = {read_npy(runs_ + "/" + k_tag(v, kmax, "exact") + ".npy"),
                              read_npy(runs_ + "/" + k_tag(v, kmax, "table") + ".npy")};
        for (int n : table_sizes_) {
            out_["table_rows"].push_back(havs_run(table_tag(v, kmax, n), table_options(a_, kmax, n), top[0],
                                                  {{"view", v.index}, {"k", kmax}, {"table_size", n}}));
            step();
        }
        const ErrorMeasures floor = measure_errors(top[1], top[0]);
        vj["table_floor_rmse"] = floor.rmse;
        vj["table_floor_max_abs"] = floor.max_abs;
        out_["views"].push_back(vj);
        if (a_.budget) budget_per_k(v);
        return floor.rmse;
    }

    // The budget at every k: the baseline and the factors that do not depend on k are rendered once a view (the
    // cache), the sort factor and the total once a k.
    void budget_per_k(const View& v)
    {
        BudgetRunCache cache;
        for (int k : ks_) {
            AlgoOptions o = a_.algo_options;
            o.k = k;
            const std::string page = "budget/v" + std::to_string(v.index) + "-k" + std::to_string(k);
            nlohmann::json row =
                budget_summary(run_budget(s_, "havs", o, a_.report + "/" + page, a_.scene.input.path, &cache, true),
                               page + "/index.html");
            row["view"] = v.index;
            row["k"] = k;
            out_["budget_rows"].push_back(row);
        }
    }
};

// sweep.csv: one line per run; a table-size run has mode "table-vs-exact" and its table size, and measures against
// the exact image at the largest k instead of the reference. Missing counts (a GL run without diagnostics) are empty.
void write_sweep_csv(const std::string& dir, const nlohmann::json& out)
{
    std::string csv =
        "view,k,mode,table_size,backend,rmse,max_abs,psnr,visible_fraction,ordering_errors,"
        "ordering_error_pixel_fraction,max_fragments_per_pixel,ms\n";
    auto field = [](const nlohmann::json& r, const char* key) {
        if (!r.contains(key) || r[key].is_null()) return std::string(r.contains(key) ? "inf" : "");
        char buf[64];
        if (r[key].is_number_unsigned() || r[key].is_number_integer())
            std::snprintf(buf, sizeof buf, "%lld", r[key].get<long long>());
        else
            std::snprintf(buf, sizeof buf, "%.9g", r[key].get<double>());
        return std::string(buf);
    };
    auto line = [&](const nlohmann::json& r, const std::string& mode, const std::string& table_size) {
        csv += field(r, "view") + "," + field(r, "k") + "," + mode + "," + table_size + "," +
               r["backend"].get<std::string>() + "," + field(r, "rmse") + "," + field(r, "max_abs") + "," +
               field(r, "psnr") + "," + field(r, "visible_fraction") + "," + field(r, "ordering_errors") + "," +
               field(r, "ordering_error_pixel_fraction") + "," + field(r, "max_fragments_per_pixel") + "," +
               field(r, "ms") + "\n";
    };
    for (const auto& r : out["rows"]) line(r, r["mode"].get<std::string>(), "");
    for (const auto& r : out["table_rows"]) line(r, "table-vs-exact", field(r, "table_size"));
    write_file_atomically(dir + "/sweep.csv", csv);
}

// The files of a finished sweep (JSON, CSV, plots, page) and its summary on stdout (or the JSON with --json).
void finish_sweep(const SweepArgs& a, const nlohmann::json& out)
{
    const std::string& dir = a.report;
    write_file_atomically(dir + "/sweep.json", out.dump(1) + "\n");
    write_sweep_csv(dir, out);
    // Plots by matplotlib (Debian's python3-matplotlib); without it the numbers still stand.
    const std::string plot =
        std::string("/usr/bin/python3 '") + UVR_SOURCE_DIR + "/bench/plots/sweep_plots.py' '" + dir + "' 2>&1";
    const bool plotted = std::system(plot.c_str()) == 0;
    if (!plotted) std::fprintf(stderr, "uvr: warning: plots not drawn (needs python3-matplotlib)\n");
    write_sweep_page(dir, out, plotted);
    if (a.json) {
        std::printf("%s\n", out.dump(1).c_str());
        return;
    }
    for (const auto& v : out["views"])
        std::printf("view %d (%g, %g): smallest k without visible error: sorting %s, total %s; table error RMSE %.3g\n",
                    v["view"].get<int>(), v["azimuth"].get<double>(), v["elevation"].get<double>(),
                    v["smallest_k_without_visible_error_exact"].dump().c_str(),
                    v["smallest_k_without_visible_error_table"].dump().c_str(), v["table_floor_rmse"].get<double>());
    std::printf("report: %s/index.html (%zu runs resumed from disk)\n", dir.c_str(),
                out["resumed_runs"].get<std::size_t>());
}

// A mesh sweep's lists, checked with every other option before any work.
SweepLists checked_lists(const SweepArgs& a)
{
    if (!a.steps.empty())
        throw InputError(a.scene.input.path,
                         "is a tetrahedral mesh: --step sweeps the ray caster, which renders "
                         "regular grids (use --k for HAVS)");
    return {checked_k_list(a), parse_int_list("--table-sizes", a.table_sizes, 2, 1024)};
}

// Under mpirun: every rank reads the mesh, the runs rank 0 finds missing under DIR/runs/ are dealt to the ranks, and
// rank 0 writes the report from their results, as one process writes it (the budget, with --budget, on rank 0).
void sweep_across_ranks(const SweepArgs& a)
{
    std::optional<Scene> s;
    SweepLists lists;
    mpi::on_every_rank([&] {
        s.emplace(setup_scene(a.scene));
        if (s->is_volume())
            throw InputError(a.scene.input.path,
                             "is a regular grid: under mpirun, uvr sweep spreads HAVS's runs "
                             "over the ranks (the ray caster's --step sweep runs in one process)");
        lists = checked_lists(a);
    });
    const std::vector<PlannedRun> runs = planned_runs(a, *s, lists);
    std::vector<char> wanted;
    nlohmann::json row;
    if (mpi::rank() == 0)
        for (const PlannedRun& r : runs) wanted.push_back(!stored_run(a.report + "/runs/" + r.tag, row));
    std::map<std::string, AlgoResult> rendered = render_across_ranks(*s, runs, wanted);
    mpi::on_every_rank([&] {
        if (mpi::rank() == 0) finish_sweep(a, KSweep(a, *s, lists, std::move(rendered)).run());
    });
}

}  // namespace

void register_sweep(CLI::App& app)
{
    auto* cmd = app.add_subcommand("sweep", "HAVS's error against the k-buffer size k (sorting and table error apart); "
                                            "on a regular grid, the ray caster's error against the step");
    auto a = std::make_shared<SweepArgs>();
    add_scene_options(*cmd, a->scene);
    add_algo_options(*cmd, a->algo_options, false);
    CLI::Option* k_option = cmd->add_option("--k", a->ks, "Comma-separated k values")->capture_default_str();
    cmd->add_option("--step", a->steps,
                    "Regular grids: comma-separated ray-casting steps in world units (default: 2, 1, 1/2 and 1/4 "
                    "times half the smallest spacing)");
    cmd->add_option("--table-sizes", a->table_sizes,
                    "Comma-separated table sizes: the table's error against exact at the largest k, per size");
    cmd->add_option("--views", a->views, "Number of views")->capture_default_str()->check(CLI::Range(1, 64));
    cmd->add_option("--report", a->report, "Directory for sweep.csv, sweep.json, plots, index.html")->required();
    cmd->add_flag("--budget", a->budget,
                  "The error budget (uvr budget) at every k (HAVS) or step (the ray caster) of every view: which "
                  "cause dominates as k grows or the step shrinks");
    cmd->add_flag("--json", a->json, "Print sweep.json's object on stdout");
    cmd->callback([a, k_option] {
        if (mpi::active()) return sweep_across_ranks(*a);
        const std::vector<double> steps = parse_step_list(a->steps);
        Scene s = setup_scene(a->scene);
        if (s.is_volume()) return sweep_volume(*a, s, steps, k_option->count() > 0);
        finish_sweep(*a, KSweep(*a, s, checked_lists(*a)).run());
    });
}

}  // namespace uvr::cli
