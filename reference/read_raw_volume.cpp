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

namespace {

template <class T>
void decode_as(const std::string& bytes, bool big_endian, std::vector<float>& out)
{
    out.resize(bytes.size() / sizeof(T));
    for (std::size_t i = 0; i < out.size(); ++i) {
        T v;
        std::memcpy(&v, bytes.data() + i * sizeof(T), sizeof(T));
        out[i] = static_cast<float>(big_endian ? byteswap_value(v) : v);
    }
}

void decode_voxels(const std::string& bytes, VoxelType type, bool big_endian, std::vector<float>& out)
{
    switch (type) {
    case VoxelType::u8: decode_as<uint8_t>(bytes, big_endian, out); break;
    case VoxelType::i8: decode_as<int8_t>(bytes, big_endian, out); break;
    case VoxelType::u16: decode_as<uint16_t>(bytes, big_endian, out); break;
    case VoxelType::i16: decode_as<int16_t>(bytes, big_endian, out); break;
    case VoxelType::u32: decode_as<uint32_t>(bytes, big_endian, out); break;
    case VoxelType::i32: decode_as<int32_t>(bytes, big_endian, out); break;
    case VoxelType::f32: decode_as<float>(bytes, big_endian, out); break;
    case VoxelType::f64: decode_as<double>(bytes, big_endian, out); break;
    }
}

}  // namespace

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
    decode_voxels(bytes, type, big_endian, v.values);
    finalize_volume(v);
    Dataset result;
    result.volume = std::move(v);
    return result;
}

}  // namespace uvr
