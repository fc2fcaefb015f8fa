// `uvr gpu-check MESH [input options] --out OUT`: the GPU check of docs/gpu.md. Picks the GL device, says what it is
// and which extensions HAVS's k-buffer path uses, then renders HAVS (k = 6 and the largest k), VICP and the ray caster
// at each size, each measured against the CPU reference with uvr compare's measures and timed as uvr bench times.
// OUT/gpu-check.json and OUT/index.html are rewritten after every run; a failed run is kept with its error.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <memory>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/options.h"
#include "bench/report.h"
#include "gpu/gl/gl_context.h"
#include "gpu/gl/gl_fragment_access.h"
#include "gpu/havs/gl_havs.h"
#include "reference/builtin_mesh.h"
#include "reference/choice.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/timing.h"

namespace uvr::cli {

namespace {

enum class GpuChoice { any, llvmpipe };
inline constexpr Choices<GpuChoice, 2> kGpuChoices{
    {{GpuChoice::any, "auto", "a hardware GPU through EGL, else llvmpipe"},
     {GpuChoice::llvmpipe, "llvmpipe", "Mesa's llvmpipe through OSMesa"}}};

struct GpuCheckOptions {
    InputOptions mesh;                        // the check's real mesh (Blunt Fin in the bundle)
    std::string gpu = "auto";                 // kGpuChoices
    AlgoOptions table;                        // the options table's row --gl-device (with --gpu auto)
    std::string sizes = "512,1024";           // square images, each size a round of the check
    int grid = 120;                           // builtin:grid-N beside MESH (120: 10,368,000 tetrahedra); 0: none
    std::string volume = kBuiltinVolumePath;  // the ray caster's regular grid
    int warmup = 1, repeat = 3;               // frames per configuration, as uvr bench
    double time_limit = 240.0;                // seconds after which no new run starts
    std::string out;
    bool json = false;
};

// The device the check renders on and why: EGL's hardware device where there is one (or the one --gl-device names),
// else llvmpipe through OSMesa (the bundle carries Mesa's OSMesa, not its EGL driver: docs/gpu.md).
struct CheckDevice {
    std::string platform;  // "egl" | "osmesa"
    int egl_device = gpu::kAnyEglDevice;
    gpu::GlInfo info;
    std::string choice;  // a sentence for the user
};

CheckDevice choose_device(const GpuCheckOptions& o, GpuChoice choice)
{
    const auto osmesa = [](const std::string& why) {
        const gpu::GlContext ctx(gpu::GlPlatform::osmesa);
        return CheckDevice{"osmesa", gpu::kAnyEglDevice, ctx.info(), why + ": llvmpipe through OSMesa"};
    };
    if (choice == GpuChoice::llvmpipe) return osmesa("--gpu llvmpipe");
    const int device = o.table.gl_device;
    std::string why;
    try {
        const gpu::GlContext ctx(gpu::GlPlatform::egl, gpu::GlProfile::core, device);
        if (ctx.info().hardware || device != gpu::kAnyEglDevice)
            return CheckDevice{"egl", device, ctx.info(), "EGL: " + ctx.info().detail};
        why = "no hardware GPU through EGL (it offers " + ctx.info().detail + ")";
    } catch (const InputError& e) {
        if (device != gpu::kAnyEglDevice) throw;  // the device asked for: its error lists the devices
        why = std::string("no hardware GPU through EGL (") + e.what() + ")";
    }
    return osmesa(why);
}

// The extensions the fragment programs' routes look for, the route this device takes (gl_fragment_access.h; the same
// for HAVS's k-buffer and VICP's compositing), or why it has none, and HAVS's largest k (without diagnostics).
nlohmann::json kbuffer_path(const gpu::GlInfo& info)
{
    nlohmann::json j;
    for (const char* e :
         {"GL_EXT_shader_framebuffer_fetch", "GL_ARB_fragment_shader_interlock", "GL_NV_fragment_shader_interlock"})
        j["extensions"][e] = info.has_extension(e);
    try {
        const gpu::FragmentAccessPath p =
            gpu::choose_fragment_access(info, gpu::FramebufferAccess::automatic, "HAVS and VICP");
        j["path"] = !p.images ? "framebuffer fetch"
                    : p.interlock.empty() ? "image load/store (llvmpipe: no interlock needed)"
                                          : "image load/store in a fragment-shader interlock (" + p.interlock + ")";
    } catch (const InputError& e) {
        j["path"] = "none";
        j["why"] = e.what();
    }
    j["max_k"] = gpu::GlHavsRenderer::max_k(info, false);
    return j;
}

// The share of pixels whose four channels are not all the same floats in `a` and `b` (same size).
double pixels_differing(const Image& a, const Image& b)
{
    std::size_t differ = 0;
    for (std::size_t p = 0; p + 3 < a.rgba.size(); p += 4)
        differ += std::memcmp(&a.rgba[p], &b.rgba[p], 4 * sizeof(float)) != 0 ? 1 : 0;
    return a.rgba.empty() ? 0.0 : double(differ) / double(a.rgba.size() / 4);
}

// How well llvmpipe predicts this device (docs/gpu.md): the same frame by the CPU emulation, its error against the
// reference, and the device's frame against it (RMSE, largest error, the share of pixels differing in any bit). On
// llvmpipe the emulation is llvmpipe's own arithmetic, so the difference is zero on every default path.
void add_emulation(nlohmann::json& j, const Scene& s, const std::string& algo, const AlgoOptions& o,
                   const Image& gpu_frame, const Image& reference)
{
    AlgoOptions eo = o;
    eo.backend = "emu";
    const AlgoResult emu = run_algorithm(s, algo, eo);
    j["emulation"] = measures_json(measure_errors(emu.image, reference));
    const ErrorMeasures d = measure_errors(gpu_frame, emu.image);
    j["gpu_vs_emulation"] = {{"rmse", d.rmse}, {"max_abs", d.max_abs},
                             {"pixels_differing", pixels_differing(gpu_frame, emu.image)}};
}

// One configuration: timed frames, the last one measured against the reference. `cells` counts the scene's
// tetrahedra (0 for a regular grid).
nlohmann::json check_run(const Scene& s, const std::string& name, const std::string& algo, const AlgoOptions& o,
                         const GpuCheckOptions& c, const Image& reference, std::size_t cells)
{
    Image last;
    nlohmann::json row = time_frames(s, find_algorithm(algo), o, c.warmup, c.repeat, &last);
    nlohmann::json j = measures_json(measure_errors(last, reference));
    j["scene"] = name;
    j["algo"] = algo;
    j["label"] = find_algorithm(algo).label(o);
    j["k"] = algo == "havs" ? nlohmann::json(o.k) : nlohmann::json();
    j["width"] = s.width;
    j["height"] = s.height;
    j["frame_ms"] = row["frame_ms"];
    j["build_ms"] = row["build_ms"];
    j["stages_ms"] = row["stages"];
    j["tetrahedra"] = cells;
    j["tetrahedra_per_second"] = cells ? double(cells) / (row["frame_ms"].get<double>() / 1000.0) : 0.0;
    j["peak_memory_mib"] = double(peak_memory_bytes()) / (1024.0 * 1024.0);
    add_emulation(j, s, algo, o, last, reference);
    std::printf("%-10s %5dx%-5d %-16s rmse %.3e max %.3e  %9.2f ms/frame\n", name.c_str(), s.width, s.height,
                j["label"].get<std::string>().c_str(), j["rmse"].get<double>(), j["max_abs"].get<double>(),
                j["frame_ms"].get<double>());
    std::fflush(stdout);
    return j;
}

// What the check has measured so far, rewritten (OUT/gpu-check.json and the page, each replaced whole) after every
// run, so that a check stopped at any point leaves valid files holding every run it finished (docs/gpu.md).
struct CheckRecord {
    std::string out;
    nlohmann::json j;
    Clock::time_point t0 = Clock::now();
    double time_limit = 0.0;

