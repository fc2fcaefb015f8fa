// `uvr render --algo reference` under mpirun: the reference, data-parallel over the pieces of a .pvtu
// (docs/distributed.md).
#pragma once

#include <string>

#include "bench/scene.h"

namespace uvr::cli {

// Collective. Every rank reads its pieces, traces the fragments of every pixel's ray through its cells, and sends them
// to their pixel band's owner, which composites them; rank 0 writes `out` and, with `json`, prints the run with one
// object per rank. A failure of any rank ends every rank with mpi::RanksFailed (rank 0 reports it).
void render_reference_parallel(const SceneOptions& o, const std::string& out, bool json);

}  // namespace uvr::cli
