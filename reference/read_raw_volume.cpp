// Raw volumes: samples only, x fastest, in the byte order given; the size and type come from the command line.
//
// With no header to cross-check, the file's size is the only evidence that the dimensions and type are right, so it
// must match exactly: a file even one sample too long or short means a wrong --dims or --dtype, and rendering it would
// show a sheared or noisy volume rather than an error.
#include <array>
#include <cstring>
#include <string>

#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

Dataset read_raw_volume(const std::string& path, const std::array<int64_t, 3>& dims, const std::string& dtype,
                        bool big_endian)
{
    const VoxelType type = parse_voxel_type(dtype, path);
    const std::string shape = std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
    uint64_t samples = 1;
    for (int64_t d : dims) {
        if (d < 1) throw InputError(path, "raw volume dimensions must be at least 1, got " + shape);
        if (uint64_t(d) > kMaxElements / samples)
            throw InputError(path, "raw volume dimensions " + shape + " describe more samples than uvr can hold");
        samples *= uint64_t(d);
    }
    const std::string bytes = read_file_bytes(path);
    const uint64_t need = samples * voxel_type_size(type);
    if (bytes.size() != need)
        throw InputError(path, std::string(bytes.size() < need ? "truncated" : "too long") + ": a " + shape + " " +
                                   voxel_type_name(type) + " raw volume needs exactly " + std::to_string(need) +
                                   " bytes, but the file holds " + std::to_string(bytes.size()) +
                                   " (check --dims and --dtype)");
    Volume v;
    v.source = path;
    v.dims = dims;
    v.type = type;
    v.values.resize(bytes.size() / voxel_type_size(type));
    decode_voxels(bytes, type, big_endian, v.values.data());
    finalize_volume(v);
    Dataset result;
    result.volume = std::move(v);
    return result;
}

}  // namespace uvr
