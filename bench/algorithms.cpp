#include "bench/algorithms.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <limits>
#include <sstream>

#include "bench/progress.h"
#include "bench/sort_last.h"
#include "gpu/havs/gl_havs.h"
#include "gpu/havs/gl_havs_arb.h"
#include "gpu/pipeline/llvmpipe_cpu.h"
#include "gpu/raycast/gl_raycast.h"
#include "gpu/vicp/gl_vicp.h"
#include "reference/error.h"
#include "reference/image_cache.h"
#include "reference/reference_renderer.h"
#include "reference/timing.h"

namespace uvr::cli {

namespace {

gpu::Coverage coverage_option(const AlgoOptions& a)
{
    return parse_choice("--coverage", gpu::kCoverages, a.coverage);
}

gpu::InterpolationMode interpolation_option(const AlgoOptions& a)
{
    return a.interpolation.empty() ? gpu::InterpolationMode::gpu
                                   : parse_choice("--interpolation", gpu::kInterpolationModes, a.interpolation);
}

// The emulation models llvmpipe on the CPU's features as Mesa decides them; an environment that takes away more than
// FMA is refused before any work (gpu/pipeline/llvmpipe_cpu.h).
void check_emulated_cpu(const AlgoOptions& a)
{
    if (a.backend == "emu") gpu::require_emulated_cpu_caps();
}

struct TableOptions {
    gpu::SegmentMode segment = gpu::SegmentMode::table;
    float threshold = 1.0f;
    int table_size = 128;
    gpu::TexelFormat table_format = gpu::TexelFormat::f32;
};

// The options every algorithm with a pre-integrated table shares: --segment, --threshold (`default_threshold` when
// unset), --table-size and --table-format.
TableOptions table_options(const AlgoOptions& a, double default_threshold)
{
    TableOptions o;
    o.segment = parse_choice("--segment", gpu::kSegmentModes, a.segment);
    o.threshold = float(a.threshold < 0.0 ? default_threshold : a.threshold);
    o.table_size = a.table_size;
    o.table_format = parse_choice("--table-format", gpu::kTexelFormats, a.table_format);
    return o;
}

// The GL context a run with --backend gl renders in (--gl, --gl-device).
std::unique_ptr<gpu::GlContext> gl_context(const AlgoOptions& a)
{
    return std::make_unique<gpu::GlContext>(gpu::parse_gl_platform(a.gl), gpu::GlProfile::core, a.gl_device);
}

gpu::TriangleSubmission submission(const AlgoOptions& a)
{
    return parse_choice("--send", gpu::kTriangleSubmissions, a.send);
}

}  // namespace

gpu::HavsOptions havs_options(const AlgoOptions& a)
{
    check_emulated_cpu(a);
    const TableOptions t = table_options(a, 0.99);
    gpu::HavsOptions o;
    o.k = a.k;
    o.ties = parse_choice("--ties", gpu::kTieOrders, a.ties);
    o.segment = t.segment;
    o.gaps = parse_choice("--gaps", gpu::kGapModes, a.gaps);
    o.threshold = t.threshold;
    o.table_size = t.table_size;
    o.table_format = t.table_format;
    o.coverage = coverage_option(a);
    o.interpolation = interpolation_option(a);
    o.entries = a.entries.empty()
                    ? (a.backend == "arb" ? gpu::EntryEncoding::paper : gpu::EntryEncoding::marked)
                    : parse_choice("--entries", gpu::kEntryEncodings, a.entries, gpu::kEntryEncodingsRenamed);
    if (a.backend == "arb") gpu::check_arb_options(o);
    submission(a);
    return o;
}

gpu::VicpOptions vicp_options(const AlgoOptions& a)
{
    check_emulated_cpu(a);
    const TableOptions t = table_options(a, 1.0);
    gpu::VicpOptions o;
    o.interpolation = interpolation_option(a);
    o.order = gpu::parse_cell_order(a.order);
    o.segment = t.segment;
    o.threshold = t.threshold;
    o.table_size = t.table_size;
    o.table_format = t.table_format;
    o.coverage = coverage_option(a);
    submission(a);
    return o;
}

gpu::RaycastOptions raycast_options(const AlgoOptions& a)
{
    check_emulated_cpu(a);
    const TableOptions t = table_options(a, 0.95);
    gpu::RaycastOptions o;
    o.interpolation = interpolation_option(a);
    if (coverage_option(a) == gpu::Coverage::exact)
        throw InputError("", "--coverage exact applies to HAVS and VICP: the ray caster's pass covers every pixel");
    o.step = a.step > 0.0 ? a.step : 0.0;  // 0: RaycastVolume's default
    o.preintegrate = a.preintegrate;
    if (t.segment == gpu::SegmentMode::exact && !a.preintegrate)
        throw InputError("", "--segment exact needs --preintegrate with --algo raycast (it integrates the segment "
                             "between two samples)");
    o.segment = t.segment;
    o.threshold = t.threshold;
    o.table_size = t.table_size;
    o.table_format = t.table_format;
    o.volume_format = gpu::parse_volume_format(a.volume_format);
    if (!a.light.empty()) {  // three finite numbers: the table's parser checked them
        const std::vector<std::string> xyz = split_list(a.light);
        gpu::RaycastLight light;
        for (int i = 0; i < 3; ++i) light.position[i] = std::strtod(xyz[std::size_t(i)].c_str(), nullptr);
        o.light = light;
    }
    return o;
}

namespace {

void check_backend(const Algorithm& algo, const AlgoOptions& a)
{
    for (const std::string& b : algo.backends)
        if (a.backend == b) return;
    std::string list;
    for (const std::string& b : algo.backends) list += (list.empty() ? "" : ", ") + b;
    throw InputError("", "--backend must be one of " + list + " with --algo " + algo.name + ", not '" + a.backend +
                             "'");
}

// --- the reference (reference/reference_renderer.h): the ground truth on the CPU, for meshes and regular grids ---

class ReferenceRenderer : public Renderer {
public:
    // With the cache, the integrator is built only when a frame misses it (building it is most of a small frame).
    ReferenceRenderer(const Scene& s, bool use_cache) : s_(s), use_cache_(use_cache)
    {
        if (!use_cache_) build();
    }

