#include "bench/scene.h"

#include <cstdio>

#include <glm/geometric.hpp>

#include "reference/error.h"
#include "reference/image.h"

namespace uvr::cli {

void add_scene_options(CLI::App& cmd, SceneOptions& o)
{
    add_input_options(cmd, o.input);
    cmd.add_option("--tf", o.tf_path, "Transfer function JSON (default: a ramp over the field's range)");
    cmd.add_option("--camera", o.camera_path, "Camera JSON (default: the whole mesh seen from +z)");
    cmd.add_option("--view", o.view, "Orbit the default camera: AZIMUTH,ELEVATION in degrees");
    cmd.add_option("--size", o.size, "Image size WxH")->capture_default_str();
}

Scene setup_scene(const SceneOptions& o)
{
    Scene s;
    parse_size(o.size, s.width, s.height);
    s.data = load_input(o.input);
    print_warnings(s.data);
    if (!s.data.mesh)
        throw InputError(o.input.path, "is a regular grid; rendering volumes arrives with the ray caster (issue 7)");
    const TetMesh& mesh = *s.data.mesh;
    s.field = find_field(mesh, o.input.field);
    const Bounds b = mesh_bounds(mesh);
    s.tf = o.tf_path.empty() ? default_transfer_function(field_range(mesh.fields[s.field]), glm::length(b.extent()))
                             : load_transfer_function(o.tf_path);
    if (!o.camera_path.empty() && !o.view.empty())
        throw InputError("", "give either --camera or --view, not both");
    if (!o.camera_path.empty()) {
        s.camera = load_camera(o.camera_path);
    } else {
        double az = 0.0, el = 0.0;
        char comma = 0, extra = 0;
        if (!o.view.empty() && (std::sscanf(o.view.c_str(), "%lf%c%lf%c", &az, &comma, &el, &extra) != 3 || comma != ','))
            throw InputError("", "--view must be AZIMUTH,ELEVATION in degrees, found '" + o.view + "'");
        s.camera = default_camera(b, double(s.width) / double(s.height), az, el);
    }
    s.topology = std::make_unique<MeshTopology>(build_topology(mesh));
    return s;
}

}  // namespace uvr::cli
