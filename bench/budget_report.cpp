// The page of a `uvr budget` report (write_budget_page, bench/report.h): the budget as a table and a chart, each
// factor's error heat map beside the total's, a sentence per factor. Self-contained, opened from the file system.
#include <cstdio>

#include "bench/report.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

std::string row(const std::string& name, const nlohmann::json& j, const std::string& what)
{
    char buf[256];
    std::snprintf(buf, sizeof buf, "<td>%.3g</td><td>%.3g</td><td>%.4f</td>", j["rmse"].get<double>(),
                  j["max_abs"].get<double>(), j["visible_fraction"].get<double>());
    const std::string against = j.value("against", "reference") == "step" ? "the step run" : "the reference";
    return "<tr><th>" + escape_markup(name) + "</th>" + buf + "<td>" + against + "</td><td class=\"what\">" +
           escape_markup(what) + "</td></tr>\n";
}

// What the page says the runs are measured against: the projection algorithms' every run against the reference; the
// ray caster's step and total against it, its other factors against the step run (docs/spec.md §7).
std::string measured_against(const std::string& algo)
{
    if (algo != "raycast")
        return "Every run is measured against the exact reference. The <i>baseline</i> has every switch exact; each "
               "<i>factor</i> is the baseline with one switch set back to the configuration's value, so its error is "
               "that cause's alone; the <i>total</i> is the configuration itself.";
    return "The <i>step</i> run (the baseline) has every switch exact at the configuration's step: measured against "
           "the exact reference, its error is the march's own, whose convergence <code>uvr verify --refine step "
           "--isolate --preintegrate</code> measures (docs/verification.md). Each other <i>factor</i> sets one switch "
           "back at that step and is measured against the step run, so its error is that cause's alone; the "
           "<i>total</i> is the configuration itself, against the reference.";
}

std::string figure(const std::string& name, const nlohmann::json& j)
{
    const std::string image = j["image"].get<std::string>();
    const std::string png = image.substr(0, image.size() - 4) + ".png";
    return "<figure><img src=\"" + escape_markup(j["error_map"].get<std::string>()) + "\" alt=\"" +
           escape_markup(name) + " error\"><img src=\"" + escape_markup(png) + "\" alt=\"" + escape_markup(name) +
           " image\"><figcaption>" + escape_markup(name) + "</figcaption></figure>\n";
}

}  // namespace

void write_budget_page(const std::string& dir, const nlohmann::json& b, bool chart)
{
    const std::string algo = b["algo"].get<std::string>();
    std::string h =
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>uvr budget: " + escape_markup(algo) +
        ", " + escape_markup(b["mesh"].get<std::string>()) +
        "</title>\n<style>body { font-family: sans-serif; margin: 1.5em; background: #fafafa; color: #222; "
        "max-width: 80em; } table { border-collapse: collapse; } th, td { padding: 0.4em 0.8em; "
        "border-bottom: 1px solid #ddd; text-align: right; } td.what { text-align: left; max-width: 40em; } "
        "figure { display: inline-block; margin: 0.4em; } figure img { width: 192px; "
        "image-rendering: pixelated; background: #000; margin-right: 2px; } .bad { color: #b00; "
        "font-weight: bold; }</style></head><body>\n";
    h += "<h1>uvr budget: where " + escape_markup(algo) + "'s error comes from</h1>\n<p>" +
         escape_markup(b["mesh"].get<std::string>()) + ", field <b>" + escape_markup(b["field"].get<std::string>()) +
         "</b>, " + std::to_string(b["width"].get<int>()) + " &times; " + std::to_string(b["height"].get<int>()) +
         ". " + measured_against(algo) + " Factors need not add up to the total: causes interact.</p>\n";
    if (!b["baseline_ok"].get<bool>())
        h += "<p class=\"bad\">The baseline differs from the reference beyond float32 precision: the factors cannot "
             "be told apart on this scene.</p>\n";
    h += "<table><tr><th>run</th><th>RMSE</th><th>largest error</th><th>visible fraction</th><th>measured "
         "against</th><th>what it is</th></tr>\n";
    h += row("baseline", b["baseline"],
             algo == "raycast" ? "every switch exact at the configuration's step: the step factor's run"
                               : "every switch exact: what is left is float32 rounding");
    for (const auto& n : b["factor_order"]) {
        const std::string name = n.get<std::string>();
        const nlohmann::json& j = b["factors"][name];
        std::string what = j["what"].get<std::string>();
        if (j.contains("with")) what += " (run with the rasterizer's coverage too: docs/budget.md)";
        h += row(name, j, what);
    }
    h += row("total", b["total"], "the configuration as given: every cause at once");
    h += "</table>\n";
    if (chart)
        h += "<p><img src=\"budget.png\" alt=\"the budget as a chart\"></p>\n";
    else
        h += "<p>(Chart not drawn: python3-matplotlib is missing.)</p>\n";
    h += "<h2>Error maps</h2>\n<p>Each run's largest channel error per pixel, beside its image:</p>\n" +
         heat_legend_html() + "\n";
    h += figure("total", b["total"]);
    for (const auto& n : b["factor_order"]) h += figure(n.get<std::string>(), b["factors"][n.get<std::string>()]);
    h += figure("baseline", b["baseline"]);
    h += "<p>Every number: <a href=\"budget.json\">budget.json</a>; every image as .npy under runs/.</p>\n" +
         load_check_script() + "</body></html>\n";
    write_file_atomically(dir + "/index.html", h);
}

}  // namespace uvr::cli
