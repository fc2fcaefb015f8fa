// Writing a tetrahedral mesh as a VTK legacy file, so peers (VTK's mappers, ParaView) render exactly uvr's
// tetrahedra with exactly its field.
#pragma once

#include <string>

#include "reference/mesh.h"

namespace uvr {

// BINARY (big-endian) UNSTRUCTURED_GRID: double points, tetrahedra (VTK type 10), and the field `field` as POINT_DATA
// SCALARS (double). Flat tetrahedra kept from collapsed grid cells are left out: they cover no volume, and every
// unstructured reader (uvr's included) rightly rejects them. Written atomically; throws InputError naming `path`.
void write_vtk_legacy(const std::string& path, const TetMesh& mesh, std::size_t field);

}  // namespace uvr
