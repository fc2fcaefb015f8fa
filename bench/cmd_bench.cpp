// `uvr bench MESH [--algos LIST]`: timings of each algorithm, each stage apart (SPEC §3). Medians over repetitions
// after a warm-up; the JSON carries every repetition's figures and a description of the machine.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include <sys/resource.h>

#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/scene.h"
#include "gpu/gl_havs.h"
#include "gpu/gl_raycast.h"
#include "gpu/gl_vicp.h"
#include "bench/algorithms.h"
#include "reference/error.h"
#include "reference/reference_renderer.h"

namespace uvr::cli {

namespace {

struct BenchArgs {
    SceneOptions scene;
    std::string algos = "reference";
    int repeat = 5;
    int warmup = 1;
    int k = 6;
    std::string backends = "emu";
    std::string orders = "mpvonc,centroid";
    std::string gl = "osmesa";
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
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// The measured frames of one GPU algorithm's benchmark: each frame's wall time, each named stage's time, and the
// last frame's statistics.
template <class Stats>
struct TimedFrames {
    std::vector<double> frame_ms;
    std::map<std::string, std::vector<double>> stage_ms;
    Stats last{};

    double stage_median(const std::string& name) const { return median(stage_ms.at(name)); }
    nlohmann::json stage_medians() const
    {
        nlohmann::json j;
        for (const auto& [name, v] : stage_ms) j[name] = median(v);
        return j;
    }
};

// Renders warmup + repeat frames with `render(camera, width, height)`; of each frame after the warm-up keeps its wall
// time and the stage times `stages(stats)` names (pairs of name and milliseconds).
template <class Render, class Stages>
auto time_frames(const Scene& s, const BenchArgs& a, Render&& render, Stages&& stages)
{
    using Stats = decltype(render(s.camera, s.width, s.height).stats);
    TimedFrames<Stats> t;
    for (int r = 0; r < a.warmup + a.repeat; ++r) {
        const auto f0 = Clock::now();
        const auto f = render(s.camera, s.width, s.height);
        const double ms = ms_since(f0);
        if (r < a.warmup) continue;
        t.frame_ms.push_back(ms);
        for (const auto& [name, stage] : stages(f.stats)) t.stage_ms[name].push_back(stage);
        t.last = f.stats;
    }
    return t;
}

nlohmann::json bench_reference(const Scene& s, const BenchArgs& a)
{
    std::vector<double> setup_ms, frame_ms;
    ReferenceStats stats;
    for (int r = 0; r < a.warmup + a.repeat; ++r) {
        const auto t0 = Clock::now();
        double setup = 0.0;
        if (s.is_volume()) {  // the regular-grid reference (reference/volume_integrator.h)
            const VolumeIntegrator integrator(s.volume(), s.tf);
            setup = ms_since(t0);
            render_reference(integrator, s.camera, s.width, s.height, stats);
        } else {
            const RayIntegrator integrator(s.mesh(), *s.topology, s.field, s.tf);
            setup = ms_since(t0);
            render_reference(integrator, s.camera, s.width, s.height, stats);
        }
        if (stats.failures) throw InputError(s.mesh().source, "rays were abandoned by the walk's guards");
        if (r >= a.warmup) {
            setup_ms.push_back(setup);
            frame_ms.push_back(stats.seconds * 1000.0);
        }
    }
    const double fm = median(frame_ms);
    nlohmann::json j;
    j["algo"] = "reference";
    j["backend"] = "cpu";
    j["frame_ms"] = fm;
    j["frame_ms_all"] = frame_ms;
    j["stages"] = {{"setup", median(setup_ms)}, {"integrate", fm}};
    j["rays"] = stats.rays;
    j["segments"] = stats.segments;
    j["rays_per_s"] = double(stats.rays) / (fm / 1000.0);
    j["segments_per_s"] = double(stats.segments) / (fm / 1000.0);
    return j;
}

// Times HAVS on one backend: the emulation, or GL on the chosen platform. `render` is called warmup + repeat times.
template <class Render>
nlohmann::json bench_havs_frames(const Scene& s, const BenchArgs& a, Render&& render)
{
    const auto t = time_frames(s, a, render, [](const gpu::HavsStats& st) {
        return std::vector<std::pair<std::string, double>>{{"sort", st.sort_ms},
                                                           {"vertex_and_setup", st.setup_ms},
                                                           {"raster_and_fragment", st.raster_fragment_ms},
                                                           {"flush", st.flush_ms},
                                                           {"readback", st.readback_ms}};
    });
    const gpu::HavsStats& last = t.last;
    const double fm = median(t.frame_ms);
    nlohmann::json j;
    j["algo"] = "havs";
    j["k"] = a.k;
    j["frame_ms"] = fm;
    j["frame_ms_all"] = t.frame_ms;
    j["stages"] = t.stage_medians();
    j["faces"] = last.faces;
    j["tetrahedra_per_s"] = double(s.mesh().tets.size()) / (fm / 1000.0);
    if (last.fragments) {
        j["fragments"] = last.fragments;
        j["fragments_per_s"] = double(last.fragments) / (t.stage_median("raster_and_fragment") / 1000.0);
        j["ordering_errors"] = last.ordering_errors;
    }
    return j;
}

nlohmann::json bench_havs(const Scene& s, const BenchArgs& a, const std::string& backend)
{
    gpu::HavsOptions o;
    o.k = a.k;
    const auto t0 = Clock::now();
    if (backend == "emu") {
        const gpu::HavsRenderer havs(s.mesh(), *s.topology, s.field, s.tf, o);
        const double build_ms = ms_since(t0);
        nlohmann::json j = bench_havs_frames(s, a, [&](const Camera& c, int w, int h) { return havs.render(c, w, h); });
        j["backend"] = "emu";
        j["build_ms"] = build_ms;
        return j;
    }
    // Timed as it renders by default for a user, without the diagnostics attachment (one RGBA32F target fewer to
    // fetch and write per fragment: 5 % of a Blunt Fin frame). Its counts (fragments, ordering errors) are the
    // emulation's, bit for bit (tests/test_havs_gl_frame.cpp), so the emulated row reports them.
    gpu::GlContext ctx(gpu::parse_gl_platform(a.gl));
    gpu::GlHavsRenderer havs(ctx, s.mesh(), *s.topology, s.field, s.tf, o, false);
    const double build_ms = ms_since(t0);
    nlohmann::json j = bench_havs_frames(s, a, [&](const Camera& c, int w, int h) { return havs.render(c, w, h); });
    j["backend"] = "gl";
    j["diagnostics"] = false;
    j["gl"] = ctx.info().summary();
    j["build_ms"] = build_ms;
    return j;
}

// Times VICP with one cell order on one backend: the emulation, or GL on the chosen platform.
nlohmann::json bench_vicp(const Scene& s, const BenchArgs& a, const std::string& order, const std::string& backend)
{
    gpu::VicpOptions o;
    o.order = gpu::parse_cell_order(order);
    const auto t0 = Clock::now();
    std::unique_ptr<gpu::GlContext> ctx;
    std::unique_ptr<gpu::VicpRenderer> emu;
    std::unique_ptr<gpu::GlVicpRenderer> gl;
    if (backend == "emu") {
        emu = std::make_unique<gpu::VicpRenderer>(s.mesh(), *s.topology, s.field, s.tf, o);
    } else {
        ctx = std::make_unique<gpu::GlContext>(gpu::parse_gl_platform(a.gl));
        gl = std::make_unique<gpu::GlVicpRenderer>(*ctx, s.mesh(), *s.topology, s.field, s.tf, o);
    }
    const gpu::VicpMesh& vm = emu ? emu->cpu_stage() : gl->cpu_stage();
    const double build_ms = ms_since(t0);
    const auto t = time_frames(
        s, a, [&](const Camera& c, int w, int h) { return emu ? emu->render(c, w, h) : gl->render(c, w, h); },
        [](const gpu::VicpStats& st) {
            return std::vector<std::pair<std::string, double>>{{"sort", st.sort_ms},
                                                               {"project", st.project_ms},
                                                               {"vertex_and_setup", st.setup_ms},
                                                               {"raster_and_fragment", st.raster_fragment_ms},
                                                               {"readback", st.readback_ms}};
        });
    const gpu::VicpStats& last = t.last;
    const double fm = median(t.frame_ms);
    nlohmann::json j;
    j["algo"] = "vicp";
    j["backend"] = backend;
    if (ctx) j["gl"] = ctx->info().summary();
    j["order"] = order;
    j["frame_ms"] = fm;
    j["frame_ms_all"] = t.frame_ms;
    j["build_ms"] = build_ms;
    j["stages"] = t.stage_medians();
    j["cells"] = last.cells;
    j["tetrahedra_per_s"] = double(s.mesh().tets.size()) / (fm / 1000.0);
    j["fragments"] = last.fragments;
    j["fragments_per_s"] = double(last.fragments) / (t.stage_median("raster_and_fragment") / 1000.0);
    j["ordering_errors"] = last.ordering_errors;
    j["cycle_breaks"] = last.order.cycle_breaks;
    j["bytes_sent_per_tet"] = gpu::vicp_sent_bytes_per_cell(vm);
    j["seed_bytes_sent_per_tet"] = gpu::kSeedBytesSentPerCell;
    j["resident_bytes_per_tet"] = gpu::vicp_resident_bytes_per_cell(vm);
    return j;
}

// Times the ray caster on one backend, post-classified or pre-integrated, with the default step and threshold.
nlohmann::json bench_raycast(const Scene& s, const BenchArgs& a, bool preintegrate, const std::string& backend)
{
    gpu::RaycastOptions o;
    o.preintegrate = preintegrate;
    const auto t0 = Clock::now();
    std::unique_ptr<gpu::GlContext> ctx;
    std::unique_ptr<gpu::RaycastRenderer> emu;
    std::unique_ptr<gpu::GlRaycastRenderer> gl;
    if (backend == "emu") {
        emu = std::make_unique<gpu::RaycastRenderer>(s.volume(), s.tf, o);
    } else {
        ctx = std::make_unique<gpu::GlContext>(gpu::parse_gl_platform(a.gl));
        gl = std::make_unique<gpu::GlRaycastRenderer>(*ctx, s.volume(), s.tf, o);
    }
    const gpu::RaycastVolume& rv = emu ? emu->cpu_stage() : gl->cpu_stage();
    const double build_ms = ms_since(t0);
    const auto t = time_frames(
        s, a, [&](const Camera& c, int w, int h) { return emu ? emu->render(c, w, h) : gl->render(c, w, h); },
        [](const gpu::RaycastStats& st) {
            return std::vector<std::pair<std::string, double>>{
                {"setup", st.setup_ms}, {"march", st.march_ms}, {"readback", st.readback_ms}};
        });
    nlohmann::json j;
    j["algo"] = "raycast";
    j["backend"] = backend;
    if (ctx) j["gl"] = ctx->info().summary();
    j["classification"] = preintegrate ? "pre-integrated" : "post";
    j["step"] = rv.options().step;
    j["volume_format"] = gpu::texel_format_name(rv.texel_format());
    j["frame_ms"] = median(t.frame_ms);
    j["frame_ms_all"] = t.frame_ms;
    j["build_ms"] = build_ms;
    j["stages"] = t.stage_medians();
    j["samples"] = t.last.samples;
    j["samples_per_s"] = double(t.last.samples) / (t.stage_median("march") / 1000.0);
    j["texture_bytes"] = rv.texture_bytes();
    return j;
}

}  // namespace

void register_bench(CLI::App& app)
{
    auto* cmd = app.add_subcommand("bench", "Time each algorithm and each stage (median over repetitions)");
    auto a = std::make_shared<BenchArgs>();
    add_scene_options(*cmd, a->scene);
    cmd->add_option("--algos,--algo", a->algos, "Comma-separated algorithms (reference, havs, vicp, raycast)")->capture_default_str();
    cmd->add_option("--repeat", a->repeat, "Timed repetitions")->capture_default_str()->check(CLI::Range(1, 1000));
    cmd->add_option("--warmup", a->warmup, "Untimed repetitions first")->capture_default_str()->check(CLI::Range(0, 100));
    cmd->add_option("--k", a->k, "HAVS: k-buffer entries")->capture_default_str();
    cmd->add_option("--backend,--backends", a->backends, "Comma-separated backends of the GPU algorithms (emu, gl)")
        ->capture_default_str();
    cmd->add_option("--gl", a->gl, "With the gl backend: osmesa | egl")->capture_default_str();
    cmd->add_option("--orders,--order", a->orders, "VICP: comma-separated cell orders (mpvonc, centroid)")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object on stdout");
    cmd->callback([a] {
        const std::vector<std::string> algos = split_list(a->algos), backends = split_list(a->backends);
        for (const auto& x : algos) run_algorithm_check(x);
        for (const auto& b : backends)
            if (b != "emu" && b != "gl") throw InputError("", "--backend must list emu and/or gl, not '" + b + "'");
        gpu::parse_gl_platform(a->gl);
        const std::vector<std::string> orders = split_list(a->orders);
        for (const auto& o : orders) gpu::parse_cell_order(o);
        const auto t0 = Clock::now();
        const Scene s = setup_scene(a->scene);
        const double load_ms = ms_since(t0);
        for (const auto& x : algos) check_algorithm_scene(s, x);  // refused before timing
        // Per element: tetrahedra of a mesh, voxels (samples) of a regular grid.
        const auto& dims = s.is_volume() ? s.volume().dims : std::array<int64_t, 3>{0, 0, 0};
        const std::size_t elements =
            s.is_volume() ? std::size_t(dims[0] * dims[1] * dims[2]) : s.mesh().tets.size();
        const char* element = s.is_volume() ? "voxels" : "tetrahedra";
        nlohmann::json out;
        out["mesh"] = a->scene.input.path;
        out[element] = elements;
        out["width"] = s.width;
        out["height"] = s.height;
        out["load_ms"] = load_ms;
        out["machine"] = {{"cpu", cpu_model()}, {"threads", std::thread::hardware_concurrency()}};
        out["results"] = nlohmann::json::array();
        for (const auto& x : algos) {
            if (x == "reference") {
                out["results"].push_back(bench_reference(s, *a));
                continue;
            }
            if (x == "raycast") {
                for (const auto& b : backends)
                    for (bool pre : {false, true}) out["results"].push_back(bench_raycast(s, *a, pre, b));
                continue;
            }
            if (x == "vicp") {
                for (const auto& b : backends)
                    for (const auto& o : orders) out["results"].push_back(bench_vicp(s, *a, o, b));
                continue;
            }
            for (const auto& b : backends) out["results"].push_back(bench_havs(s, *a, b));
        }
        out["peak_rss_mib"] = peak_rss_mib();
        out[s.is_volume() ? "bytes_per_voxel" : "bytes_per_tet"] = peak_rss_mib() * 1024.0 * 1024.0 / double(elements);
        if (a->json) {
            std::printf("%s\n", out.dump(1).c_str());
            return;
        }
        std::printf("%s: %zu %s, %dx%d, %s (%u threads)\n", a->scene.input.path.c_str(), elements, element, s.width,
                    s.height, cpu_model().c_str(), std::thread::hardware_concurrency());
        for (const auto& r : out["results"]) {
            std::printf("  %-10s %-4s %9.1f ms/frame ", r["algo"].get<std::string>().c_str(),
                        r["backend"].get<std::string>().c_str(), r["frame_ms"].get<double>());
            if (r["algo"] == "reference")
                std::printf(" %6.2f Mrays/s  %6.2f Msegments/s  (setup %.1f ms)\n",
                            r["rays_per_s"].get<double>() / 1e6, r["segments_per_s"].get<double>() / 1e6,
                            r["stages"]["setup"].get<double>());
            else if (r["algo"] == "raycast")
                std::printf(" %-14s %6.2f Msamples/s  setup %.1f, march %.1f, readback %.1f ms; step %g, %s texture\n",
                            r["classification"].get<std::string>().c_str(), r["samples_per_s"].get<double>() / 1e6,
                            r["stages"]["setup"].get<double>(), r["stages"]["march"].get<double>(),
                            r["stages"]["readback"].get<double>(), r["step"].get<double>(),
                            r["volume_format"].get<std::string>().c_str());
            else if (r["algo"] == "vicp")
                std::printf(" %-8s %6.2f Mfragments/s  sort %.1f, project %.1f, vertex+setup %.1f, raster+fragment "
                            "%.1f ms; %.0f bytes sent per tetrahedron (the seed's: %.0f); %llu ordering errors, %llu "
                            "cycle breaks\n",
                            r["order"].get<std::string>().c_str(), r["fragments_per_s"].get<double>() / 1e6,
                            r["stages"]["sort"].get<double>(), r["stages"]["project"].get<double>(),
                            r["stages"]["vertex_and_setup"].get<double>(),
                            r["stages"]["raster_and_fragment"].get<double>(), r["bytes_sent_per_tet"].get<double>(),
                            r["seed_bytes_sent_per_tet"].get<double>(),
                            (unsigned long long)r["ordering_errors"].get<uint64_t>(),
                            (unsigned long long)r["cycle_breaks"].get<uint64_t>());
            else
                std::printf(" k=%d  %6.2f Mfragments/s  sort %.1f, vertex+setup %.1f, raster+fragment %.1f, flush %.1f, "
                            "readback %.1f ms (built in %.0f ms)\n",
                            r["k"].get<int>(), r.value("fragments_per_s", 0.0) / 1e6, r["stages"]["sort"].get<double>(),
                            r["stages"]["vertex_and_setup"].get<double>(),
                            r["stages"]["raster_and_fragment"].get<double>(), r["stages"]["flush"].get<double>(),
                            r["stages"]["readback"].get<double>(), r["build_ms"].get<double>());
        }
        std::printf("  peak memory %.1f MiB (%.0f bytes per %s)\n", out["peak_rss_mib"].get<double>(),
                    out[s.is_volume() ? "bytes_per_voxel" : "bytes_per_tet"].get<double>(),
                    s.is_volume() ? "voxel" : "tetrahedron");
    });
}

}  // namespace uvr::cli
