// `uvr bench MESH [--algos LIST]`: timings of each algorithm, each stage apart (docs/spec.md §3). Medians over
// repetitions after a warm-up; the JSON carries every repetition's figures and a description of the machine.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/commands.h"
#include "bench/scene.h"
#include "bench/algorithms.h"
#include "gpu/gl/gl_context.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::cli {

namespace {

struct BenchArgs {
    SceneOptions scene;
    std::string algos = "reference";
    int repeat = 5;
    int warmup = 1;
    std::string backends = "emu";
    std::string orders = "mpvonc,centroid";
    AlgoOptions algo;  // the table's rows bench takes (kBenchOptions)
    bool json = false;
};

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

std::string cpu_model()
{
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown";
}

double peak_rss_mib()
{
    return double(peak_memory_bytes()) / (1024.0 * 1024.0);
}

// The start of bench's JSON: the scene, its size, the machine, and the results to come.
nlohmann::json bench_header(const BenchArgs& a, const Scene& s, double load_ms, std::size_t elements,
                            const char* element)
{
    nlohmann::json out;
    out["mesh"] = a.scene.input.path;
    out[element] = elements;
    out["width"] = s.width;
    out["height"] = s.height;
    out["load_ms"] = load_ms;
    out["machine"] = {{"cpu", cpu_model()}, {"threads", std::thread::hardware_concurrency()}};
    out["results"] = nlohmann::json::array();
    return out;
}

// Times each algorithm on each of the backends asked for that it has, each of its bench variants apart, into
// out["results"].
void time_algorithms(const Scene& s, const BenchArgs& a, const std::vector<std::string>& algos,
                     const std::vector<std::string>& backends, const std::vector<std::string>& orders,
                     nlohmann::json& out)
{
    // Each algorithm as a user renders it by default, with --k; the reference without its cache. HAVS is timed
    // without per-pixel diagnostics on every backend: on GL one RGBA32F target fewer to fetch and write per
    // fragment (5 % of a Blunt Fin frame), in the emulation no bookkeeping per fragment; the image is the same
    // (tests/test_havs.cpp), and the counts are `render --diagnostics`'s.
    AlgoOptions base;
    base.k = a.algo.k;
    base.gl = a.algo.gl;
    base.no_cache = true;
    base.diagnostics = false;
    if (a.algo.interpolation.find(',') != std::string::npos)
        throw InputError("", "--interpolation takes one of gpu or exact here, not a list");
    for (const auto& x : algos) {
        const Algorithm& algo = find_algorithm(x);
        const std::vector<std::string> algo_backends = algo.backends.size() == 1 ? algo.backends : backends;
        for (const auto& b : algo_backends) {
            if (std::find(algo.backends.begin(), algo.backends.end(), b) == algo.backends.end()) continue;
            AlgoOptions o = base;
            o.backend = b;
            if (x == "raycast" || x == "vicp") o.interpolation = a.algo.interpolation;
            if (x == "vicp") o.send = a.algo.send;
            if (x == "havs") {
                o.interpolation = a.algo.interpolation;
                o.entries = a.algo.entries;
                o.arb_draw = a.algo.arb_draw;
                o.arb_barrier = a.algo.arb_barrier;
                o.send = a.algo.send;
            }
            for (const AlgoOptions& v : algo.bench_variants(o, orders))
                out["results"].push_back(time_frames(s, algo, v, a.warmup, a.repeat));
        }
    }
}

// The text report: the scene and machine, one line per timed row, the peak memory.
void print_bench(const BenchArgs& a, const Scene& s, const nlohmann::json& out, std::size_t elements,
                 const char* element)
{
    std::printf("%s: %zu %s, %dx%d, %s (%u threads)\n", a.scene.input.path.c_str(), elements, element, s.width,
                s.height, cpu_model().c_str(), std::thread::hardware_concurrency());
    for (const auto& r : out["results"]) {
        std::printf("  %-10s %-4s %9.1f ms/frame ", r["algo"].get<std::string>().c_str(),
                    r["backend"].get<std::string>().c_str(), r["frame_ms"].get<double>());
        find_algorithm(r["algo"].get<std::string>()).print_bench_row(r);
    }
    std::printf("  peak memory %.1f MiB (%.0f bytes per %s)\n", out["peak_rss_mib"].get<double>(),
                out[s.is_volume() ? "bytes_per_voxel" : "bytes_per_tet"].get<double>(),
                s.is_volume() ? "voxel" : "tetrahedron");
}

// The bench command: the lists checked, the scene loaded, every configuration timed, the JSON or text written.
void run_bench(const BenchArgs& a)
{
    const std::vector<std::string> algos = split_list(a.algos), backends = split_list(a.backends);
    for (const auto& x : algos) run_algorithm_check(x);
    for (const auto& b : backends)
        if (b != "emu" && b != "gl" && b != "arb")
            throw InputError("", "--backend must list emu, gl and/or arb, not '" + b + "'");
    gpu::parse_gl_platform(a.algo.gl);
    const std::vector<std::string> orders = split_list(a.orders);
    for (const auto& o : orders) gpu::parse_cell_order(o);
    const auto t0 = Clock::now();
    const Scene s = setup_scene(a.scene);
    const double load_ms = ms_since(t0);
    for (const auto& x : algos) check_algorithm_scene(s, x);  // refused before timing
    // Per element: tetrahedra of a mesh, voxels (samples) of a regular grid.
    const auto& dims = s.is_volume() ? s.volume().dims : std::array<int64_t, 3>{0, 0, 0};
    const std::size_t elements = s.is_volume() ? std::size_t(dims[0] * dims[1] * dims[2]) : s.mesh().tets.size();
    const char* element = s.is_volume() ? "voxels" : "tetrahedra";
    nlohmann::json out = bench_header(a, s, load_ms, elements, element);
    time_algorithms(s, a, algos, backends, orders, out);
    out["peak_rss_mib"] = peak_rss_mib();
    out[s.is_volume() ? "bytes_per_voxel" : "bytes_per_tet"] = peak_rss_mib() * 1024.0 * 1024.0 / double(elements);
    if (a.json) {
        std::printf("%s\n", out.dump(1).c_str());
        return;
    }
    print_bench(a, s, out, elements, element);
}

}  // namespace

