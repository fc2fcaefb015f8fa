// Sub-commands whose algorithms have not landed yet. They exist so that `uvr --help` shows the whole contract of SPEC
// §3, and so that a user who calls one is told plainly that it is not there yet (exit 1), rather than getting a
// "no such command" or, worse, an empty picture.
#include <cstdio>

#include "bench/commands.h"
#include "reference/error.h"

namespace uvr::cli {

namespace {

void pending(CLI::App& app, const char* name, const char* description, const char* missing)
{
    auto* cmd = app.add_subcommand(name, description);
    cmd->allow_extras();
    cmd->callback([name, missing] {
        throw InputError("", std::string("'uvr ") + name + "' is not available yet: " + missing +
                                 " (see docs/status.md)");
    });
}

}  // namespace

void register_pending(CLI::App& app)
{
    pending(app, "sweep", "Error of HAVS against the k-buffer size k", "it needs the HAVS emulation");
}

}  // namespace uvr::cli
