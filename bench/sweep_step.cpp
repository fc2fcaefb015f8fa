#include "bench/sweep_step.h"

#include "bench/budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "bench/progress.h"
#include "bench/report.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

std::vector<double> parse_step_list(const std::string& list)
{
    std::vector<double> out;
    for (const auto& x : split_list(list)) {
        char* end = nullptr;
        const double v = std::strtod(x.c_str(), &end);
        if (*end || !(v > 0.0) || !std::isfinite(v))
            throw InputError("", "--step takes positive numbers (world units), found '" + x + "'");
        out.push_back(v);
    }
    std::sort(out.begin(), out.end(), std::greater<double>());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

nlohmann::json run_step_sweep(Scene& s, const AlgoOptions& o, std::vector<double> steps, int views,
                              const std::string& dir, bool budget)
{
    const Volume& v = s.volume();
    if (steps.empty()) {
        const double d = 0.5 * std::min(v.spacing.x, std::min(v.spacing.y, v.spacing.z));
        steps = {2.0 * d, d, 0.5 * d, 0.25 * d};
    }
    for (double st : steps) {  // every step is checked (kMaxRaySamples) before any output
        AlgoOptions c = o;
        c.step = st;
        gpu::RaycastVolume(v, s.tf, raycast_options(c));
    }
    const std::string runs = dir + "/runs";
    std::error_code ec;
    std::filesystem::create_directories(runs, ec);
    if (ec) throw InputError(dir, "cannot create the report directory: " + ec.message());

    const Camera scene_camera = s.camera;
    nlohmann::json out;
    out["volume"] = v.source;
    out["width"] = s.width;
    out["height"] = s.height;
    out["steps"] = steps;
    out["backend"] = o.backend;
    out["threshold"] = o.threshold < 0.0 ? 0.95 : o.threshold;
    out["rows"] = nlohmann::json::array();
    out["budget_rows"] = nlohmann::json::array();
    ProgressBar bar("sweep");
    const std::size_t total = std::size_t(views) * steps.size() * 2;
    std::size_t done = 0;
    std::string csv = "view,azimuth,elevation,step,classification,backend,rmse,max_abs,psnr,visible_fraction,samples,ms\n";
    for (int view = 0; view < views; ++view) {
        // View 0 is the scene's camera; the others orbit the default camera, as `sweep --k` does.
        const double az = view == 0 ? 0.0 : 360.0 * view / views, el = view == 0 ? 0.0 : (view % 2 ? 25.0 : -25.0);
        s.camera = view == 0 ? scene_camera
                             : default_camera(volume_bounds(v), double(s.width) / s.height, az, el);
        const Image ref = run_algorithm(s, "reference", o).image;
        write_npy(runs + "/v" + std::to_string(view) + "-reference.npy", ref);
        for (int pre = 0; pre < 2; ++pre)
            for (double st : steps) {
                AlgoOptions c = o;
                c.step = st;
                c.preintegrate = pre == 1;
                const AlgoResult r = run_algorithm(s, "raycast", c);
                const ErrorMeasures e = measure_errors(r.image, ref);
                char tag[96];
                std::snprintf(tag, sizeof tag, "v%d-step%.6g-%s", view, st, pre ? "preint" : "post");
                write_npy(runs + "/" + tag + ".npy", r.image);
                const nlohmann::json row = {{"view", view},
                                            {"azimuth", az},
                                            {"elevation", el},
                                            {"step", st},
                                            {"classification", pre ? "pre-integrated" : "post"},
                                            {"backend", o.backend},
                                            {"rmse", e.rmse},
                                            {"max_abs", e.max_abs},
                                            {"psnr", std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json()},
                                            {"visible_fraction", e.visible_fraction},
                                            {"samples", r.stats["samples"]},
                                            {"ms", r.ms},
                                            {"image", std::string("runs/") + tag + ".npy"}};
                out["rows"].push_back(row);
                char line[512];
                std::snprintf(line, sizeof line, "%d,%g,%g,%.9g,%s,%s,%.9g,%.9g,%.9g,%.9g,%llu,%.3f\n", view, az, el,
                              st, pre ? "pre-integrated" : "post", o.backend.c_str(), e.rmse, e.max_abs,
                              std::isfinite(e.psnr) ? e.psnr : INFINITY, e.visible_fraction,
                              static_cast<unsigned long long>(r.stats["samples"].get<uint64_t>()), r.ms);
                csv += line;
                bar.update(double(++done) / double(total));
            }
        // The budget at every step: which cause dominates as the step shrinks.
        for (double st : budget ? steps : std::vector<double>{}) {
            AlgoOptions c = o;
            c.step = st;
            char page[96];
            std::snprintf(page, sizeof page, "budget/v%d-step%.6g", view, st);
            // resumed from disk when this budget was finished by an earlier, interrupted sweep
            const nlohmann::json b = run_budget(s, "raycast", c, dir + "/" + page, v.source, nullptr, true);
            nlohmann::json row = budget_summary(b, std::string(page) + "/index.html");
            row["view"] = view;
            row["step"] = st;
            out["budget_rows"].push_back(row);
        }
    }
    bar.finish();
    write_file_atomically(dir + "/sweep.json", out.dump(1) + "\n");
    write_file_atomically(dir + "/sweep.csv", csv);
    // The page: one table, error against step (the numbers are in sweep.csv for plotting).
    std::string html =
        "<!doctype html><meta charset=utf-8><title>uvr sweep --step</title>"
        "<h1>Ray caster: error against the step</h1><p>" +
        escape_markup(v.source) + ", " + std::to_string(s.width) + "x" + std::to_string(s.height) + ", backend " +
        escape_markup(o.backend) +
        ". Error against the regular-grid reference (docs/spec.md §4).</p><table border=1 cellpadding=4>"
        "<tr><th>view<th>classification<th>step<th>RMSE<th>max abs<th>PSNR<th>visible<th>samples<th>ms";
    for (const auto& r : out["rows"]) {
        char row[512];
        std::snprintf(row, sizeof row, "<tr><td>%d<td>%s<td>%.6g<td>%.3g<td>%.3g<td>%s<td>%.4f<td>%llu<td>%.0f",
                      r["view"].get<int>(), r["classification"].get<std::string>().c_str(), r["step"].get<double>(),
                      r["rmse"].get<double>(), r["max_abs"].get<double>(), r["psnr"].dump().c_str(),
                      r["visible_fraction"].get<double>(),
                      static_cast<unsigned long long>(r["samples"].get<uint64_t>()), r["ms"].get<double>());
        html += row;
    }
    html += "</table>\n";
    if (!out["budget_rows"].empty()) {
        html += "<h2>The error budget against the step</h2><p>At every step, the ray caster with every switch exact "
                "at that step against the reference, then with one cause at a time set back, against that run (uvr "
                "budget).</p>"
                "<table border=1 cellpadding=4><tr><th>view<th>step<th>largest cause<th>its RMSE<th>total RMSE<th>budget";
        for (const auto& r : out["budget_rows"]) {
            char row[256];
            const std::string dominant = r["dominant"].get<std::string>();
            std::snprintf(row, sizeof row, "<tr><td>%d<td>%.6g<td>%s<td>%.3g<td>%.3g", r["view"].get<int>(),
                          r["step"].get<double>(), escape_markup(dominant).c_str(),
                          r["factors"][dominant].get<double>(), r["total"].get<double>());
            html += std::string(row) + "<td><a href=\"" + escape_markup(r["page"].get<std::string>()) + "\">page</a>";
        }
        html += "</table>\n";
    }
    write_file_atomically(dir + "/index.html", html);
    return out;
}

}  // namespace uvr::cli
