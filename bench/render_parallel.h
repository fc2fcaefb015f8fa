// `uvr render` under mpirun (docs/distributed.md): the reference data-parallel over the pieces of a .pvtu, and
// sort-last HAVS and VICP over them.
#pragma once

#include <string>

#include "bench/algo_options.h"
#include "bench/scene.h"

namespace uvr::cli {

// Collective. Every rank reads its pieces, traces the fragments of every pixel's ray through its cells, and sends them
// to their pixel band's owner, which composites them; rank 0 writes `out` and, with `json`, prints the run with one
// object per rank. A failure of any rank ends every rank with mpi::RanksFailed (rank 0 reports it).
void render_reference_parallel(const SceneOptions& o, const std::string& out, bool json);

// Collective: sort-last HAVS or VICP (`algo`), as ParaView runs them. Every rank renders each of its pieces on its
// own; rank 0 receives the pieces' images and boxes, blends them back to front in the order of the boxes
// (bench/sort_last.h) and writes `out`. Failures as render_reference_parallel's.
void render_sort_last_parallel(const SceneOptions& o, const std::string& algo, const AlgoOptions& ao,
                               const std::string& out, bool json);

}  // namespace uvr::cli
