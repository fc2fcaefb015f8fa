// `uvr demo`: the whole lab on the built-in data set, no argument needed. It grows with the project: today it builds
// the built-in torus and describes it; the reference render, the comparisons and the k sweep join as they land.
#include <chrono>
#include <cstdio>

#include "bench/commands.h"
#include "reference/builtin_mesh.h"
#include "reference/topology.h"

namespace uvr::cli {

void register_demo(CLI::App& app)
{
    auto* cmd = app.add_subcommand("demo", "Run the lab on the built-in mesh (a tetrahedralized torus)");
    cmd->callback([] {
        const auto t0 = std::chrono::steady_clock::now();
        const TetMesh mesh = load_builtin("builtin:torus");
        const MeshTopology topo = build_topology(mesh);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const Range r = field_range(mesh.fields[0]);
        std::printf("uvr demo: built-in torus (TetGen), %zu points, %zu tetrahedra, %zu faces (%zu boundary), "
                    "field '%s' in [%.4g, %.4g], convex: %s (%.2f s)\n",
                    mesh.points.size(), mesh.tets.size(), topo.faces.size(), topo.boundary_faces,
                    mesh.fields[0].name.c_str(), r.lo, r.hi, boundary_is_convex(mesh, topo) ? "yes" : "no", secs);
        std::printf("uvr demo: renderers, comparisons and the k sweep are not available yet (docs/status.md)\n");
    });
}

}  // namespace uvr::cli
