#include "bench/algorithms.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "bench/progress.h"
#include "gpu/gl_havs.h"
#include "gpu/gl_raycast.h"
#include "gpu/gl_vicp.h"
#include "reference/error.h"
#include "reference/image_cache.h"
#include "reference/reference_renderer.h"

namespace uvr::cli {

void add_algo_options(CLI::App& cmd, AlgoOptions& o, bool with_k)
{
    cmd.add_option("--backend", o.backend, "emu | gl")->capture_default_str();
    cmd.add_option("--gl", o.gl, "With --backend gl: osmesa | egl")->capture_default_str();
    if (with_k) cmd.add_option("--k", o.k, "HAVS: k-buffer entries")->capture_default_str();
    cmd.add_option("--segment", o.segment, "HAVS: table | exact (emulation only)")->capture_default_str();
    cmd.add_option("--gaps", o.gaps, "HAVS: exact | maxgap (VTK's heuristic)")->capture_default_str();
    cmd.add_option("--order", o.order, "VICP: cell order, mpvonc | centroid")->capture_default_str();
    cmd.add_option("--threshold", o.threshold, "Early-termination opacity (HAVS 0.99, VICP 1; 1 switches it off)");
    cmd.add_option("--table-size", o.table_size, "HAVS: pre-integration table texels per axis")->capture_default_str();
    cmd.add_option("--table-format", o.table_format, "HAVS: f32 | u16 | u8")->capture_default_str();
    cmd.add_flag("--no-cache", o.no_cache, "Do not read or write the reference image cache");
    if (with_k)  // sweep takes a list of steps
        cmd.add_option("--step", o.step, "Ray caster: step in world units (default: half the smallest spacing)");
    cmd.add_flag("--preintegrate", o.preintegrate, "Ray caster: pre-integrated segments between samples");
    cmd.add_option("--light", o.light, "Ray caster: X,Y,Z of a point light (world coordinates): Blinn-Phong shading");
    cmd.add_option("--volume-format", o.volume_format, "Ray caster: volume texture, native | f32 | u16 | u8")
        ->capture_default_str();
}

gpu::HavsOptions havs_options(const AlgoOptions& a)
{
    gpu::HavsOptions o;
    o.k = a.k;
    if (a.segment != "table" && a.segment != "exact") throw InputError("", "--segment must be table or exact");
    o.segment = a.segment == "exact" ? gpu::SegmentMode::exact : gpu::SegmentMode::table;
    if (a.gaps != "exact" && a.gaps != "maxgap") throw InputError("", "--gaps must be exact or maxgap");
    o.gaps = a.gaps == "maxgap" ? gpu::GapMode::maxgap : gpu::GapMode::exact;
    if (a.threshold >= 0.0 && a.threshold > 1.0) throw InputError("", "--threshold must be in [0, 1]");
    o.threshold = a.threshold < 0.0 ? 0.99f : float(a.threshold);
    if (a.table_size < 2 || a.table_size > 1024) throw InputError("", "--table-size must be between 2 and 1024");
    o.table_size = a.table_size;
    if (a.table_format == "f32")
        o.table_format = gpu::TexelFormat::f32;
    else if (a.table_format == "u16")
        o.table_format = gpu::TexelFormat::u16;
    else if (a.table_format == "u8")
        o.table_format = gpu::TexelFormat::u8;
    else
        throw InputError("", "--table-format must be f32, u16 or u8");
    return o;
}

gpu::VicpOptions vicp_options(const AlgoOptions& a)
{
    // The table and segment options mean what they mean for HAVS; only the order and the threshold's default differ.
    AlgoOptions h = a;
    if (h.threshold < 0.0) h.threshold = 1.0;
    const gpu::HavsOptions ho = havs_options(h);
    gpu::VicpOptions o;
    o.order = gpu::parse_cell_order(a.order);
    o.segment = ho.segment;
    o.threshold = ho.threshold;
    o.table_size = ho.table_size;
    o.table_format = ho.table_format;
    return o;
}

gpu::RaycastOptions raycast_options(const AlgoOptions& a)
{
    // The table options mean what they mean for HAVS (the pre-integrated table); the threshold's default is 0.95.
    AlgoOptions h = a;
    if (h.threshold < 0.0) h.threshold = 0.95;
    const gpu::HavsOptions ho = havs_options(h);
    gpu::RaycastOptions o;
    if (a.step != -1.0 && !(a.step > 0.0 && std::isfinite(a.step)))
        throw InputError("", "--step must be positive and finite (world units)");
    o.step = a.step > 0.0 ? a.step : 0.0;  // 0: RaycastVolume's default
    o.preintegrate = a.preintegrate;
    if (ho.segment == gpu::SegmentMode::exact && !a.preintegrate)
        throw InputError("", "--segment exact needs --preintegrate with --algo raycast (it integrates the segment "
                             "between two samples)");
    o.segment = ho.segment;
    o.threshold = ho.threshold;
    o.table_size = ho.table_size;
    o.table_format = ho.table_format;
    o.volume_format = gpu::parse_volume_format(a.volume_format);
    if (!a.light.empty()) {
        const std::vector<std::string> xyz = split_list(a.light);
        gpu::RaycastLight light;
        bool ok = xyz.size() == 3;
        for (int i = 0; ok && i < 3; ++i) {
            char* end = nullptr;
            light.position[i] = std::strtod(xyz[std::size_t(i)].c_str(), &end);
            ok = end && *end == '\0' && std::isfinite(light.position[i]);
        }
        if (!ok) throw InputError("", "--light must be X,Y,Z (three finite numbers), not '" + a.light + "'");
        o.light = light;
    }
    return o;
}

namespace {

using Clock = std::chrono::steady_clock;

// The regular-grid reference (reference/volume_integrator.h). Not cached: the cache's key is a mesh's.
AlgoResult run_volume_reference(const Scene& s)
{
    AlgoResult r;
    const VolumeIntegrator integrator(s.volume(), s.tf);
    ProgressBar bar("reference");
    ReferenceStats st;
    r.image = render_reference(integrator, s.camera, s.width, s.height, st, [&](double f) { bar.update(f); });
    bar.finish();
    r.ms = st.seconds * 1000.0;
    r.stats = {{"cached", false}, {"rays", st.rays}, {"cell_pieces", st.segments}, {"entries", st.entries}};
    return r;
}

AlgoResult run_reference(const Scene& s, bool use_cache)
{
    if (s.is_volume()) return run_volume_reference(s);
    AlgoResult r;
    const std::string key = reference_cache_key(s.mesh(), s.field, s.tf, s.camera, s.width, s.height);
    if (use_cache) {
        if (auto img = cache_load(key, s.width, s.height)) {
            r.image = std::move(*img);
            r.cached = true;
            r.stats = {{"cached", true}};
            return r;
        }
    }
    const RayIntegrator integrator(s.mesh(), *s.topology, s.field, s.tf);
    ProgressBar bar("reference");
    ReferenceStats st;
    r.image = render_reference(integrator, s.camera, s.width, s.height, st, [&](double f) { bar.update(f); });
    bar.finish();
    if (st.failures)
        throw InputError(s.mesh().source, std::to_string(st.failures) +
                                              " rays were abandoned by the walk's guards; the image would be wrong");
    if (use_cache) cache_store(key, r.image);
    r.ms = st.seconds * 1000.0;
    r.stats = {{"cached", false}, {"rays", st.rays}, {"segments", st.segments}, {"entries", st.entries}};
    return r;
}

AlgoResult havs_result(gpu::HavsFrame f, const AlgoOptions& a, double ms)
{
    AlgoResult r;
    r.ms = ms;
    const auto& st = f.stats;
    r.stats = {{"k", a.k}, {"segment", a.segment}, {"gaps", a.gaps}, {"faces", st.faces},
               {"clip", {{"triangles", st.triangles}, {"clipped_faces", st.clipped_faces},
                         {"culled_faces", st.culled_faces}, {"near_sections", st.near_sections},
                         {"gpu_clipped", st.gpu_clipped}}},
               {"stages_ms", {{"table", st.table_ms}, {"sort", st.sort_ms}, {"setup", st.setup_ms},
                              {"raster_fragment", st.raster_fragment_ms}, {"flush", st.flush_ms}}}};
    if (!f.fragments.empty()) {
        r.stats["fragments"] = st.fragments;
        r.stats["max_fragments_per_pixel"] = st.max_fragments;
        r.stats["max_held"] = st.max_held;
        r.stats["ordering_errors"] = st.ordering_errors;
    }
    r.image = std::move(f.image);
    r.fragments = std::move(f.fragments);
    r.max_held = std::move(f.max_held);
    r.ordering_errors = std::move(f.ordering_errors);
    return r;
}

AlgoResult run_havs(const Scene& s, const AlgoOptions& a)
{
    if (a.backend != "emu" && a.backend != "gl") throw InputError("", "--backend must be emu or gl, not '" + a.backend + "'");
    const auto t0 = Clock::now();
    if (a.backend == "emu") {
        const gpu::HavsRenderer havs(s.mesh(), *s.topology, s.field, s.tf, havs_options(a));
        gpu::HavsFrame f = havs.render(s.camera, s.width, s.height);
        return havs_result(std::move(f), a, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    gpu::GlContext ctx(gpu::parse_gl_platform(a.gl));
    const int kmax_diag = gpu::GlHavsRenderer::max_k(ctx.info(), true);
    if (a.require_diagnostics && a.k > kmax_diag)
        throw InputError("", "--diagnostics with --backend gl needs a free draw buffer: k at most " +
                                 std::to_string(kmax_diag) + " on " + ctx.info().renderer);
    gpu::GlHavsRenderer havs(ctx, s.mesh(), *s.topology, s.field, s.tf, havs_options(a), a.k <= kmax_diag);
    gpu::HavsFrame f = havs.render(s.camera, s.width, s.height);
    AlgoResult r = havs_result(std::move(f), a, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    r.stats["gl"] = ctx.info().summary();
    return r;
}

AlgoResult vicp_result(gpu::VicpFrame f, const gpu::VicpMesh& vm, const AlgoOptions& a, double ms)
{
    AlgoResult r;
    r.ms = ms;
    const auto& st = f.stats;
    r.stats = {{"order", a.order},
               {"segment", a.segment},
               {"cells", st.cells},
               {"drawn_cells", st.drawn_cells},
               {"fragments", st.fragments},
               {"max_fragments_per_pixel", st.max_fragments},
               {"ordering_errors", st.ordering_errors},
               {"cycle_breaks", st.order.cycle_breaks},
               {"face_dependencies", st.order.face_dependencies},
               {"ray_dependencies", st.order.ray_dependencies},
               {"bytes_sent_per_tet", gpu::vicp_sent_bytes_per_cell(vm)},
               {"clip", {{"clipped_cells", st.clipped_cells}, {"culled_cells", st.culled_cells},
                         {"near_sections", st.near_sections}, {"fan_triangles", st.fan_triangles},
                         {"gpu_clipped", st.gpu_clipped}}},
               {"stages_ms", {{"table", st.table_ms}, {"sort", st.sort_ms}, {"project", st.project_ms},
                              {"setup", st.setup_ms}, {"raster_fragment", st.raster_fragment_ms}}}};
    r.image = std::move(f.image);
    r.fragments = std::move(f.fragments);
    r.ordering_errors = std::move(f.ordering_errors);
    return r;
}

AlgoResult run_vicp(const Scene& s, const AlgoOptions& a)
{
    if (a.backend != "emu" && a.backend != "gl")
        throw InputError("", "--backend must be emu or gl, not '" + a.backend + "'");
    const auto t0 = Clock::now();
    auto ms = [&] { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); };
    if (a.backend == "emu") {
        const gpu::VicpRenderer vicp(s.mesh(), *s.topology, s.field, s.tf, vicp_options(a));
        gpu::VicpFrame f = vicp.render(s.camera, s.width, s.height);
        return vicp_result(std::move(f), vicp.cpu_stage(), a, ms());
    }
    gpu::GlContext ctx(gpu::parse_gl_platform(a.gl));
    gpu::GlVicpRenderer vicp(ctx, s.mesh(), *s.topology, s.field, s.tf, vicp_options(a));
    gpu::VicpFrame f = vicp.render(s.camera, s.width, s.height);
    AlgoResult r = vicp_result(std::move(f), vicp.cpu_stage(), a, ms());
    r.stats["gl"] = ctx.info().summary();
    return r;
}

AlgoResult raycast_result(gpu::RaycastFrame f, const gpu::RaycastVolume& rv, double ms)
{
    AlgoResult r;
    r.ms = ms;
    const auto& st = f.stats;
    const gpu::RaycastOptions& o = rv.options();
    r.stats = {{"step", o.step},
               {"preintegrate", o.preintegrate},
               {"threshold", o.threshold},
               {"shading", o.light.has_value()},
               {"volume_format", gpu::texel_format_name(rv.texel_format())},
               {"rays", st.rays},
               {"samples", st.samples},
               {"max_samples_per_pixel", st.max_samples},
               {"stages_ms", {{"table", st.table_ms}, {"setup", st.setup_ms}, {"march", st.march_ms},
                              {"readback", st.readback_ms}}}};
    r.image = std::move(f.image);
    r.samples = std::move(f.samples);
    return r;
}

AlgoResult run_raycast(const Scene& s, const AlgoOptions& a)
{
    if (a.backend != "emu" && a.backend != "gl")
        throw InputError("", "--backend must be emu or gl, not '" + a.backend + "'");
    check_algorithm_scene(s, "raycast");
    const auto t0 = Clock::now();
    auto ms = [&] { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); };
    const gpu::RaycastOptions o = raycast_options(a);
    if (a.backend == "emu") {
        const gpu::RaycastRenderer rc(s.volume(), s.tf, o);
        gpu::RaycastFrame f = rc.render(s.camera, s.width, s.height);
        return raycast_result(std::move(f), rc.cpu_stage(), ms());
    }
    gpu::GlContext ctx(gpu::parse_gl_platform(a.gl));
    gpu::GlRaycastRenderer rc(ctx, s.volume(), s.tf, o);
    gpu::RaycastFrame f = rc.render(s.camera, s.width, s.height);
    AlgoResult r = raycast_result(std::move(f), rc.cpu_stage(), ms());
    r.stats["gl"] = ctx.info().summary();
    return r;
}

}  // namespace

void run_algorithm_check(const std::string& algo)
{
    if (algo == "reference" || algo == "havs" || algo == "vicp" || algo == "raycast") return;
    throw InputError("", "unknown algorithm '" + algo + "' (reference, havs, vicp, raycast)");
}

void check_algorithm_scene(const Scene& s, const std::string& algo)
{
    run_algorithm_check(algo);
    if (algo == "havs" || algo == "vicp") s.mesh();  // throws for a regular grid
    if (algo == "raycast" && !s.is_volume())
        throw InputError(s.mesh().source, "is a tetrahedral mesh: --algo raycast renders regular grids (.vti, .nrrd, "
                                          "structured points, raw)");
}

AlgoResult run_algorithm(const Scene& s, const std::string& algo, const AlgoOptions& o)
{
    run_algorithm_check(algo);
    if (algo == "reference") return run_reference(s, !o.no_cache);
    if (algo == "raycast") return run_raycast(s, o);
    return algo == "vicp" ? run_vicp(s, o) : run_havs(s, o);
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
