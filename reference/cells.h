// Mixed unstructured cells as files store them (VTK's cell types), and their conversion to tetrahedra.
//
// Readers of unstructured formats (VTK legacy, VTK XML .vtu) fill an UnstructuredCells with VTK's cell type numbers and
// connectivity, then call tetrahedralize_cells(), which is the one place where hexahedra, voxels, wedges and pyramids
// are split into tetrahedra that conform across shared faces, and where 2D/1D cells are dropped with a warning.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "reference/mesh.h"

namespace uvr {

// VTK's linear cell type numbers (vtkCellType.h).
enum VtkCellType : int {
    kVtkVertex = 1, kVtkPolyVertex = 2, kVtkLine = 3, kVtkPolyLine = 4, kVtkTriangle = 5, kVtkTriangleStrip = 6,
    kVtkPolygon = 7, kVtkPixel = 8, kVtkQuad = 9, kVtkTetra = 10, kVtkVoxel = 11, kVtkHexahedron = 12,
    kVtkWedge = 13, kVtkPyramid = 14,
};

struct UnstructuredCells {
    std::string source;                 // file name, for messages
    std::vector<glm::dvec3> points;
    std::vector<int32_t> types;         // one VTK cell type per cell
    std::vector<int64_t> offsets;       // cells + 1 entries: cell c uses connectivity[offsets[c] .. offsets[c+1])
    std::vector<int64_t> connectivity;  // point indices, as read (checked here, so readers need not)
    std::vector<ScalarField> point_fields;
    std::vector<ScalarField> cell_fields;  // one value per cell, as read; each cell's tetrahedra take its value
};

// Converts to a finalized TetMesh (finalize_mesh is applied). Hexahedra, voxels, wedges and pyramids are split by
// coning from their smallest-index vertex over the faces that do not contain it, each quadrilateral face split along
// the diagonal through its smallest-index vertex (indices of canonical points: a point the file repeats counts once).
// Two cells sharing a quadrilateral therefore split it the same way,
// whatever the cell types, which makes the result conforming (docs/data-model.md). 0D/1D/2D cells are skipped and one
// warning per type is appended to `warnings`. Throws InputError naming the file and the cell for an unknown or
// unsupported cell type, a wrong vertex count, an out-of-range index, and for a file with no 3D cell.
TetMesh tetrahedralize_cells(const UnstructuredCells& cells, std::vector<std::string>& warnings);

}  // namespace uvr

namespace uvr {

// A curvilinear (structured) grid of ni x nj x nk points, point (i, j, k) at index i + ni * (j + nj * k).
struct StructuredGrid {
    std::string source;
    std::array<int64_t, 3> dims{0, 0, 0};
    std::vector<glm::dvec3> points;
    std::vector<int32_t> iblank;        // empty, or one per point; a cell touching a point with iblank 0 is dropped
    std::vector<ScalarField> point_fields;
};

// Splits every hexahedral cell into 5 tetrahedra, the two mirror-image 5-splits alternating with the parity of
// i + j + k so that the diagonals of shared faces agree (the classic construction that gives Blunt Fin's 187,395
// tetrahedra). Applies finalize_mesh, keeping the zero-volume tetrahedra of collapsed cells (DegenerateCells::keep).
// Throws InputError for dims < 2 or a point count that does not match.
TetMesh tetrahedralize_structured(const StructuredGrid& grid);

// The grid's cells as its writer meant them, trilinear hexahedra: how many are not blanked, how many are collapsed (two
// corners at one position: an O-grid's axis, a wedge written as a hexahedron) and how many fold (the map's Jacobian
// determinant is positive at some and negative at others of the 27 points whose parameters are 0, 1/2 or 1).
struct HexahedronCensus {
    std::size_t hexahedra = 0, collapsed = 0, folded = 0;
};
HexahedronCensus hexahedron_census(const StructuredGrid& grid);

}  // namespace uvr