    AlgoResult render(const Camera& camera, int width, int height) override
    {
        AlgoResult r;
        // The key hashes the whole mesh or grid: only where the cache is used.
        const std::string key = !use_cache_ ? std::string()
                                : s_.is_volume()
                                    ? reference_cache_key(s_.volume(), s_.tf, camera, width, height)
                                    : reference_cache_key(s_.mesh(), s_.field, s_.tf, camera, width, height);
        if (use_cache_) {
            if (auto img = cache_load(key, width, height)) {
                r.image = std::move(*img);
                r.cached = true;
                r.stats = {{"cached", true}};
                return r;
            }
        }
        build();
        ProgressBar bar("reference");
        ReferenceStats st;
        const auto progress = [&](double f) { bar.update(f); };
        r.image = mesh_ ? render_reference(*mesh_, camera, width, height, st, progress)
                        : render_reference(*volume_, camera, width, height, st, progress);
        bar.finish();
        if (mesh_ && st.failures)
            throw InputError(s_.mesh().source, std::to_string(st.failures) +
                                                   " rays were abandoned by the walk's guards; the image would be wrong");
        if (use_cache_) cache_store(key, r.image);
        r.ms = st.seconds * 1000.0;
        r.stats = {{"cached", false}, {"rays", st.rays}, {mesh_ ? "segments" : "cell_pieces", st.segments},
                   {"entries", st.entries}, {"stages_ms", {{"integrate", r.ms}}}};
        return r;
    }

private:
    const Scene& s_;
    bool use_cache_;
    std::unique_ptr<RayIntegrator> mesh_;
    std::unique_ptr<VolumeIntegrator> volume_;

