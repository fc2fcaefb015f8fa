// The sub-commands of `uvr`, one file each (cmd_<name>.cpp). Each registers itself on the application; its callback
// throws InputError for bad input, which main() turns into a message and exit code.
#pragma once

#include <CLI/CLI.hpp>

#include "bench/options.h"

namespace uvr::cli {

void register_info(CLI::App& app);
void register_demo(CLI::App& app);
void register_render(CLI::App& app);
void register_bench(CLI::App& app);
void register_export(CLI::App& app);
void register_compare(CLI::App& app);
void register_sweep(CLI::App& app);

}  // namespace uvr::cli
