// The `uvr` program as a function: the sub-commands on one command line, and its error reporting (bench/program.cpp).
#pragma once

namespace uvr::cli {

// Parses `argv` and runs the chosen sub-command. Every InputError becomes "uvr: FILE:LINE: what" on stderr and exit
// code kExitInputError; nothing escapes as a crash. Returns the process's exit code.
int run_program(int argc, char** argv);

}  // namespace uvr::cli