    void build()
    {
        if (mesh_ || volume_) return;
        if (s_.is_volume())
            volume_ = std::make_unique<VolumeIntegrator>(s_.volume(), s_.tf);
        else
            mesh_ = std::make_unique<RayIntegrator>(s_.mesh(), *s_.topology, s_.field, s_.tf);
    }
};

// --- HAVS (gpu/havs/): emulated, or on GL ---

// A part of a larger mesh normalizes its scalars and spans its table as the whole does (SceneExtent).
template <class Options>
void span_whole(const Scene& s, Options& o)
{
    if (!s.whole) return;
    o.scalar_range = s.whole->range;
    if (s.whole->longest_edge > 0.0) o.table_max_length = s.whole->longest_edge;
}

class HavsRendererEntry : public Renderer {
public:
    HavsRendererEntry(const Scene& s, const AlgoOptions& a) : a_(a)
    {
        gpu::HavsOptions o = havs_options(a);
        span_whole(s, o);
        if (a.backend == "emu") {
            // Without diagnostics as the GL driver is timed (bench): the same image, no per-pixel counts.
            emu_ = std::make_unique<gpu::HavsRenderer>(s.mesh(), *s.topology, s.field, s.tf, o, a.diagnostics);
            diagnostics_ = a.diagnostics;
            return;
        }
        if (a.backend == "arb") {
            if (a.gl != "osmesa")
                throw InputError("", "--backend arb runs under OSMesa's compatibility profile only (--gl osmesa)");
            if (a.require_diagnostics)
                throw InputError("", "--diagnostics: the paper's ARB program writes no per-pixel diagnostics");
            ctx_ = std::make_unique<gpu::GlContext>(gpu::GlPlatform::osmesa, gpu::GlProfile::compatibility);
            arb_ = std::make_unique<gpu::ArbHavsRenderer>(*ctx_, s.mesh(), *s.topology, s.field, s.tf, o);
            arb_->set_triangles_per_draw(a.arb_draw);
            arb_->set_barrier_after_each_draw(a.arb_barrier);
            arb_->set_submission(submission(a));
            diagnostics_ = false;
            return;
        }
        ctx_ = gl_context(a);
        const int kmax_diag = gpu::GlHavsRenderer::max_k(ctx_->info(), true);
        if (a.require_diagnostics && a.k > kmax_diag)
            throw InputError("", "--diagnostics with --backend gl needs a free draw buffer: k at most " +
                                     std::to_string(kmax_diag) + " on " + ctx_->info().renderer);
        diagnostics_ = a.diagnostics && a.k <= kmax_diag;
        gl_ = std::make_unique<gpu::GlHavsRenderer>(*ctx_, s.mesh(), *s.topology, s.field, s.tf, o, diagnostics_);
        gl_->set_submission(submission(a));
    }

    AlgoResult render(const Camera& camera, int width, int height) override
    {
        gpu::HavsFrame f = emu_ ? emu_->render(camera, width, height)
                           : arb_ ? arb_->render(camera, width, height)
                                  : gl_->render(camera, width, height);
        AlgoResult r;
        const auto& st = f.stats;
        const gpu::HavsMesh& hm = emu_ ? emu_->cpu_stage() : arb_ ? arb_->cpu_stage() : gl_->cpu_stage();
        r.stats = {{"k", k_json(a_.k)},
                   {"ties", a_.ties},
                   {"entries", std::string(choice_name(gpu::kEntryEncodings, hm.options().entries))},
                   {"segment", a_.segment},
                   {"gaps", a_.gaps},
                   {"coverage", a_.coverage},
                   {"interpolation", a_.interpolation.empty() ? "gpu" : a_.interpolation},
                   {"faces", st.faces},
                   {"table_ms", st.table_ms},
                   {"clip",
                    {{"triangles", st.triangles},
                     {"clipped_faces", st.clipped_faces},
                     {"culled_faces", st.culled_faces},
                     {"near_sections", st.near_sections},
                     {"gpu_clipped", st.gpu_clipped},
                     {"uncovered", st.uncovered}}},
                   {"stages_ms",
                    {{"sort", st.sort_ms},
                     {"vertex_and_setup", st.setup_ms},
                     {"raster_and_fragment", st.raster_fragment_ms},
                     {"flush", st.flush_ms},
                     {"readback", st.readback_ms}}}};
        if (!f.fragments.empty()) {
            r.stats["fragments"] = st.fragments;
            r.stats["max_fragments_per_pixel"] = st.max_fragments;
            r.stats["max_held"] = st.max_held;
            r.stats["ordering_errors"] = st.ordering_errors;
        }
        if (ctx_) {
            r.stats["gl"] = ctx_->info().summary();
            r.stats["send"] = a_.send;
        }
        r.stats["diagnostics"] = diagnostics_;
        r.image = std::move(f.image);
        r.fragments = std::move(f.fragments);
        r.max_held = std::move(f.max_held);
        r.ordering_errors = std::move(f.ordering_errors);
        return r;
    }

private:
    AlgoOptions a_;
    bool diagnostics_ = true;
    std::unique_ptr<gpu::HavsRenderer> emu_;
    std::unique_ptr<gpu::GlContext> ctx_;
    std::unique_ptr<gpu::GlHavsRenderer> gl_;
    std::unique_ptr<gpu::ArbHavsRenderer> arb_;
};

// --- VICP (gpu/vicp/): emulated, or on GL ---

class VicpRendererEntry : public Renderer {
public:
    VicpRendererEntry(const Scene& s, const AlgoOptions& a) : a_(a)
    {
        gpu::VicpOptions o = vicp_options(a);
        span_whole(s, o);
        if (a.backend == "emu") {
            // Without diagnostics as the GL driver is timed (bench): the same image, no exact segment beside it.
            emu_ = std::make_unique<gpu::VicpRenderer>(s.mesh(), *s.topology, s.field, s.tf, o, a.diagnostics);
            return;
        }
        ctx_ = gl_context(a);
        gl_ = std::make_unique<gpu::GlVicpRenderer>(*ctx_, s.mesh(), *s.topology, s.field, s.tf, o);
        gl_->set_submission(submission(a));
    }

