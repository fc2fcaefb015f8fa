// The algorithms' options, declared once: one table of {name, help, default, parser} from which the `uvr` program's
// options (bench/options.cpp, add_algo_options) and the Python module's keywords (python/uvr_module.cpp) are both
// built. Each choice is read by the parser declared beside its enum (reference/choice.h). docs/architecture.md,
// "Options".
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace uvr::cli {

// What a run of an algorithm is asked for. Every field holds a value its table row's parser accepted (choices in
// their canonical spelling), so the algorithms convert them without a second check.
struct AlgoOptions {
    std::string backend = "emu";       // emu | gl | arb (the algorithm's registry entry says which it has)
    std::string gl = "osmesa";         // --backend gl: osmesa | egl
    int gl_device = -1;                // --gl egl: an index into EGL's device list; -1 (gpu::kAnyEglDevice): any
    bool require_diagnostics = false;  // render --diagnostics: refuse a configuration that cannot produce them
    bool diagnostics = true;           // per-pixel diagnostics where the backend can give them (bench times without)
    int k = 6;                         // or gpu::kEveryFragment (--k all)
    std::string ties = "arrival";
    std::string segment = "table";
    std::string gaps = "exact";
    std::string order = "mpvonc";
    std::string coverage = "gpu";
    std::string interpolation;  // empty: gpu; compare alone takes the list gpu,exact
    std::string entries;        // empty: the backend's default (paper with --backend arb, else marked)
    std::size_t arb_draw = 0;   // --backend arb: triangles per draw call (0: the driver's 131,072)
    bool arb_barrier = false;
    std::string send = "covered";
    double threshold = -1.0;  // unset: the algorithm's default
    int table_size = 128;
    std::string table_format = "f32";
    bool no_cache = false;
    double step = -1.0;  // the ray caster's, world units; unset: half the smallest spacing
    bool preintegrate = false;
    std::string light;  // "X,Y,Z"
    std::string volume_format = "native";
    int parts = 1;                  // HAVS, VICP: sort-last on this many parts (bench/sort_last.h); 1: the whole mesh
    std::string partition = "rcb";  // with parts > 1: how the mesh is split (reference/partition.h)
};

// One option of the table. The program spells it --NAME; Python's keyword is NAME with '_' for '-' (or `python`).
struct AlgoOption {
    std::string name;
    std::string help;
    std::string default_text;      // shown by --help; empty when the default depends on the algorithm
    bool flag = false;             // a switch: its text is "true" or "false"
    bool per_run = false;          // a value sweep replaces with a list of its own (--k, --step)
    std::string python;            // Python's keyword, when not NAME with '_'
    bool python_inverted = false;  // Python's keyword is the switch's opposite (cache = not --no-cache)
    // Reads `text` into `o`; throws InputError naming --NAME for a value it refuses.
    std::function<void(AlgoOptions& o, const std::string& text)> set;
};

// Every algorithm option, in the order help texts list them.
const std::vector<AlgoOption>& algo_option_table();
std::string python_keyword(const AlgoOption& option);

// --k's value: a whole number >= 1, or "all" (gpu::kEveryFragment); and k as JSON (a number, or "all").
int parse_k(const std::string& v);
nlohmann::json k_json(int k);

}  // namespace uvr::cli
