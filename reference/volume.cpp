#include "reference/volume.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

VoxelType parse_voxel_type(const std::string& name, const std::string& file)
{
    const std::string n = lowercase(name);
    struct Alias {
        const char* name;
        VoxelType type;
    };
    static const Alias aliases[] = {
        {"uint8", VoxelType::u8},         {"uchar", VoxelType::u8},     {"unsigned_char", VoxelType::u8},
        {"unsigned char", VoxelType::u8}, {"int8", VoxelType::i8},      {"char", VoxelType::i8},
        {"signed char", VoxelType::i8},   {"uint16", VoxelType::u16},   {"ushort", VoxelType::u16},
        {"unsigned_short", VoxelType::u16}, {"unsigned short", VoxelType::u16}, {"int16", VoxelType::i16},
        {"short", VoxelType::i16},        {"uint32", VoxelType::u32},   {"uint", VoxelType::u32},
        {"unsigned_int", VoxelType::u32}, {"unsigned int", VoxelType::u32}, {"int32", VoxelType::i32},
        {"int", VoxelType::i32},          {"float32", VoxelType::f32},  {"float", VoxelType::f32},
        {"float64", VoxelType::f64},      {"double", VoxelType::f64},
    };
    for (const Alias& a : aliases)
        if (n == a.name) return a.type;
    throw InputError(file, "unknown voxel type '" + name + "' (expected uint8, int8, uint16, int16, uint32, int32, "
                           "float32 or float64)");
}

const char* voxel_type_name(VoxelType t)
{
    switch (t) {
    case VoxelType::u8: return "uint8";
    case VoxelType::i8: return "int8";
    case VoxelType::u16: return "uint16";
    case VoxelType::i16: return "int16";
    case VoxelType::u32: return "uint32";
    case VoxelType::i32: return "int32";
    case VoxelType::f32: return "float32";
    case VoxelType::f64: return "float64";
    }
    return "?";
}

std::size_t voxel_type_size(VoxelType t)
{
    switch (t) {
    case VoxelType::u8:
    case VoxelType::i8: return 1;
    case VoxelType::u16:
    case VoxelType::i16: return 2;
    case VoxelType::u32:
    case VoxelType::i32:
    case VoxelType::f32: return 4;
    case VoxelType::f64: return 8;
    }
    return 1;
}

namespace {

template <class T>
void decode_as(std::string_view bytes, bool big_endian, float* out)
{
    const std::size_t n = bytes.size() / sizeof(T);
    for (std::size_t i = 0; i < n; ++i) {
        T v;
        std::memcpy(&v, bytes.data() + i * sizeof(T), sizeof(T));
        out[i] = static_cast<float>(big_endian ? byteswap_value(v) : v);
    }
}

}  // namespace

void decode_voxels(std::string_view bytes, VoxelType type, bool big_endian, float* out)
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

void finalize_volume(Volume& v)
{
    const std::string& file = v.source;
    for (int a = 0; a < 3; ++a)
        if (v.dims[a] < 1)
            throw InputError(file, "volume dimension " + std::to_string(a) + " is " + std::to_string(v.dims[a]) +
                                       " (must be at least 1)");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(v.spacing[a]) || !(v.spacing[a] > 0.0))
            throw InputError(file, "volume spacing " + std::to_string(a) + " is " + std::to_string(v.spacing[a]) +
                                       " (must be finite and positive)");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(v.origin[a])) throw InputError(file, "volume origin is not finite");
    const uint64_t n = uint64_t(v.dims[0]) * uint64_t(v.dims[1]) * uint64_t(v.dims[2]);
    if (v.values.size() != n)
        throw InputError(file, "volume holds " + std::to_string(v.values.size()) + " values for " +
                                   std::to_string(v.dims[0]) + "x" + std::to_string(v.dims[1]) + "x" +
                                   std::to_string(v.dims[2]) + " = " + std::to_string(n) + " samples");
    for (std::size_t i = 0; i < v.values.size(); ++i)
        if (!std::isfinite(v.values[i]))
            throw InputError(file, "volume value " + std::to_string(i) + " is not finite");
}

Bounds volume_bounds(const Volume& v)
{
    Bounds b;
    b.lo = v.origin;
    b.hi = v.origin + glm::dvec3(double(v.dims[0] - 1), double(v.dims[1] - 1), double(v.dims[2] - 1)) * v.spacing;
    return b;
}

Range volume_range(const Volume& v)
{
    Range r;
    if (v.values.empty()) return r;
    auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
    r.lo = *lo;
    r.hi = *hi;
    return r;
}

}  // namespace uvr
