#include "distributed/mpi_runtime.h"

#include <algorithm>
#include <cstdlib>
#include <utility>
#include <vector>

#include <mpi.h>

namespace uvr::mpi {

namespace {
bool g_active = false;
int g_rank = 0, g_ranks = 1;
}  // namespace

bool launched()
{
    return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_RANK");
}

Runtime::Runtime(int& argc, char**& argv)
{
    if (!launched()) return;
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_ranks);
    g_active = true;
}

Runtime::~Runtime()
{
    if (g_active) MPI_Finalize();
    g_active = false;
}

bool active()
{
    return g_active;
}
int rank()
{
    return g_rank;
}
int ranks()
{
    return g_ranks;
}

void agree(const std::string& error)
{
    if (!g_active) {
        if (!error.empty()) throw RanksFailed("", error);
        return;
    }
    const int length = int(error.size());
    std::vector<int> lengths(static_cast<std::size_t>(g_ranks));
    MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, MPI_COMM_WORLD);
    std::vector<int> offsets(std::size_t(g_ranks) + 1, 0);
    for (int r = 0; r < g_ranks; ++r) offsets[std::size_t(r) + 1] = offsets[std::size_t(r)] + lengths[std::size_t(r)];
    if (offsets.back() == 0) return;
    std::string all(std::size_t(offsets.back()), '\0');
    MPI_Allgatherv(error.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
                   MPI_COMM_WORLD);
    // One line per distinct message, in the order of the first rank that gave it, with the ranks that gave it.
    std::vector<std::pair<std::string, std::vector<int>>> messages;
    for (int r = 0; r < g_ranks; ++r) {
        if (lengths[std::size_t(r)] == 0) continue;
        const std::string m = all.substr(std::size_t(offsets[std::size_t(r)]), std::size_t(lengths[std::size_t(r)]));
        auto it = std::find_if(messages.begin(), messages.end(), [&](const auto& e) { return e.first == m; });
        if (it == messages.end()) it = messages.insert(messages.end(), {m, {}});
        it->second.push_back(r);
    }
    std::string text;
    for (const auto& [m, who] : messages) {
        if (!text.empty()) text += "; ";
        if (int(who.size()) == g_ranks) {
            text += m;
            continue;
        }
        text += who.size() == 1 ? "rank " : "ranks ";
        for (std::size_t i = 0; i < who.size(); ++i) text += (i ? ", " : "") + std::to_string(who[i]);
        text += ": " + m;
    }
    throw RanksFailed("", text);
}

void reduce_extent(Bounds& bounds, Range& range, double& longest_edge)
{
    if (!g_active) return;
    double lo[4] = {bounds.lo.x, bounds.lo.y, bounds.lo.z, range.lo};
    double hi[5] = {bounds.hi.x, bounds.hi.y, bounds.hi.z, range.hi, longest_edge};
    MPI_Allreduce(MPI_IN_PLACE, lo, 4, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, hi, 5, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    longest_edge = hi[4];
    bounds.lo = glm::dvec3(lo[0], lo[1], lo[2]);
    bounds.hi = glm::dvec3(hi[0], hi[1], hi[2]);
    range = Range{lo[3], hi[3]};
}

void abort_all(int code)
{
    if (g_active) MPI_Abort(MPI_COMM_WORLD, code);
}

}  // namespace uvr::mpi