    AlgoResult render(const Camera& camera, int width, int height) override
    {
        gpu::VicpFrame f = emu_ ? emu_->render(camera, width, height) : gl_->render(camera, width, height);
        const gpu::VicpMesh& vm = emu_ ? emu_->cpu_stage() : gl_->cpu_stage();
        AlgoResult r;
        const auto& st = f.stats;
        r.stats = {{"order", a_.order},
                   {"segment", a_.segment},
                   {"coverage", a_.coverage},
                   {"interpolation", vm.options().interpolation == gpu::InterpolationMode::gpu ? "gpu" : "exact"},
                   {"cells", st.cells},
                   {"drawn_cells", st.drawn_cells},
                   {"fragments", st.fragments},
                   {"max_fragments_per_pixel", st.max_fragments},
                   {"ordering_errors", st.ordering_errors},
                   {"cycle_breaks", st.order.cycle_breaks},
                   {"face_dependencies", st.order.face_dependencies},
                   {"ray_dependencies", st.order.ray_dependencies},
                   {"bytes_sent_per_tet", gpu::vicp_sent_bytes_per_cell(vm, st.sent_faces)},
                   {"published_bytes_sent_per_tet", gpu::kPublishedBytesSentPerCell},
                   {"resident_bytes_per_tet", gpu::vicp_resident_bytes_per_cell(vm)},
                   {"table_ms", st.table_ms},
                   {"clip",
                    {{"clipped_cells", st.clipped_cells},
                     {"culled_cells", st.culled_cells},
                     {"near_sections", st.near_sections},
                     {"fan_triangles", st.fan_triangles},
                     {"gpu_clipped", st.gpu_clipped}}},
                   {"stages_ms",
                    {{"sort", st.sort_ms},
                     {"project", st.project_ms},
                     {"vertex_and_setup", st.setup_ms},
                     {"raster_and_fragment", st.raster_fragment_ms},
                     {"readback", st.readback_ms}}}};
        r.stats["diagnostics"] = !emu_ || a_.diagnostics;  // the GL driver always reads its counts back
        if (vm.options().interpolation == gpu::InterpolationMode::gpu) {
            // The wrong-exit and length diagnostics compare with the exact segment, which only the emulation computes
            // (the GL frame is the emulation's, bit for bit: tests/test_vicp_gl_frame.cpp); null on GL.
            const bool exits = emu_ && a_.diagnostics;
            r.stats["wrong_exits"] = exits ? nlohmann::json(st.wrong_exits) : nlohmann::json();
            r.stats["max_length_error"] = exits ? nlohmann::json(st.max_length_error) : nlohmann::json();
            r.stats["exact_cut_cells"] = st.clipped_cells;  // drawn by the exact variant (docs/vicp.md)
            r.stats["sent_faces"] = st.sent_faces;
            if (gl_) r.stats["send"] = a_.send;
        }
        if (ctx_) r.stats["gl"] = ctx_->info().summary();
        r.image = std::move(f.image);
        r.fragments = std::move(f.fragments);
        r.ordering_errors = std::move(f.ordering_errors);
        r.wrong_exits = std::move(f.wrong_exits);
        return r;
    }

private:
    AlgoOptions a_;
    std::unique_ptr<gpu::VicpRenderer> emu_;
    std::unique_ptr<gpu::GlContext> ctx_;
    std::unique_ptr<gpu::GlVicpRenderer> gl_;
};

// --- the regular-grid ray caster (gpu/raycast/): emulated, or on GL ---

class RaycastRendererEntry : public Renderer {
public:
    RaycastRendererEntry(const Scene& s, const AlgoOptions& a)
    {
        const gpu::RaycastOptions o = raycast_options(a);
        if (a.backend == "emu") {
            emu_ = std::make_unique<gpu::RaycastRenderer>(s.volume(), s.tf, o);
            return;
        }
        ctx_ = gl_context(a);
        gl_ = std::make_unique<gpu::GlRaycastRenderer>(*ctx_, s.volume(), s.tf, o);
    }