    void save() const;
    // True, and the record says why, once the time limit has passed: no new run starts.
    bool out_of_time()
    {
        if (ms_since(t0) <= 1000.0 * time_limit) return false;
        j["stopped"] = "the time limit of " + std::to_string(time_limit) + " s passed (--time-limit)";
        return true;
    }
    // A run this device has no route for, kept with the reason: the check goes on without it.
    void skipped(const std::string& scene, const std::string& what, int size, const std::string& why)
    {
        j["runs"].push_back({{"scene", scene}, {"label", what}, {"width", size}, {"height", size}, {"skipped", why}});
        std::printf("%-10s %5dx%-5d %-16s skipped: %s\n", scene.c_str(), size, size, what.c_str(), why.c_str());
        save();
    }
    // A run that failed, kept with its error: the check goes on without it.
    void failed(const std::string& scene, const std::string& what, int size, const std::exception& e)
    {
        j["runs"].push_back({{"scene", scene}, {"label", what}, {"width", size}, {"height", size}, {"error", e.what()}});
        std::printf("%-10s %5dx%-5d %-16s failed: %s\n", scene.c_str(), size, size, what.c_str(), e.what());
        save();
    }
};

// One run, timed and measured, or its error; saved either way. False once the time limit stops the check.
bool record_run(CheckRecord& rec, const Scene& s, const std::string& name, const std::string& algo,
                const AlgoOptions& o, const GpuCheckOptions& c, const Image& reference, std::size_t cells)
{
    if (rec.out_of_time()) return false;
    try {
        rec.j["runs"].push_back(check_run(s, name, algo, o, c, reference, cells));
        rec.save();
    } catch (const std::exception& e) {
        rec.failed(name, find_algorithm(algo).label(o), s.width, e);
    }
    return true;
}

// Every run on one scene at one size: HAVS at k = 6 and at the largest k and VICP on a mesh, the ray caster on a grid;
// the CPU reference first, its time recorded apart from the GPU's frames. False once the time limit stops the check.
bool check_scene(const SceneOptions& so, const std::string& name, const CheckDevice& d, const GpuCheckOptions& c,
                 CheckRecord& rec)
{
    if (rec.out_of_time()) return false;
    const Scene s = setup_scene(so);
    const AlgoResult ref = run_algorithm(s, "reference", AlgoOptions{});
    rec.j["references"].push_back(
        {{"scene", name}, {"width", s.width}, {"height", s.height}, {"ms", ref.ms}, {"cached", ref.cached}});
    AlgoOptions o;
    o.backend = "gl";
    o.gl = d.platform;
    o.gl_device = d.egl_device;
    o.diagnostics = false;  // as uvr bench times them; the image is the same
    if (s.is_volume()) return record_run(rec, s, name, "raycast", o, c, ref.image, 0);
    const std::size_t cells = s.mesh().tets.size();
    const nlohmann::json path = kbuffer_path(d.info);
    if (path["path"] == "none") {  // neither algorithm has a route here: both skipped, the reason kept
        for (const char* algo : {"havs", "vicp"})
            rec.skipped(name, algo, s.width, path["why"].get<std::string>());
        return true;
    }
    // k = 6 (the HAVS paper's) and the largest k, each once.
    const int kmax = gpu::GlHavsRenderer::max_k(d.info, false);
    for (const int k : std::set<int>{std::min(6, kmax), kmax}) {
        o.k = k;
        if (!record_run(rec, s, name, "havs", o, c, ref.image, cells)) return false;
    }
    return record_run(rec, s, name, "vicp", o, c, ref.image, cells);
}

void write_check_page(const std::string& dir, const nlohmann::json& j)
{
    std::string html =
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>uvr GPU check</title>"
        "<style>body{font-family:sans-serif}td,th{padding:2px 8px;text-align:right}</style></head><body>"
        "<h1>uvr GPU check</h1><p>" +
        escape_markup(j["renderer"].get<std::string>()) + "<br>" + escape_markup(j["choice"].get<std::string>()) +
        "<br>k-buffer: " + escape_markup(j["kbuffer"]["path"].get<std::string>()) +
        "</p><table><tr><th>scene</th><th>size</th><th>run</th><th>RMSE</th><th>largest error</th>"
        "<th>ms per frame</th><th>tetrahedra per second</th><th>emulation's RMSE</th>"
        "<th>pixels differing from the emulation</th></tr>";
    for (const auto& r : j["runs"]) {
        if (r.contains("error") || r.contains("skipped")) {
            const bool failed = r.contains("error");
            html += "<tr><td>" + escape_markup(r["scene"].get<std::string>()) + "</td><td>" +
                    std::to_string(r["width"].get<int>()) + "&times;" + std::to_string(r["height"].get<int>()) +
                    "</td><td>" + escape_markup(r["label"].get<std::string>()) + "</td><td colspan=\"6\">" +
                    (failed ? "failed: " : "skipped: ") +
                    escape_markup(r[failed ? "error" : "skipped"].get<std::string>()) + "</td></tr>";
            continue;
        }
        char line[512];
        std::snprintf(line, sizeof line,
                      "<tr><td>%s</td><td>%d&times;%d</td><td>%s</td><td>%.3e</td><td>%.3e</td><td>%.2f</td>"
                      "<td>%.3g</td><td>%.3e</td><td>%.4f</td></tr>",
                      escape_markup(r["scene"].get<std::string>()).c_str(), r["width"].get<int>(),
                      r["height"].get<int>(), escape_markup(r["label"].get<std::string>()).c_str(),
                      r["rmse"].get<double>(), r["max_abs"].get<double>(), r["frame_ms"].get<double>(),
                      r["tetrahedra_per_second"].get<double>(), r["emulation"]["rmse"].get<double>(),
                      r["gpu_vs_emulation"]["pixels_differing"].get<double>());
        html += line;
    }
    html += "</table><p>" +
            std::string(j["complete"].get<bool>() ? "Every run of the check is here."
                        : j.contains("stopped")   ? "Stopped: " + escape_markup(j["stopped"].get<std::string>()) + "."
                                                  : "The check is still running, or was stopped.") +
            " Every number: <a href=\"gpu-check.json\">gpu-check.json</a></p></body></html>\n";
    write_file_atomically(dir + "/index.html", html);
}

void CheckRecord::save() const
{
    write_file_atomically(out + "/gpu-check.json", j.dump(1) + "\n");
    write_check_page(out, j);
}

// The scenes in the order that gives the most for the time: the real mesh at every size (largest first), the ray
// caster's volume, then the large grid. Each: its options and the name the runs carry.
std::vector<std::pair<SceneOptions, std::string>> check_scenes(const GpuCheckOptions& c)
{
    std::vector<std::string> sizes = split_list(c.sizes);
    std::reverse(sizes.begin(), sizes.end());
    std::vector<std::pair<SceneOptions, std::string>> scenes;
    const auto add = [&](const InputOptions& input, const std::string& name) {
        for (const std::string& n : sizes) {
            SceneOptions so;
            so.size = n + "x" + n;  // checked where the scene reads it
            so.input = input;
            scenes.push_back({so, name});
        }
    };
    add(c.mesh, std::filesystem::path(c.mesh.path).stem().string());
    InputOptions volume;
    volume.path = c.volume;
    add(volume, std::filesystem::path(c.volume).stem().string());
    if (c.grid > 0) {
        InputOptions grid;
        grid.path = "builtin:grid-" + std::to_string(c.grid);
        add(grid, "grid-" + std::to_string(c.grid));
    }
    return scenes;
}

void run_gpu_check(const GpuCheckOptions& c)
{
    if (split_list(c.sizes).empty()) throw InputError("", "--sizes needs at least one size");
    if (c.warmup < 0 || c.repeat < 1) throw InputError("", "--warmup takes 0 or more frames, --repeat 1 or more");
    if (c.grid < 0) throw InputError("", "--grid takes 0 (none) or the N of builtin:grid-N");
    if (!(c.time_limit > 0.0)) throw InputError("", "--time-limit takes a positive number of seconds");
    const GpuChoice gpu_choice = parse_choice("--gpu", kGpuChoices, c.gpu);
    std::error_code ec;
    std::filesystem::create_directories(c.out, ec);
    if (ec) throw InputError(c.out, "cannot create the directory: " + ec.message());
    const CheckDevice d = choose_device(c, gpu_choice);
    CheckRecord rec{c.out, {}, Clock::now(), c.time_limit};
    nlohmann::json& j = rec.j;
    j["renderer"] = d.info.summary();
    j["vendor"] = d.info.vendor;
    j["gl_renderer"] = d.info.renderer;
    j["gl_version"] = d.info.version;
    j["extensions"] = d.info.extensions;
    j["platform"] = d.platform;
    j["hardware"] = d.info.hardware;
    j["choice"] = d.choice;
    j["kbuffer"] = kbuffer_path(d.info);
    j["machine"] = {{"threads", std::thread::hardware_concurrency()}};
    j["complete"] = false;
    j["runs"] = nlohmann::json::array();
    j["references"] = nlohmann::json::array();
    rec.save();
    std::printf("GL: %s\n%s\nk-buffer: %s (largest k %d)\n", j["renderer"].get<std::string>().c_str(), d.choice.c_str(),
                j["kbuffer"]["path"].get<std::string>().c_str(), j["kbuffer"]["max_k"].get<int>());
    bool finished = true;
    for (const auto& [so, name] : check_scenes(c)) {
        try {
            finished = check_scene(so, name, d, c, rec);
        } catch (const std::exception& e) {  // a scene that cannot be made or drawn: kept with its error
            rec.failed(name, "scene", std::stoi(so.size), e);
        }
        if (!finished) break;
    }
    j["complete"] = finished;
    rec.save();
    if (c.json) std::printf("%s\n", j.dump(1).c_str());
}

}  // namespace

void register_gpu_check(CLI::App& app)
{
    auto* cmd = app.add_subcommand("gpu-check",
                                   "The GPU check (docs/gpu.md): each GL algorithm's error against the "
                                   "reference and its speed, on the GPU or on llvmpipe");
    auto c = std::make_shared<GpuCheckOptions>();
    add_input_options(*cmd, c->mesh);
    cmd->add_option("--gpu", c->gpu, choices_help(kGpuChoices))->capture_default_str();
    add_algo_options(*cmd, c->table, true, {"gl-device"});
    cmd->add_option("--sizes", c->sizes, "Square image sizes, comma-separated")->capture_default_str();
    cmd->add_option("--grid", c->grid, "builtin:grid-N beside the mesh (N^3 cubes of six tetrahedra; 0: none)")
        ->capture_default_str();
    cmd->add_option("--volume", c->volume, "The ray caster's regular grid")->capture_default_str();
    cmd->add_option("--warmup", c->warmup, "Frames rendered before the timed ones")->capture_default_str();
    cmd->add_option("--repeat", c->repeat, "Timed frames per configuration (the median is kept)")
        ->capture_default_str();
    cmd->add_option("--time-limit", c->time_limit,
                    "Seconds after which no new run starts; the files hold every run finished")
        ->capture_default_str();
    cmd->add_option("--out", c->out, "Directory for gpu-check.json and index.html")->required();
    cmd->add_flag("--json", c->json, "Print gpu-check.json's object on stdout");
    cmd->callback([c] { run_gpu_check(*c); });
}

}  // namespace uvr::cli
