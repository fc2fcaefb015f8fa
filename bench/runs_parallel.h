// Independent renders of one scene spread over the ranks under mpirun (docs/distributed.md): `uvr sweep`'s runs.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "bench/algorithms.h"

namespace uvr::cli {

// One render: `algo` with `options` from `camera`, known by its `tag` (unique in its list).
struct PlannedRun {
    std::string tag;
    std::string algo;
    Camera camera;
    AlgoOptions options;
};

// Collective. Renders the runs whose `wanted` flag is set (read on rank 0 only), dealt round robin in list order (one
// run a rank a round), and returns every result on rank 0 by tag: the image, ms, stats and ordering errors (the other
// diagnostics stay empty); rank 0 holds every image until it returns. The other ranks return an empty map. A failing
// run ends every rank (mpi::RanksFailed).
std::map<std::string, AlgoResult> render_across_ranks(Scene& scene, const std::vector<PlannedRun>& runs,
                                                      std::vector<char> wanted);

}  // namespace uvr::cli
