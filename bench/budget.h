// `uvr budget`'s parts (docs/spec.md §7): the baseline's options, the factors, and the whole run; the command is
// bench/cmd_budget.cpp, the page bench/report.cpp (write_budget_page). docs/budget.md.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/algorithms.h"

namespace uvr::cli {

// How far the baseline may differ from the reference (largest channel error) and still count as equal to float32
// precision: with every switch exact HAVS and VICP leave at most 9e-7 on the hardest views measured
// (tests/test_exact_coverage.cpp, docs/havs.md "Convergence on many views"), whose bar this is.
inline constexpr double kBudgetBaselineMax = 2e-6;

// What a factor's run is measured against (docs/spec.md §7): the reference, or, for a marching algorithm's factors
// other than the step, the `step` run (every switch exact at the user's step), whose error is the march's own.
enum class BudgetAgainst { reference, step };

// One cause of error: its name (docs/spec.md §7's key), what it is (a sentence for the page), how its run differs
// from the baseline (`apply` sets the one switch of `run`, the baseline's options, to the user's value), and what it
// is measured against.
struct BudgetFactor {
    std::string name, what;
    std::function<void(AlgoOptions& run, const AlgoOptions& user)> apply;
    BudgetAgainst against = BudgetAgainst::reference;
};
// `algo`'s factors; `partition` only where the user asks for parts (--parts N > 1).
std::vector<BudgetFactor> budget_factors(const std::string& algo, const AlgoOptions& user);

// The user's options with every switch exact: the baseline.
AlgoOptions budget_baseline(const std::string& algo, const AlgoOptions& user);

// Runs rendered by earlier budgets of the same scene and camera (uvr sweep's budget per k): a run's switches -> where
// its files are (the path without the suffixes) and its JSON. A budget takes a run from here instead of rendering it.
struct BudgetRunCache {
    std::map<std::string, std::pair<std::string, nlohmann::json>> runs;
};

// The reference, the baseline, one run per factor and the user's configuration on scene `s`, each measured against
// the reference and written to `dir` (runs/NAME.npy, .png and -error.png; budget.json; the chart; index.html).
// Every run's options are checked before anything is written. Returns budget.json's object. With `resume` (uvr sweep
// --budget), a budget.json already in `dir` whose every run has these switches and its image is taken as it is
// (its runs join `cache`): an interrupted sweep goes on from the budgets it finished.
nlohmann::json run_budget(const Scene& s, const std::string& algo, const AlgoOptions& options, const std::string& dir,
                          const std::string& mesh_name, BudgetRunCache* cache = nullptr, bool resume = false);

// A budget in one line of a sweep: `page` (its index.html), baseline_ok, the baseline's and the total's RMSE, each
// factor's RMSE (`factors`) and the largest factor's name (`dominant`).
nlohmann::json budget_summary(const nlohmann::json& budget, const std::string& page);

}  // namespace uvr::cli
