#include "bench/options.h"

#include <algorithm>
#include <cstdint>

#include "reference/error.h"

namespace uvr::cli {

void add_input_options(CLI::App& cmd, InputOptions& in)
{
    cmd.add_option("MESH", in.path, "Mesh or volume file (or builtin:torus, builtin:torus-small, builtin:grid-N)")
        ->required();
    cmd.add_option("--q", in.q_file, "PLOT3D solution (Q) file; MESH is then the PLOT3D XYZ file");
    cmd.add_option("--dims", in.dims, "Raw volume size X,Y,Z (x fastest)");
    cmd.add_option("--dtype", in.dtype, "Raw volume voxel type (uint8, int16, float32, ...)");
    cmd.add_flag("--big-endian", in.big_endian, "Raw volume is big-endian");
    cmd.add_option("--field", in.field, "Scalar field by name or index (default: the first), of any kind: point, "
                                        "per-cell vertex or cell data");
    cmd.add_option("--time", in.time_step, "Exodus II: the time step whose variables are read, INDEX (from 1) or last")
        ->capture_default_str();
}

void add_scene_options(CLI::App& cmd, SceneOptions& o)
{
    add_input_options(cmd, o.input);
    cmd.add_option("--tf", o.tf_path,
                   "Transfer function JSON, or preset:NAME (viridis, inferno, plasma, cool-to-warm, grayscale, jet) "
                   "on the default opacity (default: a ramp over the field's range; on a regular grid transparent "
                   "around the most common value)");
    cmd.add_option("--camera", o.camera_path, "Camera JSON (default: the whole mesh seen from +z)");
    cmd.add_option("--view", o.view, "Orbit the default camera: AZIMUTH,ELEVATION in degrees");
    cmd.add_option("--size", o.size, "Image size WxH")->capture_default_str();
}

void add_algo_options(CLI::App& cmd, AlgoOptions& o, bool with_per_run, const std::vector<std::string>& only)
{
    for (const AlgoOption& row : algo_option_table()) {
        if (!with_per_run && row.per_run) continue;
        if (!only.empty() && std::find(only.begin(), only.end(), row.name) == only.end()) continue;
        const AlgoOption* r = &row;  // the table lives as long as the program
        if (row.flag) {
            cmd.add_flag_function(
                "--" + row.name, [&o, r](std::int64_t n) { r->set(o, n > 0 ? "true" : "false"); }, row.help);
        } else {
            CLI::Option* opt = cmd.add_option_function<std::string>(
                "--" + row.name, [&o, r](const std::string& v) { r->set(o, v); }, row.help);
            if (!row.default_text.empty()) opt->default_str(row.default_text);
        }
    }
}

}  // namespace uvr::cli
