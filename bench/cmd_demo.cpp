// `uvr demo`: the whole lab on built-in data, no argument needed, summarised on one landing page (DIR/index.html): the
// torus's ground truth beside HAVS and VICP, emulated and on GL (OSMesa), each GL image marked where it has the
// emulation's bits; HAVS through the paper's own ARB programs beside the emulation with the same entries; the ray
// caster on a built-in volume; a short error-versus-k sweep; the error budgets of HAVS and VICP. Each part keeps its
// own report page, which the landing page links.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/algorithms.h"
#include "bench/budget.h"
#include "bench/commands.h"
#include "bench/report.h"
#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr::cli {

namespace {

bool same_image_bits(const std::string& a, const std::string& b)
{
    const Image x = read_npy(a), y = read_npy(b);
    return x.width == y.width && x.height == y.height && x.rgba.size() == y.rgba.size() &&
           std::memcmp(x.rgba.data(), y.rgba.data(), x.rgba.size() * sizeof(float)) == 0;
}

// The demo's steps, each announced on its own line.
class Steps {
public:
    explicit Steps(int total) : total_(total) {}
    void begin(const std::string& what)
    {
        std::printf("uvr demo [%d/%d] %s\n", ++done_, total_, what.c_str());
        std::fflush(stdout);
    }

private:
    int total_, done_ = 0;
};

// One comparison on the landing page: its report under DIR/`sub`, and the results (metrics.json's) with, on GL and
// ARB rows, whether the image has the bits of its emulated twin (`twin_dir`'s image of the same algorithm).
nlohmann::json compare_part(const Scene& s, const std::vector<std::string>& algos, const AlgoOptions& o,
                            const std::string& dir, const std::string& sub, const std::string& title,
                            const std::string& data_name)
{
    nlohmann::json part;
    part["title"] = title;
    part["page"] = sub + "/index.html";
    try {
        nlohmann::json m = run_compare(s, algos, o, dir + "/" + sub, data_name);
        for (auto& r : m["results"]) r["image"] = sub + "/" + r["image"].get<std::string>();
        part["results"] = m["results"];
    } catch (const InputError& e) {  // no GL context here: the page says why instead of showing the part
        part["unavailable"] = e.what();
        part.erase("page");
    }
    return part;
}

// Marks each non-reference result of `part` with whether its image equals, bit for bit, the image of the same
// algorithm in `twin` (its emulated counterpart).
void mark_same_bits(nlohmann::json& part, const nlohmann::json& twin, const std::string& dir)
{
    if (!part.contains("results") || !twin.contains("results")) return;
    for (auto& r : part["results"]) {
        if (r["algo"] == "reference") continue;
        for (const auto& t : twin["results"])
            if (t["algo"] == r["algo"] && t["algo"] != "reference") {
                const auto npy = [&](const nlohmann::json& x) {
                    std::string png = dir + "/" + x["image"].get<std::string>();
                    return png.substr(0, png.size() - 4) + ".npy";
                };
                r["same_bits_as"] = t["label"];
                r["same_bits"] = same_image_bits(npy(r), npy(t));
            }
    }
}

// The mesh's comparisons: emulated, on GL, through the paper's ARB programs, each GL image marked against its twin.
void demo_mesh_parts(const Scene& s, const std::string& dir, Steps& steps, nlohmann::json& page)
{
    const std::vector<std::string> mesh_algos = {"reference", "havs", "vicp"};
    AlgoOptions emu;
    steps.begin("the reference, HAVS and VICP, emulated");
    const nlohmann::json emulated = compare_part(s, mesh_algos, emu, dir, "compare",
                                                 "Emulated (the CPU computes llvmpipe's bits)", "builtin:torus");
    page["parts"].push_back(emulated);

    AlgoOptions gl = emu;
    gl.backend = "gl";
    steps.begin("HAVS and VICP in GLSL on OSMesa (llvmpipe)");
    nlohmann::json on_gl =
        compare_part(s, mesh_algos, gl, dir, "compare-gl", "On GL (OSMesa, llvmpipe)", "builtin:torus");
    mark_same_bits(on_gl, emulated, dir);
    page["parts"].push_back(on_gl);

    // The published programs run the published entries; their twin is the emulation with the same entries.
    steps.begin("HAVS through the paper's own ARB programs, and emulated with the same entries");
    AlgoOptions paper = emu;
    paper.entries = "paper";
    const nlohmann::json published_emulated =
        compare_part(s, {"reference", "havs"}, paper, dir, "compare-paper-entries",
                     "Emulated with the published entries", "builtin:torus");
    AlgoOptions arb = emu;
    arb.backend = "arb";
    nlohmann::json on_arb =
        compare_part(s, {"reference", "havs"}, arb, dir, "compare-arb",
                     "The paper's own ARB programs (OSMesa, compatibility profile)", "builtin:torus");
    mark_same_bits(on_arb, published_emulated, dir);
    page["parts"].push_back(published_emulated);
    page["parts"].push_back(on_arb);
}

// The ray caster on the built-in volume, emulated and on GL.
void demo_volume_parts(const std::string& size, const std::string& dir, Steps& steps, nlohmann::json& page)
{
    AlgoOptions emu, gl;
    gl.backend = "gl";
    SceneOptions vo;
    vo.input.path = kBuiltinVolumePath;
    vo.view = "30,50";
    vo.size = size;
    const Scene v = setup_scene(vo);
    steps.begin("the ray caster on a built-in volume (a fuzzy torus on a 64 x 64 x 32 grid), emulated");
    const nlohmann::json ray_emulated =
        compare_part(v, {"reference", "raycast"}, emu, dir, "raycast", "The ray caster, emulated", kBuiltinVolumePath);
    steps.begin("the ray caster in GLSL");
    nlohmann::json ray_gl =
        compare_part(v, {"reference", "raycast"}, gl, dir, "raycast-gl", "The ray caster on GL", kBuiltinVolumePath);
    mark_same_bits(ray_gl, ray_emulated, dir);
    page["parts"].push_back(ray_emulated);
    page["parts"].push_back(ray_gl);
}

// A short sweep and the error budgets of HAVS and VICP, with their plots for the landing page.
void demo_sweep_and_budgets(const Scene& s, const std::string& dir, Steps& steps, nlohmann::json& page)
{
    const AlgoOptions emu;
    std::error_code ec;
    // A short sweep through the same program, as a user would run it.
    steps.begin("error against k (uvr sweep)");
    const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (ec || self.empty()) throw InputError("/proc/self/exe", "cannot find the uvr program to run the sweep");
    const std::string sweep = "'" + self +
                              "' sweep builtin:torus-small --k 1,2,4,8,16 --views 3 --size 256x256 "
                              "--report '" +
                              dir + "/sweep' > /dev/null";
    std::fflush(stdout);
    if (std::system(sweep.c_str()) != 0) throw InputError(dir, "the demo's sweep failed");
    page["sweep"] = "sweep/index.html";
    if (std::filesystem::exists(dir + "/sweep/error_vs_k.png")) page["sweep_plot"] = "sweep/error_vs_k.png";

    // The error budgets of HAVS and VICP on the same scene (uvr budget).
    steps.begin("where HAVS's and VICP's errors come from (uvr budget)");
    page["budgets"] = nlohmann::json::array();
    for (const std::string algo : {"havs", "vicp"}) {
        run_budget(s, algo, emu, dir + "/budget-" + algo, "builtin:torus");
        nlohmann::json b = {{"title", algo == "havs" ? "HAVS (k = 6)" : "VICP (MPVONC)"},
                            {"page", "budget-" + algo + "/index.html"}};
        b["chart"] = "budget-" + algo + "/budget.svg";
        page["budgets"].push_back(b);
    }
}

// One line per comparison on stdout: each algorithm's errors and its twin's bits.
void print_demo_summary(const nlohmann::json& page)
{
    for (const auto& part : page["parts"]) {
        if (part.contains("unavailable")) {
            std::printf("uvr demo: %s: not run here (%s)\n", part["title"].get<std::string>().c_str(),
                        part["unavailable"].get<std::string>().c_str());
            continue;
        }
        for (const auto& r : part["results"]) {
            if (r["algo"] == "reference") continue;
            std::string twin;
            if (r.contains("same_bits"))
                twin = (r["same_bits"].get<bool>() ? ", same bits as " : ", NOT the bits of ") +
                       r["same_bits_as"].get<std::string>();
            std::printf("uvr demo: %-24s RMSE %.3g, largest error %.3g%s\n", r["label"].get<std::string>().c_str(),
                        r["rmse"].get<double>(), r["max_abs"].get<double>(), twin.c_str());
        }
    }
}

}  // namespace

