#include "bench/options.h"

#include <cstdio>
#include <sstream>

#include "reference/error.h"

namespace uvr::cli {

void add_input_options(CLI::App& cmd, InputOptions& in)
{
    cmd.add_option("MESH", in.path, "Mesh or volume file (or builtin:torus, builtin:torus-small)")->required();
    cmd.add_option("--q", in.q_file, "PLOT3D solution (Q) file; MESH is then the PLOT3D XYZ file");
    cmd.add_option("--dims", in.dims, "Raw volume size X,Y,Z (x fastest)");
    cmd.add_option("--dtype", in.dtype, "Raw volume voxel type (uint8, int16, float32, ...)");
    cmd.add_flag("--big-endian", in.big_endian, "Raw volume is big-endian");
    cmd.add_option("--field", in.field, "Scalar field by name or index (default: the first), of any kind: point, "
                                        "per-cell vertex or cell data");
    cmd.add_option("--time", in.time_step, "Exodus II: the time step whose variables are read, INDEX (from 1) or last")
        ->capture_default_str();
}

Dataset load_input(const InputOptions& in)
{
    LoadOptions lo;
    lo.q_file = in.q_file;
    lo.raw_dtype = in.dtype;
    lo.raw_big_endian = in.big_endian;
    lo.time_step = in.time_step;
    if (!in.dims.empty()) {
        std::array<int64_t, 3> d{0, 0, 0};
        char c1 = 0, c2 = 0, extra = 0;
        long long x = 0, y = 0, z = 0;
        if (std::sscanf(in.dims.c_str(), "%lld%c%lld%c%lld%c", &x, &c1, &y, &c2, &z, &extra) != 5 || c1 != ',' ||
            c2 != ',' || x < 1 || y < 1 || z < 1)
            throw InputError("", "--dims must be X,Y,Z with positive integers, found '" + in.dims + "'");
        d = {x, y, z};
        lo.raw_dims = d;
    }
    Dataset d = load_dataset(in.path, lo);
    if (d.mesh && !in.field.empty()) find_field(*d.mesh, in.field);  // fail early on an unknown --field
    return d;
}

void print_warnings(const Dataset& d)
{
    for (const auto& w : d.warnings) std::fprintf(stderr, "uvr: warning: %s\n", w.c_str());
}

}  // namespace uvr::cli
