// Running one algorithm on a scene, the same way for every command (render, compare, sweep, bench).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/scene.h"
#include "gpu/havs.h"
#include "gpu/raycast.h"
#include "gpu/vicp.h"
#include "reference/image.h"

namespace uvr::cli {

struct AlgoOptions {
    std::string backend = "emu";
    std::string gl = "osmesa";  // --backend gl: osmesa | egl
    bool require_diagnostics = false;  // render --diagnostics: refuse a configuration that cannot produce them
    int k = 6;
    std::string segment = "table";
    std::string gaps = "exact";
    std::string order = "mpvonc";  // VICP's cell order
    double threshold = -1.0;  // per algorithm default (SPEC §3): HAVS 0.99
    int table_size = 128;
    std::string table_format = "f32";
    bool no_cache = false;
    // The ray caster (regular grids).
    double step = -1.0;            // world units; unset (< 0): half the smallest spacing
    bool preintegrate = false;
    std::string light;             // "X,Y,Z": shading with a point light there
    std::string volume_format = "native";
};

// --backend, --gl, --k (unless with_k is false: sweep takes a list), --segment, --gaps, --threshold, --table-size,
// --table-format, --no-cache.
void add_algo_options(CLI::App& cmd, AlgoOptions& o, bool with_k = true);
gpu::HavsOptions havs_options(const AlgoOptions& o);
gpu::VicpOptions vicp_options(const AlgoOptions& o);
gpu::RaycastOptions raycast_options(const AlgoOptions& o);

struct AlgoResult {
    Image image;
    double ms = 0.0;      // wall time of the render (0 for a cached reference)
    bool cached = false;  // reference taken from the cache
    nlohmann::json stats;
    // Diagnostics, SPEC row order: HAVS all three, VICP fragments and ordering errors, the ray caster's samples.
    std::vector<uint32_t> fragments, max_held, ordering_errors, samples;
};

// algo: "reference", "havs", "vicp" or "raycast" (emu or gl). Throws InputError for an algorithm or backend that has not landed.
AlgoResult run_algorithm(const Scene& scene, const std::string& algo, const AlgoOptions& o);

// Throws InputError for an algorithm that is unknown or has not landed (before any work is done).
void run_algorithm_check(const std::string& algo);

// Throws InputError (naming the data) when `algo` cannot render this scene: HAVS and VICP take tetrahedral meshes, the
// ray caster regular grids; the reference takes both. Commands call it for every algorithm before writing anything.
void check_algorithm_scene(const Scene& s, const std::string& algo);

// Splits "a,b,c" (empty items dropped).
std::vector<std::string> split_list(const std::string& s);

}  // namespace uvr::cli
