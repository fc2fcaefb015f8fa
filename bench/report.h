// The HTML page of a report: a self-contained file next to its images, opened from the file system, no server, no
// script needed to see the pictures and numbers.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "reference/error_measures.h"
#include "reference/io_util.h"  // escape_markup

namespace uvr::cli {

// docs/spec.md §4's measures as a run's JSON has them (psnr null for identical images).
nlohmann::json measures_json(const ErrorMeasures& e);

// Writes DIR/index.html for a compare report described by `metrics` (the content of metrics.json).
void write_compare_page(const std::string& dir, const nlohmann::json& metrics);

// Writes DIR/index.html for a sweep report (the content of sweep.json); `plots` says whether the PNG plots exist.
void write_sweep_page(const std::string& dir, const nlohmann::json& sweep, bool plots);

// Writes DIR/budget.svg, the budget (the content of budget.json) as a bar chart, and DIR/index.html, its page.
void write_budget_chart(const std::string& dir, const nlohmann::json& budget);
void write_budget_page(const std::string& dir, const nlohmann::json& budget);

// Writes DIR/index.html for `uvr demo`: `page` has "parts" (each a compare report: "title", "page", "results" as in
// metrics.json with image paths relative to DIR and, on GL and ARB rows, "same_bits" / "same_bits_as"; or
// "unavailable" with the reason), "sweep" (the sweep page), "budgets" (each a budget report: "title", "page") and
// "mesh" (counts).
void write_demo_page(const std::string& dir, const nlohmann::json& page);

// A small script that marks <body> with data-loaded, data-images and data-broken once the page has loaded.
std::string load_check_script();

// The inferno legend of the error heat maps as an inline CSS gradient with its logarithmic ticks.
std::string heat_legend_html();

}  // namespace uvr::cli
