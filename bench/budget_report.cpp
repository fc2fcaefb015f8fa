// The page of a `uvr budget` report (write_budget_page, bench/report.h): the budget as a table and a chart (budget.svg),
// each factor's error heat map beside the total's, a sentence per factor. Self-contained, opened from the file system.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

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

// The chart's geometry in SVG user units: the plot area's left edge (room for the axis' labels), its height, one
// run's slot, and the smallest error drawn (an exact run's bar stands at this floor).
constexpr double kChartLeft = 70, kChartTop = 30, kChartHeight = 220, kChartSlot = 80, kChartFloor = 1e-9;

// The budget as a bar chart (SVG): each run's RMSE on a logarithmic axis, its largest error as a black tick, the
// baseline grey, the factors blue, the total red; a factor measured against the step run is labelled so.
std::string budget_chart_svg(const nlohmann::json& b)
{
    std::vector<std::pair<std::string, const nlohmann::json*>> runs{{"baseline", &b["baseline"]}};
    for (const auto& n : b["factor_order"]) runs.push_back({n.get<std::string>(), &b["factors"][n.get<std::string>()]});
    runs.push_back({"total", &b["total"]});
    double top = kChartFloor * 10;
    for (const auto& [name, j] : runs) top = std::max({top, (*j)["rmse"].get<double>(), (*j)["max_abs"].get<double>()});
    const int decades = int(std::ceil(std::log10(top / kChartFloor)));
    const auto y = [&](double v) {
        return kChartTop + kChartHeight * (1.0 - std::log10(std::max(v, kChartFloor) / kChartFloor) / decades);
    };
    const double width = kChartLeft + kChartSlot * double(runs.size()) + 20;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" "
                  "font-size=\"11\"><text x=\"%.0f\" y=\"16\" font-size=\"13\">error (RMSE bars, largest error ticks)"
                  "</text>\n",
                  width, kChartTop + kChartHeight + 50, kChartLeft);
    std::string svg = buf;
    for (int d = 0; d <= decades; ++d) {
        const double v = kChartFloor * std::pow(10.0, d), yy = y(v);
        std::snprintf(buf, sizeof buf,
                      "<line x1=\"%.0f\" x2=\"%.0f\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.0f\" "
                      "y=\"%.1f\" text-anchor=\"end\">1e%d</text>\n",
                      kChartLeft, width - 10, yy, yy, kChartLeft - 6, yy + 4, int(std::lround(std::log10(v))));
        svg += buf;
    }
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const auto& [name, j] = runs[i];
        const double x = kChartLeft + kChartSlot * double(i) + 15, bar = y((*j)["rmse"].get<double>());
        const char* colour = i == 0 ? "#999" : i + 1 == runs.size() ? "#d62728" : "#1f77b4";
        const bool vs_step = j->value("against", "reference") == "step";
        std::snprintf(buf, sizeof buf,
                      "<rect x=\"%.0f\" y=\"%.1f\" width=\"%.0f\" height=\"%.1f\" fill=\"%s\"/><line x1=\"%.0f\" "
                      "x2=\"%.0f\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#000\" stroke-width=\"2\"/><text x=\"%.0f\" "
                      "y=\"%.0f\" text-anchor=\"middle\">%s</text>\n",
                      x, bar, kChartSlot - 30, kChartTop + kChartHeight - bar, colour, x - 5, x + kChartSlot - 25,
                      y((*j)["max_abs"].get<double>()), y((*j)["max_abs"].get<double>()), x + (kChartSlot - 30) / 2,
                      kChartTop + kChartHeight + 16, escape_markup(name).c_str());
        svg += buf;
        if (vs_step) {
            std::snprintf(buf, sizeof buf, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">(vs step)</text>\n",
                          x + (kChartSlot - 30) / 2, kChartTop + kChartHeight + 30);
            svg += buf;
        }
    }
    return svg + "</svg>\n";
}

}  // namespace

void write_budget_chart(const std::string& dir, const nlohmann::json& budget)
{
    write_file_atomically(dir + "/budget.svg", budget_chart_svg(budget));
}

void write_budget_page(const std::string& dir, const nlohmann::json& b)
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
    h += "<p><img src=\"budget.svg\" alt=\"the budget as a chart\"></p>\n";
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
