// `uvr export MESH --out DIR`: the scene as uvr resolves it (tetrahedra or a regular grid's samples, field, transfer
// function, camera, size), written in open formats so that other renderers (bench/peers/) draw exactly the same thing.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/commands.h"
#include "bench/scene.h"
#include "gpu/raycast/raycast_setup.h"
#include "reference/error.h"
#include "reference/io_util.h"
#include "reference/write_vtk.h"

namespace uvr::cli {

void register_export(CLI::App& app)
{
    auto* cmd = app.add_subcommand(
        "export", "Write the resolved scene: mesh.vtk (or volume.vtk), tf.json, camera.json, scene.json");
    auto o = std::make_shared<SceneOptions>();
    auto dir = std::make_shared<std::string>();
    add_scene_options(*cmd, *o);
    cmd->add_option("--out", *dir, "Output directory")->required();
    cmd->callback([o, dir] {
        const Scene s = setup_scene(*o);
        std::error_code ec;
        std::filesystem::create_directories(*dir, ec);
        if (ec) throw InputError(*dir, "cannot create the directory: " + ec.message());
        nlohmann::json j = {{"width", s.width}, {"height", s.height}, {"field", s.field_name()}};
        const char* data_file = s.is_volume() ? "volume.vtk" : "mesh.vtk";
        if (s.is_volume()) {
            // A regular grid: its samples as they are (a peer's ray caster samples them, as uvr's does).
            const Volume& v = s.volume();
            write_vtk_legacy(*dir + "/" + data_file, v);
            const Range r = volume_range(v);
            j["kind"] = "volume";
            j["scalar_range"] = {r.lo, r.hi};
            j["dims"] = v.dims;
            j["voxels"] = v.dims[0] * v.dims[1] * v.dims[2];
            j["default_step"] = gpu::default_raycast_step(v);
        } else {
            write_vtk_legacy(*dir + "/" + data_file, s.mesh(), s.field);
            const Range r = field_range(s.mesh().fields[s.field]);
            j["kind"] = "mesh";
            j["scalar_range"] = {r.lo, r.hi};
            j["tetrahedra"] = s.mesh().tets.size();
        }
        write_file_atomically(*dir + "/tf.json", transfer_function_json(s.tf) + "\n");
        write_file_atomically(*dir + "/camera.json", camera_json(s.camera) + "\n");
        write_file_atomically(*dir + "/scene.json", j.dump(1) + "\n");
        std::printf("%s/: %s, tf.json, camera.json, scene.json\n", dir->c_str(), data_file);
    });
}

}  // namespace uvr::cli
