// The `uvr` program: every sub-command (cmd_<name>.cpp) registered on one CLI11 application; the one place where
// errors become messages and exit codes (bench/program.h).
#include "bench/program.h"

#include <cstdio>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "bench/commands.h"
#include "distributed/mpi_runtime.h"
#include "reference/error.h"

namespace uvr::cli {

namespace {

// The exit status of a failure on this rank alone: under MPI the other ranks may wait for it in a collective call, so
// every rank is ended with it (mpi::abort_all); without MPI it is returned.
int failed(int code)
{
    if (code != 0) mpi::abort_all(code);
    return code;
}

}  // namespace

int run_program(int argc, char** argv)
{
    CLI::App app{"uvr: how right GPU volume renderers of tetrahedral meshes are, and what they cost"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "uvr 0.1");
    register_info(app);
    register_render(app);
    register_bench(app);
    register_export(app);
    register_compare(app);
    register_sweep(app);
    register_budget(app);
    register_partition(app);
    register_verify(app);
    register_gpu_check(app);
    register_demo(app);
    // Under mpirun every rank runs the program; a failure that not every rank knows of ends them all (failed()).
    const mpi::Runtime runtime(argc, argv);
    try {
        const std::string command = argc < 2 ? "" : argv[1];
        if (mpi::active() && command != "render" && command != "sweep")
            throw mpi::RanksFailed("", "under mpirun, uvr runs render and sweep only");
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return failed(rc == 0 ? 0 : kExitUsage);
    } catch (const mpi::RanksFailed& e) {
        if (mpi::rank() == 0) std::fprintf(stderr, "uvr: %s\n", e.what());
        return kExitInputError;
    } catch (const uvr::InputError& e) {
        std::fprintf(stderr, "uvr: %s\n", e.what());
        return failed(kExitInputError);
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "uvr: out of memory\n");
        return failed(kExitInputError);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "uvr: internal error: %s\n", e.what());
        return failed(kExitInternal);
    }
    return 0;
}

}  // namespace uvr::cli
