#include "reference/dataset.h"

#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

Dataset load_dataset(const std::string& path, const LoadOptions& options)
{
    if (is_builtin_path(path)) {
        Dataset d;
        if (path == kBuiltinVolumePath) {
            d.volume = builtin_torus_volume();
            return d;
        }
        d.mesh = load_builtin(path);
        return d;
    }
    const std::string ext = file_extension(path);
    if (options.raw_dims) return read_raw_volume(path, *options.raw_dims, options.raw_dtype, options.raw_big_endian);
    if (!options.q_file.empty()) return read_plot3d(path, options.q_file, options.cell_census);
    if (ext == ".vtk") return read_vtk_legacy(path);
    if (ext == ".vtu" || ext == ".vti") return read_vtk_xml(path);
    if (ext == ".pvtu") return read_pvtu(path);
    if (ext == ".node" || ext == ".ele") return read_tetgen(path);
    if (ext == ".off") return read_off(path);
    if (ext == ".nrrd" || ext == ".nhdr") return read_nrrd(path);
    if (ext == ".mhd" || ext == ".mha") return read_metaimage(path);
    if (ext == ".slc") return read_slc(path);
    if (ext == ".exo" || ext == ".e" || ext == ".ex2" || (ext == ".g" && looks_like_exodus(path)))
        return read_exodus(path, options.time_step);
    if (ext == ".xyz" || ext == ".x" || ext == ".g" || ext == ".p3d") return read_plot3d(path, "", options.cell_census);
    if (ext == ".raw")
        throw InputError(path, "a raw volume needs its size: --dims X,Y,Z (and --dtype, default uint8)");
    if (ext == ".bin")
        throw InputError(path, "ambiguous .bin file: give --q Q.bin for a PLOT3D grid, or --dims X,Y,Z for a raw "
                               "volume");
    throw InputError(path, "unknown file format '" + ext +
                               "' (known: .vtk .vtu .pvtu .vti .node .ele .off .nrrd .nhdr "
                               ".mhd .mha .slc .raw .exo .e .ex2 .g, PLOT3D with --q)");
}

}  // namespace uvr
