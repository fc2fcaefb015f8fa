#include "bench/report.h"

#include <cmath>
#include <cstdio>

#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

nlohmann::json measures_json(const ErrorMeasures& e)
{
    return {{"rmse", e.rmse}, {"max_abs", e.max_abs},
            {"psnr", std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json(nullptr)},
            {"visible_fraction", e.visible_fraction}, {"covered_left_empty", e.covered_left_empty}};
}

std::string load_check_script()
{
    // Marks the body once the page has loaded: how many images it has and which failed, so a headless browser can
    // tell a reader's view from a broken page (tests/test_report_browser.cpp). The page needs no script to be read.
    return "<script>window.addEventListener('load', function () {\n"
           "  var imgs = Array.prototype.slice.call(document.images);\n"
           "  var broken = imgs.filter(function (i) { return !(i.complete && i.naturalWidth > 0); })\n"
           "                   .map(function (i) { return i.getAttribute('src'); });\n"
           "  document.body.setAttribute('data-images', String(imgs.length));\n"
           "  document.body.setAttribute('data-broken', broken.join(' '));\n"
           "  document.body.setAttribute('data-loaded', 'yes');\n"
           "});</script>\n";
}

std::string heat_legend_html()
{
    // Styled inline, so that it renders the same on every page whatever that page's style sheet holds (a tick label
    // without its absolute position runs into the next one).
    std::string stops;
    for (int i = 0; i <= 8; ++i) {
        unsigned char c[3];
        inferno(i / 8.0, c);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s#%02x%02x%02x %d%%", i ? ", " : "", c[0], c[1], c[2], i * 100 / 8);
        stops += buf;
    }
    std::string html =
        "<div class=\"legend\" style=\"width: 420px; margin: 1em 0 2em 0\"><div class=\"bar\" "
        "style=\"height: 14px; border: 1px solid #888; background: linear-gradient(to right, " +
        stops +
        ")\"></div><div class=\"ticks\" style=\"position: relative; height: 1.2em; "
        "font-size: 80%\">";
    const int decades = int(std::lround(std::log10(kHeatMax / kHeatMin)));
    for (int d = 0; d <= decades; ++d) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "<span style=\"position: absolute; left: %.2f%%; transform: translateX(-50%%)\">1e%d</span>",
                      100.0 * d / decades, int(std::lround(std::log10(kHeatMin))) + d);
        html += buf;
    }
    return html +
           "</div><div class=\"caption\" style=\"font-size: 85%; color: #555\">largest channel error per "
           "pixel (log scale; black: none)</div></div>";
}

namespace {

std::string number(const nlohmann::json& v, const char* fmt)
{
    if (v.is_null()) return "&infin;";
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v.get<double>());
    return buf;
}

}  // namespace

void write_compare_page(const std::string& dir, const nlohmann::json& m)
{
    std::string h = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>uvr compare: )" +
                    escape_markup(m["mesh"].get<std::string>()) + R"(</title>
