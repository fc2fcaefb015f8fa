#include "bench/render_parallel.h"

#include <cstdio>
#include <optional>

#include <nlohmann/json.hpp>

#include "distributed/exchange.h"
#include "distributed/mpi_session.h"
#include "reference/error.h"
#include "reference/fragments.h"
#include "reference/io_util.h"
#include "reference/ray_integrator.h"
#include "reference/timing.h"

namespace uvr::cli {

namespace {

// Runs `stage` on this rank and agrees on its failure with every other rank (mpi::agree).
template <class Stage>
void on_every_rank(Stage&& stage)
{
    std::string error;
    try {
        stage();
    } catch (const InputError& e) {
        error = e.what();
    } catch (const std::bad_alloc&) {
        error = "out of memory";
    }
    mpi::agree(error);
}

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

}  // namespace

void render_reference_parallel(const SceneOptions& o, const std::string& out, bool json)
{
    const auto start = Clock::now();
    mpi::RankStats st;
    std::optional<Dataset> data;
    on_every_rank([&] {
        if (file_extension(o.input.path) != ".pvtu")
            throw InputError(o.input.path,
                             "under mpirun, uvr render reads a .pvtu of pieces (uvr partition writes one)");
        data = read_pvtu(o.input.path, std::size_t(mpi::rank()), std::size_t(mpi::ranks()));
    });
    st.read_seconds = ms_since(start) / 1000.0;

    const auto t_build = Clock::now();
    SceneExtent whole;
    on_every_rank([&] {
        const TetMesh& mesh = *data->mesh;
        whole.bounds = mesh_bounds(mesh);
        whole.range = field_range(mesh.fields[find_field(mesh, o.input.field)]);
    });
    mpi::reduce_extent(whole.bounds, whole.range);
    std::optional<Scene> scene;
    on_every_rank([&] { scene.emplace(setup_scene(std::move(*data), o, whole)); });
    const Scene& s = *scene;
    const RayIntegrator integrator(s.mesh(), *s.topology, s.field, s.tf);
    st.cells = s.mesh().tets.size();
    st.build_seconds = ms_since(t_build) / 1000.0;

    std::vector<Fragment> fragments = trace_fragments(integrator, s.camera, s.width, s.height, st.trace);
    const Image image = mpi::composite_across_ranks(fragments, s.width, s.height, st.exchange);
    st.peak_memory_bytes = peak_memory_bytes();
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

}  // namespace uvr::cli
