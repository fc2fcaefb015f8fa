// `uvr export MESH --out DIR`: the scene as uvr resolves it (tetrahedra, field, transfer function, camera, size),
// written in open formats so that other renderers (bench/peers/) draw exactly the same thing.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/scene.h"
#include "reference/error.h"
#include "reference/io_util.h"
#include "reference/write_vtk.h"

namespace uvr::cli {

void register_export(CLI::App& app)
{
    auto* cmd = app.add_subcommand("export", "Write the resolved scene: mesh.vtk, tf.json, camera.json, scene.json");
    auto o = std::make_shared<SceneOptions>();
    auto dir = std::make_shared<std::string>();
    add_scene_options(*cmd, *o);
    cmd->add_option("--out", *dir, "Output directory")->required();
    cmd->callback([o, dir] {
        const Scene s = setup_scene(*o);
        std::error_code ec;
        std::filesystem::create_directories(*dir, ec);
        if (ec) throw InputError(*dir, "cannot create the directory: " + ec.message());
        write_vtk_legacy(*dir + "/mesh.vtk", s.mesh(), s.field);
        write_file_atomically(*dir + "/tf.json", transfer_function_json(s.tf) + "\n");
        write_file_atomically(*dir + "/camera.json", camera_json(s.camera) + "\n");
        const Range r = field_range(s.mesh().fields[s.field]);
        nlohmann::json j = {{"width", s.width},
                            {"height", s.height},
                            {"field", s.mesh().fields[s.field].name},
                            {"scalar_range", {r.lo, r.hi}},
                            {"tetrahedra", s.mesh().tets.size()}};
        write_file_atomically(*dir + "/scene.json", j.dump(1) + "\n");
        std::printf("%s/: mesh.vtk, tf.json, camera.json, scene.json\n", dir->c_str());
    });
}

}  // namespace uvr::cli