void register_demo(CLI::App& app)
{
    auto* cmd = app.add_subcommand("demo", "Run the lab on built-in data (a tetrahedralized torus and a volume) and "
                                           "summarise it on one page");
    auto out_dir = std::make_shared<std::string>("uvr-demo");
    auto size = std::make_shared<std::string>("512x512");
    cmd->add_option("--out", *out_dir, "Directory for the demo's reports")->capture_default_str();
    cmd->add_option("--size", *size, "Image size of the comparisons, WxH")->capture_default_str();
    cmd->callback([out_dir, size] {
        const auto t0 = std::chrono::steady_clock::now();
        const std::string dir = *out_dir;
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) throw InputError(dir, "cannot create the demo directory: " + ec.message());
        Steps steps(8);
        SceneOptions so;
        so.input.path = "builtin:torus";
        so.view = "30,50";
        so.size = *size;
        const Scene s = setup_scene(so);
        const TetMesh& mesh = s.mesh();
        std::printf("uvr demo: built-in torus (TetGen): %zu points, %zu tetrahedra, %zu faces (%zu boundary)\n",
                    mesh.points.size(), mesh.tets.size(), s.topology->faces.size(), s.topology->boundary_faces);
        nlohmann::json page;
        page["parts"] = nlohmann::json::array();
        demo_mesh_parts(s, dir, steps, page);
        demo_volume_parts(*size, dir, steps, page);
        demo_sweep_and_budgets(s, dir, steps, page);
        steps.begin("the landing page");
        page["mesh"] = {{"points", mesh.points.size()}, {"tetrahedra", mesh.tets.size()}};
        write_demo_page(dir, page);
        print_demo_summary(page);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("uvr demo: done in %.1f s. Open %s/index.html\n", secs, dir.c_str());
    });
}

}  // namespace uvr::cli
