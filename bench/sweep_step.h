// `uvr sweep VOLUME --step LIST`: the ray caster's error against the reference as the step shrinks, post-classified and
// pre-integrated, per view, as `sweep --k` studies HAVS's error against k.
#pragma once

#include <string>
#include <vector>

#include "bench/algorithms.h"

namespace uvr::cli {

// Parses "1,0.5,0.25" (positive, finite), sorted from the longest step down, duplicates dropped.
std::vector<double> parse_step_list(const std::string& list);

// Writes DIR/sweep.json, DIR/sweep.csv, DIR/index.html and every run's image under DIR/runs/; returns sweep.json's
// object. `steps` empty: twice, once, a half and a quarter of the default step (half the smallest spacing). With
// `budget`, the ray caster's error budget (uvr budget) at every step of every view too, under DIR/budget/.
nlohmann::json run_step_sweep(Scene& s, const AlgoOptions& o, std::vector<double> steps, int views,
                              const std::string& dir, bool budget = false);

}  // namespace uvr::cli
