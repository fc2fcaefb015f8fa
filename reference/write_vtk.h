// Writing a tetrahedral mesh or a regular grid as a VTK legacy file, so peers (VTK's mappers, ParaView) render exactly
// uvr's tetrahedra, or its samples, with exactly its field.
#pragma once

#include <string>

#include "reference/mesh.h"
#include "reference/volume.h"

namespace uvr {

// BINARY (big-endian) UNSTRUCTURED_GRID: double points (as the mesh holds them: repeated points stay repeated, so
// per-cell vertex data survives), tetrahedra (VTK type 10), and the field `field` as POINT_DATA SCALARS (double), or
// CELL_DATA for a cell field. Flat tetrahedra kept from collapsed grid cells are left out: they cover no volume, and every
// unstructured reader (uvr's included) rightly rejects them. Written atomically; throws InputError naming `path`.
void write_vtk_legacy(const std::string& path, const TetMesh& mesh, std::size_t field);

// BINARY (big-endian) STRUCTURED_POINTS: the volume's dims, origin and spacing (written with 17 significant digits:
// they read back as the same doubles), its samples as POINT_DATA SCALARS float (the values uvr holds, whatever the
// file's own type was). Written atomically; throws InputError naming `path`.
void write_vtk_legacy(const std::string& path, const Volume& volume);

}  // namespace uvr
