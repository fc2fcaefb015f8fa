#include "bench/algo_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "gpu/gl/gl_context.h"
#include "gpu/havs/havs_setup.h"
#include "gpu/pipeline/exact_coverage.h"
#include "gpu/pipeline/interpolation.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/pipeline/segment.h"
#include "gpu/pipeline/texture_sampling.h"
#include "gpu/raycast/raycast_setup.h"
#include "gpu/vicp/vicp_order.h"
#include "reference/choice.h"
#include "reference/error.h"
#include "reference/partition.h"

namespace uvr::cli {

int parse_k(const std::string& v)
{
    if (v == "all") return gpu::kEveryFragment;
    char* end = nullptr;
    errno = 0;
    const long k = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno != 0 || k < 1 || k > std::numeric_limits<int>::max())
        throw InputError("", "--k must be a whole number of at least 1, or all, not '" + v + "'");
    return int(k);
}

nlohmann::json k_json(int k)
{
    if (k == gpu::kEveryFragment) return "all";
    return k;
}

std::string python_keyword(const AlgoOption& option)
{
    if (!option.python.empty()) return option.python;
    std::string k = option.name;
    for (char& c : k)
        if (c == '-') c = '_';
    return k;
}

namespace {

// A number, all of `text`; InputError naming --NAME and `what` otherwise.
double parse_number(const std::string& name, const std::string& text, const char* what)
{
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
        throw InputError("", "--" + name + " must be " + what + ", not '" + text + "'");
    return v;
}

long long parse_whole(const std::string& name, const std::string& text, long long lo, long long hi, const char* what)
{
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
        throw InputError("", "--" + name + " must be " + what + ", not '" + text + "'");
    return v;
}

bool parse_switch(const std::string& name, const std::string& text)
{
    if (text == "true") return true;
    if (text == "false") return false;
    throw InputError("", "--" + name + " is a switch: true or false, not '" + text + "'");
}

// A choice of an enum, stored in its canonical spelling. `list`: a comma-separated list of choices (compare's
// --interpolation gpu,exact).
template <class E, std::size_t N>
AlgoOption choice(const std::string& name, const std::string& applies, const Choices<E, N>& choices,
                  std::string AlgoOptions::*field, std::span<const RenamedChoice> renamed = {},
                  const std::string& more = "", bool list = false)
{
    AlgoOption o;
    o.name = name;
    o.help = applies + ": " + choices_help(choices) + more;
    o.default_text = AlgoOptions{}.*field;
    o.set = [name, &choices, field, renamed, list](AlgoOptions& a, const std::string& text) {
        std::size_t from = 0;
        do {
            const std::size_t comma = list ? text.find(',', from) : std::string::npos;
            parse_choice("--" + name, choices, text.substr(from, comma - from), renamed);
            from = comma == std::string::npos ? comma : comma + 1;
        } while (from != std::string::npos);
        a.*field = text;
    };
    return o;
}

AlgoOption flag(const std::string& name, const std::string& help, bool AlgoOptions::*field)
{
    AlgoOption o;
    o.name = name;
    o.help = help;
    o.flag = true;
    o.set = [name, field](AlgoOptions& a, const std::string& text) { a.*field = parse_switch(name, text); };
    return o;
}

AlgoOption value(const std::string& name, const std::string& help, const std::string& default_text,
                 std::function<void(AlgoOptions&, const std::string&)> set)
{
    AlgoOption o;
    o.name = name;
    o.help = help;
    o.default_text = default_text;
    o.set = std::move(set);
    return o;
}

// Where every algorithm runs: the backend and the GL platform.
void add_backend_rows(std::vector<AlgoOption>& t)
{
    using namespace gpu;
    t.push_back(value("backend",
                      "emu | gl | arb (HAVS only: the paper's own ARB programs under an OSMesa compatibility "
                      "context)",
                      "emu",
                      // Which backends an algorithm has is its registry entry's to say (bench/algorithms.cpp).
                      [](AlgoOptions& a, const std::string& v) { a.backend = v; }));
    t.push_back(choice("gl", "With --backend gl", kGlPlatforms, &AlgoOptions::gl));
    t.push_back(value("gl-device",
                      "With --gl egl: the device, by its index in EGL's device list, or auto (the first hardware "
                      "device that gives a context, else Mesa's software device)",
                      "auto", [](AlgoOptions& a, const std::string& v) {
                          a.gl_device = v == "auto" ? kAnyEglDevice
                                                    : int(parse_whole("gl-device", v, 0, kMaxEglDevices - 1,
                                                                      "auto or a device index from 0"));
                      }));
}

// The mesh renderers' choices (HAVS, VICP): the k-buffer, ties, segments, gaps, cell order, coverage,
// interpolation (the ray caster's too) and k-buffer entries.
void add_mesh_rows(std::vector<AlgoOption>& t)
{
    using namespace gpu;
    AlgoOption k = value("k",
                         "HAVS: k-buffer entries, or all (every fragment of a pixel held until the flush: the "
                         "exact sort; emulation only)",
                         "6", [](AlgoOptions& a, const std::string& v) { a.k = parse_k(v); });
    k.per_run = true;
    t.push_back(k);
    t.push_back(choice("ties", "HAVS with --k all, the order at one distance", kTieOrders, &AlgoOptions::ties));
    t.push_back(
        choice("segment", "HAVS, VICP, the ray caster's pre-integrated mode", kSegmentModes, &AlgoOptions::segment));
    t.push_back(choice("gaps", "HAVS", kGapModes, &AlgoOptions::gaps));
    t.push_back(choice("order", "VICP's cell order", kCellOrders, &AlgoOptions::order));
    t.push_back(choice("coverage", "HAVS, VICP", kCoverages, &AlgoOptions::coverage));
    t.push_back(choice("interpolation", "HAVS, VICP, ray caster", kInterpolationModes, &AlgoOptions::interpolation, {},
                       ". compare takes the list gpu,exact: each algorithm in both modes, side by side", true));
    t.back().default_text = "gpu";
    t.push_back(
        choice("entries", "HAVS's k-buffer entries", kEntryEncodings, &AlgoOptions::entries, kEntryEncodingsRenamed));
}

// What the GL backends send: ARB draw calls and barriers, the triangles sent.
void add_submission_rows(std::vector<AlgoOption>& t)
{
    using namespace gpu;
    t.push_back(value("arb-draw", "With --backend arb: triangles per draw call (0: 131072)", "0",
                      [](AlgoOptions& a, const std::string& v) {
                          a.arb_draw = std::size_t(parse_whole("arb-draw", v, 0, 1LL << 40, "a whole number >= 0"));
                      }));
    t.push_back(
        flag("arb-barrier", "With --backend arb: a texture barrier after every draw call", &AlgoOptions::arb_barrier));
    t.push_back(choice("send", "HAVS with --backend gl or arb, VICP on gl: the triangles sent", kTriangleSubmissions,
                       &AlgoOptions::send));
}

// The compositing: the early-termination opacity and the pre-integration table.
void add_integration_rows(std::vector<AlgoOption>& t)
{
    using namespace gpu;
    t.push_back(value("threshold", "Early-termination opacity (HAVS 0.99, VICP 1, ray caster 0.95; 1 switches it off)",
                      "", [](AlgoOptions& a, const std::string& v) {
                          const double x = parse_number("threshold", v, "a number in [0, 1]");
                          if (x < 0.0 || x > 1.0)
                              throw InputError("", "--threshold must be a number in [0, 1], not '" + v + "'");
                          a.threshold = x;
                      }));
    t.push_back(
        value("table-size", "Pre-integration table texels per axis", "128", [](AlgoOptions& a, const std::string& v) {
            a.table_size = int(parse_whole("table-size", v, 2, 1024, "between 2 and 1024"));
        }));
    t.push_back(
        choice("table-format", "The pre-integration table's texels", kTexelFormats, &AlgoOptions::table_format));
}

// The reference's image cache.
void add_reference_rows(std::vector<AlgoOption>& t)
{
    AlgoOption cache = flag("no-cache", "Do not read or write the reference image cache", &AlgoOptions::no_cache);
    cache.python = "cache";
    cache.python_inverted = true;
    t.push_back(cache);
}

// The ray caster: step, pre-integration, light, volume texture.
void add_raycast_rows(std::vector<AlgoOption>& t)
{
    using namespace gpu;
    AlgoOption step =
        value("step", "Ray caster: step in world units (default: half the smallest spacing)", "",
              [](AlgoOptions& a, const std::string& v) {
                  const double x = parse_number("step", v, "positive and finite (world units)");
                  if (!(x > 0.0))
                      throw InputError("", "--step must be positive and finite (world units), not '" + v + "'");
                  a.step = x;
              });
    step.per_run = true;
    t.push_back(step);
    t.push_back(
        flag("preintegrate", "Ray caster: pre-integrated segments between samples", &AlgoOptions::preintegrate));
    t.push_back(value("light", "Ray caster: X,Y,Z of a point light (world coordinates): Blinn-Phong shading", "",
                      [](AlgoOptions& a, const std::string& v) {
                          std::size_t from = 0;
                          int n = 0;
                          for (; n < 3 && from != std::string::npos; ++n) {
                              const std::size_t comma = v.find(',', from);
                              const std::string item = v.substr(from, comma - from);
                              char* end = nullptr;
                              const double x = std::strtod(item.c_str(), &end);
                              if (item.empty() || *end != '\0' || !std::isfinite(x)) n = 99;
                              from = comma == std::string::npos ? comma : comma + 1;
                          }
                          if (n != 3 || from != std::string::npos)
                              throw InputError("", "--light must be X,Y,Z (three finite numbers), not '" + v + "'");
                          a.light = v;
                      }));
    t.push_back(choice("volume-format", "Ray caster: the volume texture", kVolumeFormats, &AlgoOptions::volume_format));
}

// Sort-last compositing in one process: the parts and how the mesh is split.
void add_sort_last_rows(std::vector<AlgoOption>& t)
{
    t.push_back(value("parts",
                      "HAVS, VICP: render the mesh in N parts, each on its own, and blend their images back to "
                      "front in the order of their boxes (sort-last, as data-parallel renderers do); 1: the whole mesh",
                      "1", [](AlgoOptions& a, const std::string& v) {
                          a.parts = int(parse_whole("parts", v, 1, 4096, "a whole number from 1 to 4096"));
                      }));
    t.push_back(choice("partition", "With --parts", kPartitionMethods, &AlgoOptions::partition));
}

// Every row, in the order help texts list them.
std::vector<AlgoOption> make_table()
{
    std::vector<AlgoOption> t;
    add_backend_rows(t);
    add_mesh_rows(t);
    add_submission_rows(t);
    add_integration_rows(t);
    add_reference_rows(t);
    add_raycast_rows(t);
    add_sort_last_rows(t);
    return t;
}

}  // namespace

const std::vector<AlgoOption>& algo_option_table()
{
    static const std::vector<AlgoOption> table = make_table();
    return table;
}

}  // namespace uvr::cli
