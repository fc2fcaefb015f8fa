// Regular grids (volumes) for the ray caster and its reference.
//
// Sample (i, j, k) sits at world position origin + (i, j, k) * spacing and is stored at index i + dims.x * (j +
// dims.y * k) (x fastest). Values are kept as float together with the type they were stored as in the file, so the GL
// backend can upload the volume texture in its original format (8-bit, 16-bit, float) and the emulation can sample it
// the same way. Every integer type up to 16 bits converts to float exactly.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "reference/mesh.h"

namespace uvr {

enum class VoxelType { u8, i8, u16, i16, u32, i32, f32, f64 };

// "uint8", "int16", "float32", ... and the C-like aliases readers meet ("unsigned_char", "short", "float", "double").
// Throws InputError (with `file`) for an unknown name.
VoxelType parse_voxel_type(const std::string& name, const std::string& file);
const char* voxel_type_name(VoxelType t);
std::size_t voxel_type_size(VoxelType t);

struct Volume {
    std::string source;
    std::string name;                  // the scalar array's name, where the file has one
    std::array<int64_t, 3> dims{0, 0, 0};
    glm::dvec3 origin{0.0};
    glm::dvec3 spacing{1.0};
    VoxelType type = VoxelType::f32;   // as stored in the file
    std::vector<float> values;         // dims[0] * dims[1] * dims[2], x fastest
};

// Converts the samples stored in `bytes` (bytes.size() / voxel_type_size(type) of them, in the file's byte order) to
// float at out[0 ...]; the caller sizes `out`. Every integer type up to 16 bits converts exactly.
void decode_voxels(std::string_view bytes, VoxelType type, bool big_endian, float* out);

// Checks dims >= 1, spacing finite and > 0, value count, finite values. Throws InputError naming volume.source.
void finalize_volume(Volume& volume);

Bounds volume_bounds(const Volume& volume);
Range volume_range(const Volume& volume);

}  // namespace uvr
