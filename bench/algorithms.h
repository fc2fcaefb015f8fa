// The registry of algorithms: one entry per algorithm (name, the inputs it takes, its options, how to make its renderer
// on a backend), and one renderer result that render, compare, sweep, bench and demo all use. Adding an algorithm is
// one entry in algorithms.cpp (docs/architecture.md, "How to add an algorithm").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/scene.h"
#include "gpu/havs/havs.h"
#include "gpu/raycast/raycast.h"
#include "gpu/vicp/vicp.h"
#include "reference/image.h"

namespace uvr::cli {

struct AlgoOptions {
    std::string backend = "emu";
    std::string gl = "osmesa";  // --backend gl: osmesa | egl
    bool require_diagnostics = false;  // render --diagnostics: refuse a configuration that cannot produce them
    bool diagnostics = true;   // per-pixel diagnostics where the backend can give them (bench times without)
    int k = 6;  // or gpu::kEveryFragment (--k all)
    std::string ties = "arrival";  // HAVS with --k all: arrival | facing (the order at one distance)
    std::string segment = "table";
    std::string gaps = "exact";
    std::string order = "mpvonc";  // VICP's cell order
    std::string coverage = "gpu";  // HAVS and VICP: gpu (the rasterizer's) | exact (emulation only)
    // gpu (the rasterizer's interpolated varyings: the seed's pipeline) | exact (double from the pixel's ray). Empty:
    // the algorithm's default (gpu for HAVS, VICP and the ray caster: the seeds' pipelines, SPEC §7).
    std::string interpolation;
    // HAVS: marked (uvr's entries: exit, entry and extrapolated fragments told apart) | seed (the program as printed:
    // the scalar itself, exit faces negative). Empty: the backend's default (seed with --backend arb, else marked).
    std::string entries;
    // --backend arb: triangles per draw call (0: the driver's 131,072) and a glTextureBarrier after each draw (what
    // conformant GL would need; docs/havs-arb.md, "Reading the targets").
    std::size_t arb_draw = 0;
    bool arb_barrier = false;
    // HAVS on GL and ARB: which triangles the CPU sends, covered (those that cover a pixel; the same image) | all
    // (every face, as the seed sends them). docs/gl-backend.md, "Triangles that cover no pixel".
    std::string send = "covered";
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
// --k's value: a whole number >= 1, or "all" (gpu::kEveryFragment); and k as JSON (a number, or "all").
int parse_k(const std::string& v);
nlohmann::json k_json(int k);
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
    // Diagnostics, SPEC row order: HAVS all three, VICP fragments and ordering errors (and, with the seed's
    // interpolation emulated, its wrong exits), the ray caster's samples.
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
