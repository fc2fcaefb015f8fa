// `uvr demo`: the whole lab on the built-in data set, no argument needed. It grows with the project: today it builds
// the built-in torus, renders its ground truth from two views and writes the images; the GPU algorithms, the
// comparisons and the k sweep join as they land (docs/status.md).
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/progress.h"
#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "reference/io_util.h"
#include "reference/reference_renderer.h"
#include "reference/topology.h"

namespace uvr::cli {

void register_demo(CLI::App& app)
{
    auto* cmd = app.add_subcommand("demo", "Run the lab on the built-in mesh (a tetrahedralized torus)");
    auto out_dir = std::make_shared<std::string>("uvr-demo");
    cmd->add_option("--out", *out_dir, "Directory for the demo's images and numbers")->capture_default_str();
    cmd->callback([out_dir] {
        const auto t0 = std::chrono::steady_clock::now();
        const TetMesh mesh = load_builtin("builtin:torus");
        const MeshTopology topo = build_topology(mesh);
        const Range r = field_range(mesh.fields[0]);
        std::printf("uvr demo: built-in torus (TetGen): %zu points, %zu tetrahedra, %zu faces (%zu boundary), "
                    "field '%s' in [%.4g, %.4g], convex: %s\n",
                    mesh.points.size(), mesh.tets.size(), topo.faces.size(), topo.boundary_faces,
                    mesh.fields[0].name.c_str(), r.lo, r.hi, boundary_is_convex(mesh, topo) ? "yes" : "no");
        std::error_code ec;
        std::filesystem::create_directories(*out_dir, ec);
        if (ec) throw InputError(*out_dir, "cannot create the demo directory: " + ec.message());
        const Bounds b = mesh_bounds(mesh);
        const TransferFunction tf = default_transfer_function(r, glm::length(b.extent()));
        const RayIntegrator integrator(mesh, topo, 0, tf);
        nlohmann::json summary;
        summary["mesh"] = {{"points", mesh.points.size()}, {"tetrahedra", mesh.tets.size()}};
        for (const auto& [name, az, el] : {std::tuple{"front", 0.0, 0.0}, std::tuple{"oblique", 30.0, 50.0}}) {
            const Camera cam = default_camera(b, 1.0, az, el);
            ReferenceStats stats;
            ProgressBar bar(std::string("reference ") + name);
            const Image img = render_reference(integrator, cam, 512, 512, stats, [&](double f) { bar.update(f); });
            bar.finish();
            if (stats.failures) throw InputError("builtin:torus", "rays were abandoned by the walk's guards");
            const std::string base = *out_dir + "/reference-" + name;
            write_image(base + ".png", img);
            write_image(base + ".npy", img);
            std::printf("uvr demo: reference, %s view: %.0f ms, %llu segments -> %s.png\n", name,
                        stats.seconds * 1000.0, static_cast<unsigned long long>(stats.segments), base.c_str());
            summary["views"][name] = {{"azimuth", az}, {"elevation", el}, {"ms", stats.seconds * 1000.0},
                                      {"segments", stats.segments}};
        }
        write_file_atomically(*out_dir + "/demo.json", summary.dump(1) + "\n");
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("uvr demo: done in %.1f s; images and numbers in %s/\n", secs, out_dir->c_str());
        std::printf("uvr demo: HAVS, VICP, the ray caster, comparisons and the k sweep are not available yet "
                    "(docs/status.md)\n");
    });
}

}  // namespace uvr::cli