    AlgoResult render(const Camera& camera, int width, int height) override
    {
        gpu::RaycastFrame f = emu_ ? emu_->render(camera, width, height) : gl_->render(camera, width, height);
        const gpu::RaycastVolume& rv = emu_ ? emu_->cpu_stage() : gl_->cpu_stage();
        AlgoResult r;
        const auto& st = f.stats;
        const gpu::RaycastOptions& o = rv.options();
        r.stats = {{"step", o.step},
                   {"preintegrate", o.preintegrate},
                   {"classification", o.preintegrate ? "pre-integrated" : "post"},
                   {"threshold", o.threshold},
                   {"shading", o.light.has_value()},
                   {"volume_format", gpu::texel_format_name(rv.texel_format())},
                   {"texture_bytes", rv.texture_bytes()},
                   {"rays", st.rays},
                   {"samples", st.samples},
                   {"max_samples_per_pixel", st.max_samples},
                   {"interpolation", o.interpolation == gpu::InterpolationMode::gpu ? "gpu" : "exact"},
                   {"table_ms", st.table_ms},
                   {"stages_ms", {{"setup", st.setup_ms}, {"march", st.march_ms}, {"readback", st.readback_ms}}}};
        if (o.interpolation == gpu::InterpolationMode::gpu) {
            // The published box passes: what was drawn, and (emulation only) entries, entries without an exit,
            // overlaps.
            r.stats["box"] = {{"triangles", st.box_triangles}, {"near_sections", st.near_sections},
                              {"clipped_faces", st.clipped_faces}, {"gpu_clipped", st.gpu_clipped}};
            if (emu_) {
                r.stats["box"]["entries"] = st.entries;
                r.stats["box"]["unpaired"] = st.unpaired;
                r.stats["box"]["overlaps"] = st.overlaps;
            }
        }
        if (ctx_) r.stats["gl"] = ctx_->info().summary();
        r.image = std::move(f.image);
        r.samples = std::move(f.samples);
        return r;
    }

private:
    std::unique_ptr<gpu::RaycastRenderer> emu_;
    std::unique_ptr<gpu::GlContext> ctx_;
    std::unique_ptr<gpu::GlRaycastRenderer> gl_;
};

double per_s(double count, double ms) { return count / (ms / 1000.0); }
double stage(const nlohmann::json& row, const char* name) { return row["stages"][name].get<double>(); }

// bench's variants of an algorithm timed as configured: the options alone.
std::vector<AlgoOptions> single_variant(const AlgoOptions& a, const std::vector<std::string>&)
{
    return std::vector{a};
}

// The reference's entry: the ground truth on the CPU, for meshes and regular grids.
Algorithm reference_entry()
{
    return {"reference", Inputs::both, {"cpu"}, [](const AlgoOptions&) {},
            [](const AlgoOptions&) { return std::string("reference"); },
            [](const Scene& s, const AlgoOptions& a) -> std::unique_ptr<Renderer> {
                return std::make_unique<ReferenceRenderer>(s, !a.no_cache);
            },
            single_variant,
            [](nlohmann::json& row, const Scene&) {
                const double fm = row["frame_ms"].get<double>();
                row["stages"]["setup"] = row["build_ms"];
                row["rays_per_s"] = per_s(row["rays"].get<double>(), fm);
                // A mesh's segments, a grid's cell pieces.
                row["segments_per_s"] = per_s(row.value("segments", row.value("cell_pieces", 0.0)), fm);
            },
            [](const nlohmann::json& r) {
                std::printf(" %6.2f Mrays/s  %6.2f Msegments/s  (setup %.1f ms)\n", r["rays_per_s"].get<double>() / 1e6,
                            r["segments_per_s"].get<double>() / 1e6, stage(r, "setup"));
            }};
}

// HAVS's entry: meshes, emulated or on GL (GLSL or ARB programs).
Algorithm havs_entry()
{
    return {"havs",
            Inputs::mesh,
            {"emu", "gl", "arb"},
            [](const AlgoOptions& a) { havs_options(a); },
            [](const AlgoOptions& a) {
                // The published interpolation is the default; the exact variant says so in its label, and so do
                // entries other than the backend's default (the published on arb, uvr's marked ones elsewhere).
                const bool arb = a.backend == "arb";
                const std::string entries = a.entries.empty() || a.entries == (arb ? "paper" : "marked")
                                                ? ""
                                                : "-" + a.entries + "-entries";
                return "havs-" + a.backend + "-k" + (a.k == gpu::kEveryFragment ? "all" : std::to_string(a.k)) +
                       (a.ties == "facing" ? "-facing-ties" : "") +
                       (a.interpolation == "exact" ? "-exact-interpolation" : "") + entries;
            },
            [](const Scene& s, const AlgoOptions& a) -> std::unique_ptr<Renderer> {
                return std::make_unique<HavsRendererEntry>(s, a);
            },
            single_variant,
            [](nlohmann::json& row, const Scene& s) {
                row["tetrahedra_per_s"] = per_s(double(s.mesh().tets.size()), row["frame_ms"].get<double>());
                if (row.value("fragments", uint64_t(0)))
                    row["fragments_per_s"] = per_s(row["fragments"].get<double>(), stage(row, "raster_and_fragment"));
            },
            [](const nlohmann::json& r) {
                // Fragments are counted only with diagnostics, which a timed frame leaves off: no rate then.
                std::printf(" k=%d  ", r["k"].get<int>());
                if (r.contains("fragments_per_s"))
                    std::printf("%6.2f Mfragments/s  ", r["fragments_per_s"].get<double>() / 1e6);
                std::printf("sort %.1f, vertex+setup %.1f, raster+fragment %.1f, flush %.1f, readback %.1f ms "
                            "(built in %.0f ms)\n",
                            stage(r, "sort"), stage(r, "vertex_and_setup"), stage(r, "raster_and_fragment"),
                            stage(r, "flush"), stage(r, "readback"), r["build_ms"].get<double>());
            }};
}

// VICP's entry: meshes, emulated or on GL; bench times each visibility order.
Algorithm vicp_entry()
{
    return {"vicp",
            Inputs::mesh,
            {"emu", "gl"},
            [](const AlgoOptions& a) { vicp_options(a); },
            [](const AlgoOptions& a) {
                return "vicp-" + a.backend + "-" + a.order + (a.interpolation == "exact" ? "-exact-interpolation" : "");
            },
            [](const Scene& s, const AlgoOptions& a) -> std::unique_ptr<Renderer> {
                return std::make_unique<VicpRendererEntry>(s, a);
            },
            [](const AlgoOptions& a, const std::vector<std::string>& orders) {
                std::vector<AlgoOptions> v;
                for (const auto& o : orders) {
                    v.push_back(a);
                    v.back().order = o;
                }
                return v;
            },
            [](nlohmann::json& row, const Scene& s) {
                row["tetrahedra_per_s"] = per_s(double(s.mesh().tets.size()), row["frame_ms"].get<double>());
                if (row["diagnostics"].get<bool>())
                    row["fragments_per_s"] = per_s(row["fragments"].get<double>(), stage(row, "raster_and_fragment"));
            },
            [](const nlohmann::json& r) {
                // The emulation counts fragments and ordering errors only with diagnostics, which a timed frame
                // leaves off; the GL driver reads its counts back with every frame.
                std::printf(" %-8s ", r["order"].get<std::string>().c_str());
                if (r.contains("fragments_per_s"))
                    std::printf("%6.2f Mfragments/s  ", r["fragments_per_s"].get<double>() / 1e6);
                std::printf(
                    "sort %.1f, project %.1f, vertex+setup %.1f, raster+fragment %.1f ms; %.0f bytes sent per "
                    "tetrahedron (the published: %.0f); ",
                    stage(r, "sort"), stage(r, "project"), stage(r, "vertex_and_setup"),
                    stage(r, "raster_and_fragment"), r["bytes_sent_per_tet"].get<double>(),
                    r["published_bytes_sent_per_tet"].get<double>());
                if (r["diagnostics"].get<bool>())
                    std::printf("%llu ordering errors, ", (unsigned long long)r["ordering_errors"].get<uint64_t>());
                std::printf("%llu cycle breaks\n", (unsigned long long)r["cycle_breaks"].get<uint64_t>());
            }};
}

// The ray caster's entry: regular grids, emulated or on GL; bench times post-classified and pre-integrated.
Algorithm raycast_entry()
{
    return {"raycast",
            Inputs::grid,
            {"emu", "gl"},
            [](const AlgoOptions& a) {
                if (a.parts > 1)
                    throw InputError("",
                                     "--parts is for HAVS and VICP (a mesh in parts); the ray caster renders a "
                                     "regular grid whole");
                raycast_options(a);
            },
            [](const AlgoOptions& a) {
                return "raycast-" + a.backend + (a.preintegrate ? "-preint" : "-post") +
                       (a.interpolation == "exact" ? "-exact-interpolation" : "");
            },
            [](const Scene& s, const AlgoOptions& a) -> std::unique_ptr<Renderer> {
                return std::make_unique<RaycastRendererEntry>(s, a);
            },
            [](const AlgoOptions& a, const std::vector<std::string>&) {
                std::vector<AlgoOptions> v(2, a);
                v[0].preintegrate = false;
                v[1].preintegrate = true;
                return v;
            },
            [](nlohmann::json& row, const Scene&) {
                row["samples_per_s"] = per_s(row["samples"].get<double>(), stage(row, "march"));
            },
            [](const nlohmann::json& r) {
                std::printf(" %-14s %6.2f Msamples/s  setup %.1f, march %.1f, readback %.1f ms; step %g, %s "
                            "texture\n",
                            r["classification"].get<std::string>().c_str(), r["samples_per_s"].get<double>() / 1e6,
                            stage(r, "setup"), stage(r, "march"), stage(r, "readback"), r["step"].get<double>(),
                            r["volume_format"].get<std::string>().c_str());
            }};
}

std::vector<Algorithm> make_registry()
{
    return {reference_entry(), havs_entry(), vicp_entry(), raycast_entry()};
}

}  // namespace

const std::vector<Algorithm>& algorithms()
{
    static const std::vector<Algorithm> registry = make_registry();
    return registry;
}

const Algorithm& find_algorithm(const std::string& name)
{
    std::string known;
    for (const Algorithm& a : algorithms()) {
        if (a.name == name) return a;
        known += (known.empty() ? "" : ", ") + a.name;
    }
    throw InputError("", "unknown algorithm '" + name + "' (" + known + ")");
}

std::string backend_of(const Algorithm& algo, const AlgoOptions& o)
{
    return algo.backends.size() == 1 ? algo.backends[0] : o.backend;
}

void run_algorithm_check(const std::string& algo) { find_algorithm(algo); }

void check_algorithm_scene(const Scene& s, const std::string& name)
{
    const Algorithm& algo = find_algorithm(name);
    if (algo.inputs == Inputs::mesh) s.mesh();  // throws for a regular grid
    if (algo.inputs == Inputs::grid && !s.is_volume())
        throw InputError(s.mesh().source, "is a tetrahedral mesh: --algo " + name +
                                              " renders regular grids (.vti, .nrrd, structured points, raw)");
}

AlgoResult run_algorithm(const Scene& s, const std::string& name, const AlgoOptions& o)
{
    const Algorithm& algo = find_algorithm(name);
    if (algo.backends.size() > 1) check_backend(algo, o);
    algo.check_options(o);
    check_algorithm_scene(s, name);
    // The reference is what sort-last is measured against: it renders the whole mesh whatever --parts says.
    if (o.parts > 1 && (name == "havs" || name == "vicp")) return render_sort_last(s, name, o);
    const auto t0 = Clock::now();
    const std::unique_ptr<Renderer> renderer = algo.make(s, o);
    AlgoResult r = renderer->render(s.camera, s.width, s.height);
    if (!r.cached && r.ms == 0.0) r.ms = ms_since(t0);  // the reference reports its integration alone
    return r;
}

std::vector<std::string> split_list(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string x; std::getline(ss, x, ',');)
        if (!x.empty()) out.push_back(x);
    return out;
}

}  // namespace uvr::cli
