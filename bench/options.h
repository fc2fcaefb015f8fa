// The `uvr` program's command-line options shared by its sub-commands (docs/spec.md §3), built with CLI11: the input,
// the scene and the algorithms' options (from their table, bench/algo_options.h). The Python module does not use this.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/algo_options.h"
#include "bench/scene.h"

namespace uvr::cli {

// Adds MESH (positional), --q, --dims, --dtype, --big-endian, --field, --time.
void add_input_options(CLI::App& cmd, InputOptions& in);
// Adds the input options plus --tf, --camera, --view, --size.
void add_scene_options(CLI::App& cmd, SceneOptions& o);
// Adds every row of the algorithm options' table; without the per-run ones (--k, --step) when `with_per_run` is false
// (sweep takes lists of them). `only`: just the rows named there (bench).
void add_algo_options(CLI::App& cmd, AlgoOptions& o, bool with_per_run = true,
                      const std::vector<std::string>& only = {});

// The exit codes of `uvr`: 1 for bad input (file, option), 2 for a usage error, 3 for an internal error.
inline constexpr int kExitInputError = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInternal = 3;

}  // namespace uvr::cli
