// `uvr sweep MESH --k LIST [--views N] --report DIR`: HAVS's error against the k-buffer size k, per view, split into
// what the sort costs (exact segment integration) and what the table costs (table against exact at the largest k),
// with the ordering-error counts; CSV and JSON of every number, plots, and an HTML page. Each (view, k, mode) result
// is a small JSON file under DIR/runs/, written atomically, so an interrupted sweep resumes from what is on disk.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/algorithms.h"
#include "bench/commands.h"
#include "bench/progress.h"
#include "bench/report.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

struct SweepArgs {
    SceneOptions scene;
    AlgoOptions algo_options;
    std::string ks = "1,2,4,6,8,12,16";
    int views = 1;
    std::string report;
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

}  // namespace

void register_sweep(CLI::App& app)
{
    auto* cmd = app.add_subcommand("sweep", "HAVS's error against the k-buffer size k (sorting and table error apart)");
    auto a = std::make_shared<SweepArgs>();
    add_scene_options(*cmd, a->scene);
    add_algo_options(*cmd, a->algo_options, false);
    cmd->add_option("--k", a->ks, "Comma-separated k values")->capture_default_str();
    cmd->add_option("--views", a->views, "Number of views")->capture_default_str()->check(CLI::Range(1, 64));
    cmd->add_option("--report", a->report, "Directory for sweep.csv, sweep.json, plots, index.html")->required();
    cmd->add_flag("--json", a->json, "Print sweep.json's object on stdout");
    cmd->callback([a] {
        std::vector<int> ks;
        for (const auto& x : split_list(a->ks)) {
            char* end = nullptr;
            const long k = std::strtol(x.c_str(), &end, 10);
            if (*end || k < 1 || k > gpu::kMaxK)
                throw InputError("", "--k takes integers from 1 to " + std::to_string(gpu::kMaxK) + ", found '" + x + "'");
            ks.push_back(int(k));
        }
        if (ks.empty()) throw InputError("", "--k is empty");
        std::sort(ks.begin(), ks.end());
        ks.erase(std::unique(ks.begin(), ks.end()), ks.end());
        const std::string dir = a->report, runs = dir + "/runs";
        std::error_code ec;
        std::filesystem::create_directories(runs, ec);
        if (ec) throw InputError(dir, "cannot create the report directory: " + ec.message());

        Scene s = setup_scene(a->scene);
        const Camera scene_camera = s.camera;
        const auto views = sweep_views(a->views);
        nlohmann::json out;
        out["mesh"] = a->scene.input.path;
        out["field"] = s.mesh().fields[s.field].name;
        out["width"] = s.width;
        out["height"] = s.height;
        out["k"] = ks;
        out["rows"] = nlohmann::json::array();
        out["views"] = nlohmann::json::array();
        ProgressBar bar("sweep");
        const std::size_t total = views.size() * ks.size() * 2;
        std::size_t done = 0, resumed = 0;
        double floor_sum = 0.0;
        for (const View& v : views) {
            s.camera = v.index == 0 ? scene_camera
                                    : default_camera(mesh_bounds(s.mesh()), double(s.width) / s.height, v.azimuth,
                                                     v.elevation);
            const Image ref = run_algorithm(s, "reference", a->algo_options).image;
            nlohmann::json vj = {{"view", v.index}, {"azimuth", v.azimuth}, {"elevation", v.elevation}};
            Image top[2];
            for (int mode = 0; mode < 2; ++mode) {
                const std::string mname = mode == 0 ? "exact" : "table";
                int smallest = -1;
                for (int k : ks) {
                    const std::string tag = "v" + std::to_string(v.index) + "-k" + std::to_string(k) + "-" + mname;
                    nlohmann::json row;
                    const bool last = k == ks.back();
                    if (!load_json(runs + "/" + tag + ".json", row) ||
                        (last && !std::filesystem::exists(runs + "/" + tag + ".npy", ec))) {
                        AlgoOptions o = a->algo_options;
                        o.k = k;
                        o.segment = mname;
                        const AlgoResult r = run_algorithm(s, "havs", o);
                        const ErrorMeasures e = measure_errors(r.image, ref);
                        std::size_t err_pixels = 0;
                        for (uint32_t c : r.ordering_errors) err_pixels += c ? 1 : 0;
                        row = {{"view", v.index}, {"k", k}, {"mode", mname}, {"rmse", e.rmse}, {"max_abs", e.max_abs},
                               {"psnr", std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json(nullptr)},
                               {"visible_fraction", e.visible_fraction},
                               {"ordering_errors", r.stats["ordering_errors"]},
                               {"ordering_error_pixel_fraction", double(err_pixels) / double(r.ordering_errors.size())},
                               {"max_fragments_per_pixel", r.stats["max_fragments_per_pixel"]}, {"ms", r.ms}};
                        if (last) write_npy(runs + "/" + tag + ".npy", r.image);
                        write_file_atomically(runs + "/" + tag + ".json", row.dump() + "\n");
                    } else {
                        ++resumed;
                    }
                    if (last) top[mode] = read_npy(runs + "/" + tag + ".npy");
                    if (smallest < 0 && row["visible_fraction"].get<double>() == 0.0) smallest = k;
                    out["rows"].push_back(row);
                    bar.update(double(++done) / double(total));
                }
                vj[std::string("smallest_k_without_visible_error_") + mname] =
                    smallest < 0 ? nlohmann::json(nullptr) : nlohmann::json(smallest);
            }
            const ErrorMeasures floor = measure_errors(top[1], top[0]);
            vj["table_floor_rmse"] = floor.rmse;
            vj["table_floor_max_abs"] = floor.max_abs;
            floor_sum += floor.rmse;
            out["views"].push_back(vj);
        }
        bar.finish();
        out["table_floor_rmse"] = floor_sum / double(views.size());
        out["resumed_runs"] = resumed;
        write_file_atomically(dir + "/sweep.json", out.dump(1) + "\n");
        std::string csv = "view,k,mode,rmse,max_abs,psnr,visible_fraction,ordering_errors,"
                          "ordering_error_pixel_fraction,max_fragments_per_pixel,ms\n";
        for (const auto& r : out["rows"]) {
            char buf[512];
            std::snprintf(buf, sizeof buf, "%d,%d,%s,%.9g,%.9g,%s,%.9g,%llu,%.9g,%llu,%.3f\n", r["view"].get<int>(),
                          r["k"].get<int>(), r["mode"].get<std::string>().c_str(), r["rmse"].get<double>(),
                          r["max_abs"].get<double>(),
                          r["psnr"].is_null() ? "inf" : std::to_string(r["psnr"].get<double>()).c_str(),
                          r["visible_fraction"].get<double>(), r["ordering_errors"].get<unsigned long long>(),
                          r["ordering_error_pixel_fraction"].get<double>(),
                          r["max_fragments_per_pixel"].get<unsigned long long>(), r["ms"].get<double>());
            csv += buf;
        }
        write_file_atomically(dir + "/sweep.csv", csv);
        // Plots by matplotlib (Debian's python3-matplotlib); without it the numbers still stand.
        const std::string plot = std::string("/usr/bin/python3 '") + UVR_SOURCE_DIR + "/bench/plots/sweep_plots.py' '" +
                                 dir + "' 2>&1";
        const bool plotted = std::system(plot.c_str()) == 0;
        if (!plotted) std::fprintf(stderr, "uvr: warning: plots not drawn (needs python3-matplotlib)\n");
        write_sweep_page(dir, out, plotted);
        if (a->json) {
            std::printf("%s\n", out.dump(1).c_str());
            return;
        }
        for (const auto& v : out["views"])
            std::printf("view %d (%g, %g): smallest k without visible error: sorting %s, total %s; table error RMSE "
                        "%.3g\n",
                        v["view"].get<int>(), v["azimuth"].get<double>(), v["elevation"].get<double>(),
                        v["smallest_k_without_visible_error_exact"].dump().c_str(),
                        v["smallest_k_without_visible_error_table"].dump().c_str(), v["table_floor_rmse"].get<double>());
        std::printf("report: %s/index.html (%zu runs resumed from disk)\n", dir.c_str(), resumed);
    });
}

}  // namespace uvr::cli
