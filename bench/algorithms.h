// The registry of algorithms: one entry per algorithm (name, the inputs it takes, its options, how to make its renderer
// on a backend), and one renderer result that render, compare, sweep, bench and demo all use. Adding an algorithm is
// one entry in algorithms.cpp (docs/architecture.md, "How to add an algorithm").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/algo_options.h"
#include "bench/scene.h"
#include "gpu/havs/havs.h"
#include "gpu/raycast/raycast.h"
#include "gpu/vicp/vicp.h"
#include "reference/image.h"

namespace uvr::cli {

// The options of each algorithm, from an AlgoOptions the table accepted.
gpu::HavsOptions havs_options(const AlgoOptions& o);
gpu::VicpOptions vicp_options(const AlgoOptions& o);
gpu::RaycastOptions raycast_options(const AlgoOptions& o);

// What one frame of any algorithm gives back.
struct AlgoResult {
    Image image;
    double ms = 0.0;      // wall time of the render (0 for a cached reference)
    bool cached = false;  // reference taken from the cache
    // Options in effect, counters, "stages_ms" (stage name -> milliseconds of this frame) and, on GL, "gl".
    nlohmann::json stats;
    // Diagnostics, the image's row order (row 0 on top): HAVS all three, VICP fragments and ordering errors (and, with
    // the paper's interpolation emulated, its wrong exits), the ray caster's samples.
    std::vector<uint32_t> fragments, max_held, ordering_errors, samples, wrong_exits;
};

// An algorithm made for one scene on one backend; render() may be called again and again (bench times it).
class Renderer {
public:
    virtual ~Renderer() = default;
    virtual AlgoResult render(const Camera& camera, int width, int height) = 0;
};

enum class Inputs { mesh, grid, both };  // tetrahedral meshes, regular grids, or either

struct Algorithm {
    std::string name;
    Inputs inputs;
    // The backends it renders on ("cpu" for the reference, which has no GPU backend).
    std::vector<std::string> backends;
    // Throws InputError for an option it refuses, before any work is done.
    std::function<void(const AlgoOptions&)> check_options;
    // What sets a run's image apart, for file names and labels: "havs-emu-k6".
    std::function<std::string(const AlgoOptions&)> label;
    // Builds the renderer on o.backend (the GL context too).
    std::function<std::unique_ptr<Renderer>(const Scene&, const AlgoOptions&)> make;
    // bench: the configurations timed on one backend (VICP: each of `orders`; the ray caster: post-classified and
    // pre-integrated), and the rates and text line of one timed row.
    std::function<std::vector<AlgoOptions>(const AlgoOptions&, const std::vector<std::string>& orders)> bench_variants;
    std::function<void(nlohmann::json& row, const Scene&)> bench_rates;
    std::function<void(const nlohmann::json& row)> print_bench_row;
};

// Every algorithm, in the order help texts list them.
const std::vector<Algorithm>& algorithms();

// The entry named `name`; throws InputError naming the known ones.
const Algorithm& find_algorithm(const std::string& name);

// The backend a run of `algo` reports: its only one ("cpu" for the reference), else o.backend.
std::string backend_of(const Algorithm& algo, const AlgoOptions& o);

// Makes the renderer and renders one frame (ms: both together).
AlgoResult run_algorithm(const Scene& scene, const std::string& algo, const AlgoOptions& o);

// Throws InputError for an algorithm that is unknown (before any work is done).
void run_algorithm_check(const std::string& algo);

// Throws InputError (naming the data) when `algo` cannot render this scene: HAVS and VICP take tetrahedral meshes, the
// ray caster regular grids; the reference takes both. Commands call it for every algorithm before writing anything.
void check_algorithm_scene(const Scene& s, const std::string& algo);

// Splits "a,b,c" (empty items dropped).
std::vector<std::string> split_list(const std::string& s);

}  // namespace uvr::cli
