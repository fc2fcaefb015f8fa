// MPI for the `uvr` program (docs/distributed.md): initialized only when a launcher (mpirun) started the process, so a
// plain run never pays for MPI_Init; every rank ends on a failure of any rank, with the failing rank's message.
#pragma once

#include <new>
#include <string>
#include <utility>

#include "reference/error.h"
#include "reference/mesh.h"

namespace uvr::mpi {

// True when a launcher started this process: Open MPI's mpirun sets OMPI_COMM_WORLD_SIZE, PMIx launchers PMIX_RANK,
// older ones PMI_RANK.
bool launched();

// MPI for the lifetime of the program: initialized by the constructor when launched(), finalized by the destructor.
class Runtime {
public:
    Runtime(int& argc, char**& argv);
    ~Runtime();
    Runtime(const Runtime&) = delete;
    Runtime& operator=(const Runtime&) = delete;
};

bool active();  // a Runtime initialized MPI
int rank();     // 0 without MPI
int ranks();    // 1 without MPI

// The failure of one or more ranks, known to every rank: what() names each failed rank and its message. Rank 0
// reports it; the others exit with the same status silently.
class RanksFailed : public InputError {
public:
    using InputError::InputError;
};

// The end of a stage, on every rank: `error` is this rank's failure ("" for none). When any rank failed, every rank
// throws RanksFailed with all the failed ranks' messages; otherwise every rank goes on. Collective.
void agree(const std::string& error);

// This rank's failure in `stage`: the message of an InputError, "out of memory", or "" when it succeeded.
template <class Stage>
std::string failure_of(Stage&& stage)
{
    try {
        stage();
    } catch (const InputError& e) {
        return e.what();
    } catch (const std::bad_alloc&) {
        return "out of memory";
    }
    return "";
}

// Runs `stage` on this rank and agrees on its failure with every other rank. Collective.
template <class Stage>
void on_every_rank(Stage&& stage)
{
    agree(failure_of(stage));
}

// A failure held back to a later agreement, for stages that need nothing from other ranks: once this rank fails, its
// later stages are skipped, and agree() (collective) tells every rank.
class HeldFailure {
public:
    template <class Stage>
    void run(Stage&& stage)
    {
        if (error_.empty()) error_ = failure_of(stage);
    }
    void agree() { mpi::agree(std::exchange(error_, std::string())); }

private:
    std::string error_;
};

// The whole data's bounds, field range and longest edge from each rank's part (componentwise min and max). Collective.
void reduce_extent(Bounds& bounds, Range& range, double& longest_edge);

// Ends every rank at once with exit status `code` (a failure some ranks may not know of: they could be waiting in a
// collective call). Returns only without MPI.
void abort_all(int code);

}  // namespace uvr::mpi
