#include "bench/render_parallel.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "bench/sort_last.h"
#include "distributed/exchange.h"
#include "gpu/pipeline/segment.h"
#include "distributed/mpi_runtime.h"
#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "reference/fragments.h"
#include "reference/io_util.h"
#include "reference/ray_integrator.h"
#include "reference/timing.h"

namespace uvr::cli {

namespace {

nlohmann::json rank_json(const mpi::RankStats& r)
{
    const mpi::ExchangeStats& x = r.exchange;
    return {{"cells", r.cells},
            {"peak_memory_bytes", r.peak_memory_bytes},
            {"fragments", x.fragments},
            {"fragments_sent", x.fragments_sent},
            {"fragments_received", x.fragments_received},
            {"bytes_sent", x.bytes_sent},
            {"bytes_received", x.bytes_received},
            {"band_rows", {x.first_row, x.first_row + x.rows}},
            {"segments", r.trace.segments},
            {"entries", r.trace.entries},
            {"failures", r.trace.failures},
            {"seconds",
             {{"read", r.read_seconds},
              {"build", r.build_seconds},
              {"trace", r.trace.seconds},
              {"exchange", x.exchange_seconds},
              {"composite", x.composite_seconds}}}};
}

// This rank's pieces of a .pvtu, or its z-slab of builtin:grid-N's cubes (one piece a rank, made without a file).
Dataset rank_part(const std::string& path)
{
    const std::size_t rank = std::size_t(mpi::rank()), ranks = std::size_t(mpi::ranks());
    if (const int n = builtin_grid_cubes(path)) {
        if (std::size_t(n) < ranks)
            throw InputError(path, "has " + std::to_string(n) + " layers of cubes for " + std::to_string(ranks) +
                                       " ranks (each rank makes at least one)");
        Dataset d;
        d.mesh = builtin_grid(n, int(rank * std::size_t(n) / ranks), int((rank + 1) * std::size_t(n) / ranks));
        d.piece_of_cell.assign(d.mesh->tets.size(), uint32_t(rank));
        return d;
    }
    if (file_extension(path) != ".pvtu")
        throw InputError(path,
                         "under mpirun, uvr render reads a .pvtu of pieces (uvr partition writes one) or "
                         "makes builtin:grid-N");
    return read_pvtu(path, rank, ranks);
}

// Whether the ranks may go on without each other until their parts are rendered: the .pvtu records the whole mesh's
// extent (the camera and the transfer function need it). Every rank reads the same file, so every rank decides alike;
// a file that cannot be read takes the other way, where reading it fails on every rank and they agree on that.
bool extent_recorded(const std::string& path)
{
    if (file_extension(path) != ".pvtu") return false;
    try {
        return read_pvtu_whole_extent(path).has_value();
    } catch (const InputError&) {
        return false;
    }
}

// A part's extent: its bounds, longest edge and the range of the field rendered.
SceneExtent part_extent(const TetMesh& mesh, const std::string& field)
{
    return {mesh_bounds(mesh), field_range(mesh.fields[find_field(mesh, field)]), gpu::longest_tet_edge(mesh)};
}

// The extent a .pvtu records, for the field rendered.
SceneExtent recorded_extent(const Dataset& data, const std::string& field)
{
    const std::string name = data.mesh->fields[find_field(*data.mesh, field)].name;
    const WholeExtent& w = *data.whole;
    const auto range = std::find_if(w.ranges.begin(), w.ranges.end(), [&](const auto& r) { return r.first == name; });
    return {w.bounds, range->second, w.longest_edge};  // read_pvtu checked that every field has its range
}

// This rank's part of the scene, set up with the whole mesh's extent. Where the .pvtu records that extent (`recorded`),
// no rank waits for another here: a failure stays in `held` (the scene left empty) for settle(); otherwise the ranks
// agree after reading, on the extent, and after the set-up.
struct RankScene {
    std::optional<Scene> scene;
    bool recorded = false;
    SceneExtent own;  // this rank's part's extent, checked against the record by settle()
};
RankScene rank_scene(const SceneOptions& o, mpi::RankStats& st, mpi::HeldFailure& held)
{
    const auto start = Clock::now();
    RankScene r;
    r.recorded = extent_recorded(o.input.path);
    std::optional<Dataset> data;
    held.run([&] { data = rank_part(o.input.path); });
    if (!r.recorded) held.agree();
    st.read_seconds = ms_since(start) / 1000.0;
    const auto t_setup = Clock::now();  // the topology of the part: the first half of "build"
    SceneExtent whole;
    held.run([&] {
        r.own = part_extent(*data->mesh, o.input.field);
        whole = r.recorded ? recorded_extent(*data, o.input.field) : r.own;
    });
    if (!r.recorded) {
        held.agree();
        mpi::reduce_extent(whole.bounds, whole.range, whole.longest_edge);
    }
    held.run([&] { r.scene.emplace(setup_scene(std::move(*data), o, whole)); });
    if (!r.recorded) held.agree();
    st.build_seconds = ms_since(t_setup) / 1000.0;
    if (r.scene) st.cells = r.scene->mesh().tets.size();
    return r;
}

// Collective, after the stages that need nothing from other ranks: every rank's failure known to all; where the .pvtu
// records the whole's extent, the parts' extent joined must be exactly that record (a record that does not match its
// pieces would move the camera and the colours: refused, naming the file).
void settle(mpi::HeldFailure& held, RankScene& r, const std::string& path)
{
    held.agree();
    if (!r.recorded) return;
    SceneExtent parts = r.own;
    mpi::reduce_extent(parts.bounds, parts.range, parts.longest_edge);
    const SceneExtent& w = *r.scene->whole;
    if (parts.bounds.lo != w.bounds.lo || parts.bounds.hi != w.bounds.hi || parts.range.lo != w.range.lo ||
        parts.range.hi != w.range.hi || parts.longest_edge != w.longest_edge)
        throw mpi::RanksFailed(path,
                               "records a whole extent (FieldData) that its pieces do not have: write it again with "
                               "uvr partition");
}

}  // namespace

void render_reference_parallel(const SceneOptions& o, const std::string& out, bool json)
{
    const auto start = Clock::now();
    mpi::RankStats st;
    mpi::HeldFailure held;
    RankScene r = rank_scene(o, st, held);
    std::vector<Fragment> fragments;
    held.run([&] {
        const auto t_build = Clock::now();
        const RayIntegrator integrator(r.scene->mesh(), *r.scene->topology, r.scene->field, r.scene->tf);
        st.build_seconds += ms_since(t_build) / 1000.0;
        fragments = trace_fragments(integrator, r.scene->camera, r.scene->width, r.scene->height, st.trace);
    });
    const auto t_settle = Clock::now();
    settle(held, r, o.input.path);
    const double settle_seconds = ms_since(t_settle) / 1000.0;  // the wait for the other ranks: part of "exchange"
    const Scene& s = *r.scene;
    const Image image = mpi::composite_across_ranks(fragments, s.width, s.height, st.exchange);
    st.peak_memory_bytes = peak_memory_bytes();
    st.exchange.exchange_seconds += settle_seconds;
    const std::vector<mpi::RankStats> ranks = mpi::gather_stats(st);
    if (mpi::rank() != 0) return;

    write_image(out, image);
    if (!json) return;
    nlohmann::json j;
    j["algo"] = "reference";
    j["backend"] = "cpu";
    j["out"] = out;
    j["width"] = s.width;
    j["height"] = s.height;
    uint64_t segments = 0, entries = 0, failures = 0, fragments_total = 0;
    j["ranks"] = nlohmann::json::array();
    for (const mpi::RankStats& r : ranks) {
        j["ranks"].push_back(rank_json(r));
        segments += r.trace.segments;
        entries += r.trace.entries;
        failures += r.trace.failures;
        fragments_total += r.exchange.fragments;
    }
    j["rays"] = uint64_t(s.width) * uint64_t(s.height);
    j["segments"] = segments;
    j["entries"] = entries;
    j["failures"] = failures;
    j["fragments"] = fragments_total;
    j["seconds"] = ms_since(start) / 1000.0;
    std::printf("%s\n", j.dump(1).c_str());
}

void render_sort_last_parallel(const SceneOptions& o, const std::string& algo, const AlgoOptions& ao,
                               const std::string& out, bool json)
{
    const auto start = Clock::now();
    mpi::RankStats st;
    mpi::HeldFailure held;
    RankScene r = rank_scene(o, st, held);
    // Each piece this rank holds is a part: rendered on its own, sent to rank 0 with its box and its stats as
    // [piece (uint32), box (6 doubles), image (width x height x 4 floats), stats' length (uint32), stats (JSON text)].
    const auto t_render = Clock::now();
    std::vector<char> mine;
    held.run([&] {
        const Scene& s = *r.scene;
        std::vector<uint32_t> pieces = s.data.piece_of_cell;
        std::sort(pieces.begin(), pieces.end());
        pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
        for (uint32_t piece : pieces) {
            const Scene ps = part_scene(s, extract_part(s.mesh(), s.data.piece_of_cell, piece));
            const Bounds box = centroid_box(ps.mesh());
            const AlgoResult r = run_algorithm(ps, algo, ao);
            const auto put = [&](const void* p, std::size_t n) {
                mine.insert(mine.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
            };
            const std::string stats = r.stats.dump();
            const uint32_t stats_bytes = uint32_t(stats.size());
            put(&piece, sizeof piece);
            put(&box, sizeof box);
            put(r.image.rgba.data(), r.image.rgba.size() * sizeof(float));
            put(&stats_bytes, sizeof stats_bytes);
            put(stats.data(), stats.size());
        }
    });
    st.trace.seconds = ms_since(t_render) / 1000.0;
    const auto t_gather = Clock::now();
    settle(held, r, o.input.path);
    const Scene& s = *r.scene;
    const std::vector<std::vector<char>> all = mpi::gather_bytes(mine);
    st.exchange.exchange_seconds = ms_since(t_gather) / 1000.0;
    st.exchange.bytes_sent = mpi::rank() == 0 ? 0 : mine.size();
    st.peak_memory_bytes = peak_memory_bytes();
    const std::vector<mpi::RankStats> ranks = mpi::gather_stats(st);
    if (mpi::rank() != 0) return;

    std::vector<uint32_t> piece_ids;
    std::vector<Bounds> boxes;
    std::vector<Image> images;
    std::map<uint32_t, nlohmann::json> stats_of_piece;  // in piece order, whichever rank rendered it
    const std::size_t image_bytes = std::size_t(s.width) * std::size_t(s.height) * 4 * sizeof(float);
    for (const std::vector<char>& bytes : all)
        for (std::size_t at = 0; at < bytes.size();) {
            uint32_t piece = 0, stats_bytes = 0;
            Bounds box;
            Image image(s.width, s.height);
            const auto take = [&](void* to, std::size_t n) {
                std::memcpy(to, bytes.data() + at, n);
                at += n;
            };
            take(&piece, sizeof piece);
            take(&box, sizeof box);
            take(image.rgba.data(), image_bytes);
            take(&stats_bytes, sizeof stats_bytes);
            stats_of_piece[piece] = nlohmann::json::parse(bytes.begin() + std::ptrdiff_t(at),
                                                          bytes.begin() + std::ptrdiff_t(at + stats_bytes));
            at += stats_bytes;
            piece_ids.push_back(piece);
            boxes.push_back(box);
            images.push_back(std::move(image));
        }
    bool separated = true;
    const std::vector<uint32_t> order = back_to_front(boxes, s.camera, separated);
    write_image(out, blend_back_to_front(images, order));
    if (!json) return;
    nlohmann::json pieces_back_to_front = nlohmann::json::array();
    for (uint32_t i : order) pieces_back_to_front.push_back(piece_ids[i]);
    // The parts' stats merged as the one-process sort-last merges them (bench/sort_last.h), then this run's own.
    std::vector<nlohmann::json> part_stats;
    for (auto& [piece, stats] : stats_of_piece) part_stats.push_back(std::move(stats));
    nlohmann::json j = merge_part_stats(part_stats);
    j.update({{"algo", algo},
              {"backend", ao.backend},
              {"out", out},
              {"width", s.width},
              {"height", s.height},
              {"seconds", ms_since(start) / 1000.0}});
    j["sort_last"] = {{"parts", piece_ids.size()},
                      {"order", pieces_back_to_front},
                      {"separated", separated},
                      {"part_stats", part_stats}};
    j["ranks"] = nlohmann::json::array();
    for (const mpi::RankStats& r : ranks)
        j["ranks"].push_back(
            {{"cells", r.cells},
             {"peak_memory_bytes", r.peak_memory_bytes},
             {"bytes_sent", r.exchange.bytes_sent},
             {"seconds",
              {{"read", r.read_seconds}, {"render", r.trace.seconds}, {"gather", r.exchange.exchange_seconds}}}});
    std::printf("%s\n", j.dump(1).c_str());
}

}  // namespace uvr::cli
