// Writing tetrahedral meshes in VTK's XML formats: one piece (.vtu) and the parallel file that names pieces (.pvtu),
// as ParaView and VTK's parallel readers read them (docs/formats.md, docs/distributed.md).
#pragma once

#include <string>
#include <vector>

#include "reference/dataset.h"
#include "reference/mesh.h"

namespace uvr {

// An UnstructuredGrid of one Piece: points and every field as Float64 (the doubles uvr holds, bit for bit),
// tetrahedra as VTK_TETRA (10) with Int64 connectivity and offsets, point fields as PointData and cell fields as
// CellData; the arrays appended as raw little-endian bytes with UInt64 headers. Flat tetrahedra kept from collapsed
// grid cells are left out, as write_vtk_legacy leaves them out: they cover no volume and unstructured readers refuse
// them. Written atomically; throws InputError naming `path`.
void write_vtu(const std::string& path, const TetMesh& mesh);

// A PUnstructuredGrid naming `pieces` (paths relative to the .pvtu's directory) that hold meshes with the fields of
// `like`; with `whole`, the whole mesh's extent as FieldData (ASCII doubles of 17 digits, read back bit for bit;
// readers that do not know the arrays skip them). Written atomically; throws InputError naming `path`.
void write_pvtu(const std::string& path, const TetMesh& like, const std::vector<std::string>& pieces,
                const WholeExtent* whole = nullptr);

}  // namespace uvr
