// Options shared by the sub-commands (SPEC §3), and what every command does with them.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "reference/dataset.h"

namespace uvr::cli {

struct InputOptions {
    std::string path;
    std::string q_file;
    std::string dims;   // "X,Y,Z" for raw volumes
    std::string dtype = "uint8";
    bool big_endian = false;
    std::string field;
    std::string time_step = "last";  // Exodus II: --time INDEX|last
};

// Adds MESH (positional), --q, --dims, --dtype, --big-endian, --field, --time.
void add_input_options(CLI::App& cmd, InputOptions& in);
Dataset load_input(const InputOptions& in);

// The exit codes of `uvr`: 1 for bad input (file, option), 2 for a usage error, 3 for an internal error.
inline constexpr int kExitInputError = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInternal = 3;

void print_warnings(const Dataset& d);

}  // namespace uvr::cli