<style>
body { font-family: sans-serif; margin: 1.5em; background: #fafafa; color: #222; }
table { border-collapse: collapse; }
th, td { padding: 0.4em 0.8em; border-bottom: 1px solid #ddd; text-align: right; vertical-align: middle; }
th:first-child, td:first-child { text-align: left; }
img { image-rendering: pixelated; width: 256px; background: #000; }
</style></head><body>
)";
    h += "<h1>uvr compare</h1>\n<p>" + escape_markup(m["mesh"].get<std::string>()) + ", field <b>" +
         escape_markup(m["field"].get<std::string>()) + "</b>, " + std::to_string(m["width"].get<int>()) + " &times; " +
         std::to_string(m["height"].get<int>()) +
         " pixels. Errors are measured against the reference over every "
         "pixel and the four premultiplied channels (docs/spec.md &sect;4); &ldquo;visible&rdquo; is the fraction of "
         "pixels "
         "whose largest channel error exceeds 1/255.</p>\n";
    h += heat_legend_html() + "\n<table>\n<tr><th>algorithm</th><th>image</th><th>error</th><th>RMSE</th>"
                              "<th>max</th><th>PSNR (dB)</th><th>visible</th><th>time (ms)</th></tr>\n";
    for (const auto& r : m["results"]) {
        const std::string label = r["label"].get<std::string>();
        const bool outside = r["algo"] == "image";
        // An image made elsewhere says where it came from, and when it had no alpha that only colour was compared.
        std::string note;
        if (outside)
            note = "<br><small>" + escape_markup(r["source"].get<std::string>()) +
                   (r["colour_only"].get<bool>() ? "<br>colour only (no alpha): RGB against the reference over black"
                                                 : "") +
                   "</small>";
        h += "<tr><td>" + escape_markup(label) + note + "</td><td><img src=\"" +
             escape_markup(r["image"].get<std::string>()) + "\" alt=\"" + escape_markup(label) + "\"></td><td>";
        if (r.contains("error_map"))
            h += "<img src=\"" + escape_markup(r["error_map"].get<std::string>()) + "\" alt=\"error of " +
                 escape_markup(label) + "\">";
        h += "</td><td>" + number(r["rmse"], "%.3g") + "</td><td>" + number(r["max_abs"], "%.3g") + "</td><td>" +
             number(r["psnr"], "%.1f") + "</td><td>" + number(r["visible_fraction"], "%.4f") + "</td><td>" +
             (outside ? std::string("made elsewhere") : r["cached"].get<bool>() ? std::string("cached")
                                                                      : number(r["ms"], "%.0f")) + "</td></tr>\n";
    }
    h += "</table>\n<p>Numbers: <a href=\"metrics.json\">metrics.json</a>. Images: <code>.png</code> composited over "
         "black; <code>.npy</code> float32 premultiplied RGBA beside them.</p>\n" + load_check_script() +
         "</body></html>\n";
    write_file_atomically(dir + "/index.html", h);
}

void write_sweep_page(const std::string& dir, const nlohmann::json& w, bool plots)
{
    std::string h =
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>uvr sweep: " +
        escape_markup(w["mesh"].get<std::string>()) +
        "</title>\n<style>body { font-family: sans-serif; margin: 1.5em; background: #fafafa; color: #222; }"
        " table { border-collapse: collapse; } th, td { padding: 0.4em 0.8em; border-bottom: 1px solid "
        "#ddd; text-align: right; } img { max-width: 48%; }</style></head><body>\n";
    h += "<h1>uvr sweep: HAVS error against k</h1>\n<p>" + escape_markup(w["mesh"].get<std::string>()) + ", field <b>" +
         escape_markup(w["field"].get<std::string>()) + "</b>, " + std::to_string(w["width"].get<int>()) + " &times; " +
         std::to_string(w["height"].get<int>()) +
         ". <i>Sorting error</i>: HAVS with exact segment integration "
         "against the reference. <i>Total</i>: HAVS with the pre-integrated table. <i>Table error</i>: table against "
         "exact at the largest k, where sorting no longer errs.</p>\n";
    if (plots)
        h += "<p><img src=\"error_vs_k.png\" alt=\"error against k\"> <img src=\"ordering_vs_k.png\" "
             "alt=\"ordering errors against k\"></p>\n";
    else
        h += "<p>(Plots not drawn: python3-matplotlib is missing.)</p>\n";
    h += "<table><tr><th>view</th><th>azimuth</th><th>elevation</th><th>smallest k, no visible sorting error</th>"
         "<th>smallest k, no visible error in total</th><th>table error RMSE</th></tr>\n";
    for (const auto& v : w["views"]) {
        char buf[512];
        std::snprintf(buf, sizeof buf, "<tr><td>%d</td><td>%g</td><td>%g</td><td>%s</td><td>%s</td><td>%.3g</td></tr>\n",
                      v["view"].get<int>(), v["azimuth"].get<double>(), v["elevation"].get<double>(),
                      v["smallest_k_without_visible_error_exact"].is_null()
                          ? "none in the sweep"
                          : std::to_string(v["smallest_k_without_visible_error_exact"].get<int>()).c_str(),
                      v["smallest_k_without_visible_error_table"].is_null()
                          ? "none in the sweep"
                          : std::to_string(v["smallest_k_without_visible_error_table"].get<int>()).c_str(),
                      v["table_floor_rmse"].get<double>());
        h += buf;
    }
    h += "</table>\n";
    if (!w["table_rows"].empty()) {
        h += "<h2>Table error against table size</h2>\n<p>HAVS with the table against HAVS with exact segments, both at "
             "k = " + std::to_string(w["k"].back().get<int>()) + ".</p>\n";
        if (plots) h += "<p><img src=\"table_error_vs_size.png\" alt=\"table error against table size\"></p>\n";
        h += "<table><tr><th>view</th><th>table size</th><th>RMSE</th><th>largest error</th><th>visible fraction</th>"
             "</tr>\n";
        for (const auto& r : w["table_rows"]) {
            char buf[256];
            std::snprintf(buf, sizeof buf, "<tr><td>%d</td><td>%d</td><td>%.3g</td><td>%.3g</td><td>%.4f</td></tr>\n",
                          r["view"].get<int>(), r["table_size"].get<int>(), r["rmse"].get<double>(),
                          r["max_abs"].get<double>(), r["visible_fraction"].get<double>());
            h += buf;
        }
        h += "</table>\n";
    }
    if (w.contains("budget_rows") && !w["budget_rows"].empty()) {
        h += "<h2>The error budget against k</h2>\n<p>At every k, HAVS with every switch exact, then with one cause at a "
             "time set back to its default (uvr budget): which cause dominates as k grows.</p>\n";
        if (plots) h += "<p><img src=\"budget_vs_k.png\" alt=\"the budget against k\"></p>\n";
        h += "<table><tr><th>view</th><th>k</th><th>largest cause</th><th>its RMSE</th><th>total RMSE</th>"
             "<th>budget</th></tr>\n";
        for (const auto& r : w["budget_rows"]) {
            char buf[256];
            const std::string dominant = r["dominant"].get<std::string>();
            std::snprintf(buf, sizeof buf, "<tr><td>%d</td><td>%d</td><td>%s</td><td>%.3g</td><td>%.3g</td>",
                          r["view"].get<int>(), r["k"].get<int>(), escape_markup(dominant).c_str(),
                          r["factors"][dominant].get<double>(), r["total"].get<double>());
            h += std::string(buf) + "<td><a href=\"" + escape_markup(r["page"].get<std::string>()) + "\">page</a>" +
                 (r["baseline_ok"].get<bool>() ? "" : " (baseline not exact)") + "</td></tr>\n";
        }
        h += "</table>\n";
    }
    h += "<p>Every number: <a href=\"sweep.csv\">sweep.csv</a>, <a href=\"sweep.json\">sweep.json</a>."
         "</p>\n" + load_check_script() + "</body></html>\n";
    write_file_atomically(dir + "/index.html", h);
}

void write_demo_page(const std::string& dir, const nlohmann::json& page)
{
    std::string html =
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>uvr demo</title>\n<style>"
        "body{font-family:sans-serif;margin:2em;max-width:70em}table{border-collapse:collapse}"
        "td,th{padding:4px 10px;border-bottom:1px solid #ddd;text-align:left}img{width:256px;"
        "image-rendering:pixelated;background:#000}.same{color:#070;font-weight:bold}.differs{color:#b00;"
        "font-weight:bold}.na{color:#777}img.plot{width:560px;image-rendering:auto;background:#fff}"
        "figure{display:inline-block;margin:0.5em}</style></head>\n<body>\n<h1>uvr: how right GPU volume "
        "renderers are, and what they cost</h1>\n";
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "<p>Everything below was rendered just now from built-in data: a tetrahedralized torus (%zu points, "
                  "%zu tetrahedra) and a fuzzy torus on a 64 &times; 64 &times; 32 grid. Each algorithm is measured "
                  "against the exact reference (RMSE, largest channel error, fraction of pixels visibly different). "
                  "On GL and through the paper's ARB programs, &ldquo;same bits&rdquo; means the image equals its "
                  "emulated twin bit for bit. Each heading links the full report with error maps.</p>\n",
                  page["mesh"]["points"].get<std::size_t>(), page["mesh"]["tetrahedra"].get<std::size_t>());
    html += buf;
    for (const auto& part : page["parts"]) {
        const std::string title = escape_markup(part["title"].get<std::string>());
        if (part.contains("unavailable")) {
            html += "<h2>" + title + "</h2>\n<p class=\"na\">Not run on this machine: " +
                    escape_markup(part["unavailable"].get<std::string>()) + "</p>\n";
            continue;
        }
        html += "<h2><a href=\"" + escape_markup(part["page"].get<std::string>()) + "\">" + title + "</a></h2>\n";
        html += "<table><tr><th></th><th>image</th><th>RMSE</th><th>largest error</th><th>visible</th>"
                "<th>emulated twin</th></tr>\n";
        for (const auto& r : part["results"]) {
            std::string twin = "&mdash;";
            if (r.contains("same_bits"))
                twin = r["same_bits"].get<bool>() ? "<span class=\"same\">same bits</span> as " +
                                                        escape_markup(r["same_bits_as"].get<std::string>())
                                                  : "<span class=\"differs\">differs</span> from " +
                                                        escape_markup(r["same_bits_as"].get<std::string>());
            std::snprintf(buf, sizeof buf, "<td>%.3g</td><td>%.3g</td><td>%.4f</td>", r["rmse"].get<double>(),
                          r["max_abs"].get<double>(), r["visible_fraction"].get<double>());
            const std::string image = escape_markup(r["image"].get<std::string>());
            html += "<tr><td>" + escape_markup(r["label"].get<std::string>()) + "</td><td><a href=\"" + image +
                    "\"><img src=\"" + image + "\" alt=\"" + escape_markup(r["label"].get<std::string>()) +
                    "\"></a></td>" + buf + "<td>" + twin + "</td></tr>\n";
        }
        html += "</table>\n";
    }
    html += "<h2><a href=\"" + escape_markup(page["sweep"].get<std::string>()) +
            "\">Error against the k-buffer's size (uvr sweep)</a></h2>\n<p>HAVS on the small torus, k = 1 to 16, three "
            "views: how the error falls as the k-buffer grows.</p>\n";
    if (page.contains("sweep_plot"))
        html += "<p><img class=\"plot\" src=\"" + escape_markup(page["sweep_plot"].get<std::string>()) +
                "\" alt=\"error against k\"></p>\n";
    if (page.contains("budgets")) {
        html += "<h2>Where the error comes from (uvr budget)</h2>\n<p>Each algorithm with every switch exact, then with "
                "one cause at a time set back to its default: sorting, the table, the rasterizer's interpolation and "
                "coverage, early termination.</p>\n<ul>\n";
        for (const auto& b : page["budgets"])
            html += "<li><a href=\"" + escape_markup(b["page"].get<std::string>()) + "\">" +
                    escape_markup(b["title"].get<std::string>()) + "</a></li>\n";
        html += "</ul>\n";
        for (const auto& b : page["budgets"])
            if (b.contains("chart"))
                html += "<figure><img class=\"plot\" src=\"" + escape_markup(b["chart"].get<std::string>()) +
                        "\" alt=\"" + escape_markup(b["title"].get<std::string>()) + "\"><figcaption>" +
                        escape_markup(b["title"].get<std::string>()) + "</figcaption></figure>\n";
    }
    html += load_check_script() + "</body></html>\n";
    write_file_atomically(dir + "/index.html", html);
}

}  // namespace uvr::cli
