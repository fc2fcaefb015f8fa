#include "distributed/exchange.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <stdexcept>
#include <string>

#include <mpi.h>

namespace uvr::mpi {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// MPI counts are ints: a count past INT_MAX is refused rather than wrapped.
int mpi_count(uint64_t n, const char* what)
{
    if (n > uint64_t(INT_MAX))
        throw std::runtime_error(std::string("more ") + what + " than one MPI call carries (" + std::to_string(n) +
                                 ")");
    return int(n);
}

}  // namespace

std::vector<int> balanced_bands(const std::vector<uint64_t>& fragments_per_row, int ranks)
{
    const int height = int(fragments_per_row.size());
    uint64_t total = 0;
    for (uint64_t c : fragments_per_row) total += c;
    std::vector<int> bands(std::size_t(ranks) + 1, height);
    bands[0] = 0;
    if (total == 0) {
        for (int r = 1; r < ranks; ++r) bands[std::size_t(r)] = int(int64_t(r) * height / ranks);
        return bands;
    }
    // Row j starts band r when the fragments above it reach r / ranks of the total (compared as prefix * ranks >= r *
    // total in integers, so the cut does not depend on rounding).
    uint64_t prefix = 0;
    int r = 1;
    for (int j = 0; j < height && r < ranks; ++j) {
        while (r < ranks && prefix * uint64_t(ranks) >= uint64_t(r) * total) bands[std::size_t(r++)] = j;
        prefix += fragments_per_row[std::size_t(j)];
    }
    return bands;
}

std::vector<RankStats> gather_stats(const RankStats& mine)
{
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    std::vector<RankStats> all(rank == 0 ? std::size_t(ranks) : 0);
    MPI_Gather(&mine, int(sizeof(RankStats)), MPI_BYTE, all.data(), int(sizeof(RankStats)), MPI_BYTE, 0,
               MPI_COMM_WORLD);
    return all;
}

std::vector<std::vector<char>> gather_bytes(const std::vector<char>& mine)
{
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const int count = mpi_count(mine.size(), "bytes");
    std::vector<int> counts(static_cast<std::size_t>(ranks), 0), at(static_cast<std::size_t>(ranks), 0);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    uint64_t total = 0;
    for (int r = 0; r < ranks; ++r) {
        at[std::size_t(r)] = mpi_count(total, "bytes");
        total += uint64_t(counts[std::size_t(r)]);
    }
    std::vector<char> all(rank == 0 ? total : 0);
    MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    std::vector<std::vector<char>> out;
    if (rank != 0) return out;
    for (int r = 0; r < ranks; ++r)
        out.emplace_back(all.begin() + at[std::size_t(r)], all.begin() + at[std::size_t(r)] + counts[std::size_t(r)]);
    return out;
}

void broadcast_bytes(std::vector<char>& bytes)
{
    int count = mpi_count(bytes.size(), "bytes");
    MPI_Bcast(&count, 1, MPI_INT, 0, MPI_COMM_WORLD);
    bytes.resize(std::size_t(count));
    MPI_Bcast(bytes.data(), count, MPI_BYTE, 0, MPI_COMM_WORLD);
}

Image composite_across_ranks(std::vector<Fragment>& fragments, int width, int height, ExchangeStats& stats)
{
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const auto t0 = std::chrono::steady_clock::now();
    stats.fragments = fragments.size();
    if (!std::is_sorted(fragments.begin(), fragments.end(), fragment_before))
        std::sort(fragments.begin(), fragments.end(), fragment_before);

    // Bands balanced by the fragments every rank holds per row.
    std::vector<uint64_t> per_row(std::size_t(height), 0);
    for (const Fragment& f : fragments) ++per_row[f.pixel / uint32_t(width)];
    MPI_Allreduce(MPI_IN_PLACE, per_row.data(), height, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    const std::vector<int> bands = balanced_bands(per_row, ranks);
    stats.first_row = bands[std::size_t(rank)];
    stats.rows = bands[std::size_t(rank) + 1] - bands[std::size_t(rank)];

    // The fragments are sorted by pixel, so each owner's are one stretch of them.
    std::vector<int> send(std::size_t(ranks), 0), recv(std::size_t(ranks), 0);
    std::vector<int> send_at(std::size_t(ranks), 0), recv_at(std::size_t(ranks), 0);
    std::size_t f = 0;
    for (int r = 0; r < ranks; ++r) {
        const uint64_t end = uint64_t(bands[std::size_t(r) + 1]) * uint64_t(width);
        const std::size_t start = f;
        while (f < fragments.size() && fragments[f].pixel < end) ++f;
        send_at[std::size_t(r)] = mpi_count(start, "fragments");
        send[std::size_t(r)] = mpi_count(f - start, "fragments");
    }
    MPI_Alltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, MPI_COMM_WORLD);
    uint64_t received = 0;
    for (int r = 0; r < ranks; ++r) {
        recv_at[std::size_t(r)] = mpi_count(received, "fragments");
        received += uint64_t(recv[std::size_t(r)]);
        if (r != rank) {
            stats.fragments_sent += uint64_t(send[std::size_t(r)]);
            stats.fragments_received += uint64_t(recv[std::size_t(r)]);
        }
    }
    stats.bytes_sent = stats.fragments_sent * sizeof(Fragment);
    stats.bytes_received = stats.fragments_received * sizeof(Fragment);
    MPI_Datatype type;
    MPI_Type_contiguous(int(sizeof(Fragment)), MPI_BYTE, &type);
    MPI_Type_commit(&type);
    std::vector<Fragment> band(received);
    MPI_Alltoallv(fragments.data(), send.data(), send_at.data(), type, band.data(), recv.data(), recv_at.data(), type,
                  MPI_COMM_WORLD);
    MPI_Type_free(&type);
    std::vector<Fragment>().swap(fragments);
    stats.exchange_seconds = seconds_since(t0);

    // Each owner composites its band; rank 0 gathers the bands, top to bottom.
    const auto t1 = std::chrono::steady_clock::now();
    Image mine(width, stats.rows);
    composite_fragments(band, mine, uint64_t(stats.first_row) * uint64_t(width));
    std::vector<int> counts(static_cast<std::size_t>(ranks)), at(static_cast<std::size_t>(ranks));
    for (int r = 0; r < ranks; ++r) {
        const uint64_t start = uint64_t(bands[std::size_t(r)]) * uint64_t(width) * 4u;
        at[std::size_t(r)] = mpi_count(start, "image values");
        counts[std::size_t(r)] = mpi_count(
            uint64_t(bands[std::size_t(r) + 1] - bands[std::size_t(r)]) * uint64_t(width) * 4u, "image values");
    }
    Image image;
    if (rank == 0) image = Image(width, height);
    MPI_Gatherv(mine.rgba.data(), counts[std::size_t(rank)], MPI_FLOAT, rank == 0 ? image.rgba.data() : nullptr,
                counts.data(), at.data(), MPI_FLOAT, 0, MPI_COMM_WORLD);
    stats.composite_seconds = seconds_since(t1);
    return image;
}

}  // namespace uvr::mpi
