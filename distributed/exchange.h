// Compositing ray fragments across ranks (docs/distributed.md): every rank's fragments travel to the rank that owns
// their pixel's band of rows (direct send, one MPI_Alltoallv), each owner composites its band front to back
// (composite_fragments), and rank 0 gathers the bands into the image.
#pragma once

#include <cstdint>
#include <vector>

#include "reference/fragments.h"
#include "reference/image.h"

namespace uvr::mpi {

struct ExchangeStats {
    uint64_t fragments = 0;           // this rank's own
    uint64_t fragments_sent = 0;      // to other ranks
    uint64_t fragments_received = 0;  // from other ranks
    uint64_t bytes_sent = 0, bytes_received = 0;
    int first_row = 0, rows = 0;  // this rank's band
    double exchange_seconds = 0.0, composite_seconds = 0.0;
};

// The bands: rank r owns rows [bands[r], bands[r + 1]), cut where the running count of fragments reaches r / ranks of
// their total, so that each rank composites about as many fragments; without fragments the rows are split evenly. A
// band may be empty (a row holding more than a share).
std::vector<int> balanced_bands(const std::vector<uint64_t>& fragments_per_row, int ranks);

// What one rank did in a data-parallel frame, for the JSON: its part, its trace, its share of the exchange.
struct RankStats {
    uint64_t cells = 0, peak_memory_bytes = 0;
    double read_seconds = 0.0, build_seconds = 0.0;
    ReferenceStats trace;
    ExchangeStats exchange;
};
// Every rank's stats, in rank order, on rank 0 (the others get an empty list). Collective.
std::vector<RankStats> gather_stats(const RankStats& mine);

// Every rank's bytes, in rank order, on rank 0 (the others get an empty list): sort-last's part images, a
// sweep's runs. Collective.
std::vector<std::vector<char>> gather_bytes(const std::vector<char>& mine);

// Rank 0's `bytes` on every rank (the others' `bytes` are replaced). Collective.
void broadcast_bytes(std::vector<char>& bytes);

// Collective. `fragments` (this rank's, any order) are consumed. Rank 0 returns the width x height image; the other
// ranks an empty one.
Image composite_across_ranks(std::vector<Fragment>& fragments, int width, int height, ExchangeStats& stats);

}  // namespace uvr::mpi
