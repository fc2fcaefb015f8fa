// The `uvr` program: every sub-command (cmd_<name>.cpp) registered on one CLI11 application; the one place where
// errors become messages and exit codes (bench/program.h).
#include "bench/program.h"

#include <cstdio>
#include <new>

#include <CLI/CLI.hpp>

#include "bench/commands.h"
#include "reference/error.h"

namespace uvr::cli {

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
    register_demo(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : kExitUsage;
    } catch (const uvr::InputError& e) {
        std::fprintf(stderr, "uvr: %s\n", e.what());
        return kExitInputError;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "uvr: out of memory\n");
        return kExitInputError;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "uvr: internal error: %s\n", e.what());
        return kExitInternal;
    }
    return 0;
}

}  // namespace uvr::cli