nlohmann::json time_frames(const Scene& s, const Algorithm& algo, const AlgoOptions& o, int warmup, int repeat,
                           Image* last_image)
{
    const auto t0 = Clock::now();
    const std::unique_ptr<Renderer> renderer = algo.make(s, o);
    const double build_ms = ms_since(t0);
    std::vector<double> frame_ms;
    std::map<std::string, std::vector<double>> stage_ms;
    nlohmann::json last;
    for (int r = 0; r < warmup + repeat; ++r) {
        const auto f0 = Clock::now();
        AlgoResult f = renderer->render(s.camera, s.width, s.height);
        const double ms = ms_since(f0);
        if (r < warmup) continue;
        frame_ms.push_back(ms);
        for (const auto& [name, v] : f.stats["stages_ms"].items()) stage_ms[name].push_back(v.get<double>());
        last = std::move(f.stats);
        if (last_image) *last_image = std::move(f.image);
    }
    nlohmann::json row = last;
    row.erase("stages_ms");
    row["algo"] = algo.name;
    row["backend"] = backend_of(algo, o);
    row["frame_ms"] = median(frame_ms);
    row["frame_ms_all"] = frame_ms;
    row["build_ms"] = build_ms;
    row["stages"] = nlohmann::json::object();
    for (const auto& [name, v] : stage_ms) row["stages"][name] = median(v);
    algo.bench_rates(row, s);
    return row;
}

void register_bench(CLI::App& app)
{
    auto* cmd = app.add_subcommand("bench", "Time each algorithm and each stage (median over repetitions)");
    auto a = std::make_shared<BenchArgs>();
    add_scene_options(*cmd, a->scene);
    cmd->add_option("--algos,--algo", a->algos, "Comma-separated algorithms (reference, havs, vicp, raycast)")->capture_default_str();
    cmd->add_option("--repeat", a->repeat, "Timed repetitions")->capture_default_str()->check(CLI::Range(1, 1000));
    cmd->add_option("--warmup", a->warmup, "Untimed repetitions first")
        ->capture_default_str()
        ->check(CLI::Range(0, 100));
    cmd->add_option("--backend,--backends", a->backends,
                    "Comma-separated backends of the GPU algorithms (emu, gl; arb: HAVS only)")
        ->capture_default_str();
    cmd->add_option("--orders,--order", a->orders, "VICP: comma-separated cell orders (mpvonc, centroid)")
        ->capture_default_str();
    add_algo_options(*cmd, a->algo, true, {"k", "gl", "interpolation", "entries", "arb-draw", "arb-barrier", "send"});
    cmd->add_flag("--json", a->json, "Print one JSON object on stdout");
    cmd->callback([a] { run_bench(*a); });
}

}  // namespace uvr::cli
