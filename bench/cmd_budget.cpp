// `uvr budget MESH --algo havs|vicp|raycast [scene options] [algorithm options] --report DIR [--json]`: the
// algorithm's error against the reference split into its causes (docs/spec.md §7, docs/budget.md; the computation is
// bench/budget.cpp).
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/algorithms.h"
#include "bench/budget.h"
#include "bench/commands.h"
#include "bench/options.h"
#include "reference/error.h"

namespace uvr::cli {

namespace {

struct BudgetArgs {
    SceneOptions scene;
    AlgoOptions algo_options;
    std::string algo;
    std::string report;
    bool json = false;
};

}  // namespace

void register_budget(CLI::App& app)
{
    auto* cmd = app.add_subcommand("budget", "Split an algorithm's error against the reference into its causes");
    auto a = std::make_shared<BudgetArgs>();
    add_scene_options(*cmd, a->scene);
    add_algo_options(*cmd, a->algo_options);
    cmd->add_option("--algo", a->algo, "havs | vicp | raycast")->required();
    cmd->add_option("--report", a->report, "Directory for budget.json, every run's image, the chart, index.html")
        ->required();
    cmd->add_flag("--json", a->json, "Print budget.json's object on stdout");
    cmd->callback([a] {
        run_algorithm_check(a->algo);
        const Scene s = setup_scene(a->scene);
        const nlohmann::json out = run_budget(s, a->algo, a->algo_options, a->report, a->scene.input.path);
        if (a->json) {
            std::printf("%s\n", out.dump(1).c_str());
        } else {
            const auto line = [](const char* name, const nlohmann::json& j) {
                std::printf("%-14s RMSE %-10.3g max %-10.3g visible %.4f%s\n", name, j["rmse"].get<double>(),
                            j["max_abs"].get<double>(), j["visible_fraction"].get<double>(),
                            j.value("against", "reference") == "step" ? "  (against the step run)" : "");
            };
            line("baseline", out["baseline"]);
            for (const auto& n : out["factor_order"])
                line(n.get<std::string>().c_str(), out["factors"][n.get<std::string>()]);
            line("total", out["total"]);
            std::printf("report: %s/index.html\n", a->report.c_str());
        }
        if (!out["baseline_ok"].get<bool>())
            throw InputError(a->scene.input.path,
                             "the baseline (every switch exact) differs from the reference by " +
                                 std::to_string(out["baseline"]["max_abs"].get<double>()) +
                                 " at most, above float32 precision (" + std::to_string(kBudgetBaselineMax) +
                                 "): the factors cannot be told apart on this scene (docs/budget.md); the report is "
                                 "in " + a->report);
    });
}

}  // namespace uvr::cli
