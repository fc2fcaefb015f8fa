// Splitting cells into tetrahedra that conform across shared faces.
//
// Unstructured cells (hexahedra, voxels, wedges, pyramids) are split by the rule of Dompierre et al. ("How to
// subdivide pyramids, prisms and hexahedra into tetrahedra", 1999) in its simplest form: each quadrilateral face is cut
// along the diagonal through its smallest global point index (of the canonical point: coincident points count as one), and the cell is coned from its smallest-index vertex m
// over the faces that do not contain m. The faces that contain m are then cut along diagonals through m, which is also
// their smallest index, so every quadrilateral is cut the same way from both sides whatever the neighbouring cell's
// type. Counts: hexahedron 6, wedge 3, pyramid 2 tetrahedra.
//
// Structured (curvilinear) grids use the classic 5-tetrahedra split whose two mirror images alternate with the parity of
// i + j + k; that is what gives the reference counts of the NASA data sets (Blunt Fin: 39 * 31 * 31 * 5 = 187,395).
#include "reference/cells.h"

#include <algorithm>
#include <map>

#include <glm/geometric.hpp>

#include "reference/error.h"
#include "reference/topology.h"

namespace uvr {

namespace {

struct CellShape {
    int vertices;
    std::vector<std::vector<int>> faces;  // local vertex indices, cyclic order
};

const CellShape& hexahedron_shape()
{
    static const CellShape s{8, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
    return s;
}
const CellShape& wedge_shape()
{
    static const CellShape s{6, {{0, 1, 2}, {3, 5, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}}};
    return s;
}
const CellShape& pyramid_shape()
{
    static const CellShape s{5, {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}};
    return s;
}

// Cone from the smallest-index vertex over the faces not containing it (see the file comment). Indices are compared
// by canonical point (key[i] for vertex g[i]), so that cells whose files repeat a shared point still cut the face the
// same way.
void cone_split(const CellShape& shape, const uint32_t* g, const uint32_t* key, std::vector<Tet>& out)
{
    int m = 0;
    for (int i = 1; i < shape.vertices; ++i)
        if (key[i] < key[m]) m = i;
    for (const auto& f : shape.faces) {
        if (std::find(f.begin(), f.end(), m) != f.end()) continue;
        if (f.size() == 3) {
            out.push_back({g[m], g[f[0]], g[f[1]], g[f[2]]});
            continue;
        }
        // Quadrilateral a b c d: the diagonal goes through its smallest index.
        const uint32_t a = g[f[0]], b = g[f[1]], c = g[f[2]], d = g[f[3]];
        if (std::min(key[f[0]], key[f[2]]) < std::min(key[f[1]], key[f[3]])) {
            out.push_back({g[m], a, b, c});
            out.push_back({g[m], a, c, d});
        } else {
            out.push_back({g[m], b, c, d});
            out.push_back({g[m], b, d, a});
        }
    }
}

bool is_lower_dimensional(int type)
{
    // Linear 0D/1D/2D cells, and the higher-order 1D/2D ones (quadratic, cubic, Lagrange, Bezier curves/surfaces).
    static const int kTypes[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 21, 22, 23, 28, 30, 34, 35, 36, 68, 69, 70, 75, 76, 77};
    return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

bool is_unsupported_3d(int type)
{
    // Prisms with more sides, quadratic/higher-order 3D cells, polyhedra.
    static const int kTypes[] = {15, 16, 24, 25, 26, 27, 29, 31, 32, 33, 37, 42, 71, 72, 73, 74, 78, 79, 80, 81};
    return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

const char* type_name(int type)
{
    switch (type) {
    case kVtkVertex: return "vertex";
    case kVtkPolyVertex: return "poly-vertex";
    case kVtkLine: return "line";
    case kVtkPolyLine: return "poly-line";
    case kVtkTriangle: return "triangle";
    case kVtkTriangleStrip: return "triangle strip";
    case kVtkPolygon: return "polygon";
    case kVtkPixel: return "pixel";
    case kVtkQuad: return "quad";
    default: return "higher-order 1D/2D cell";
    }
}

// The arrays' sizes: an offset per cell and one more, a value per cell in each cell field.
void check_cell_arrays(const UnstructuredCells& cells)
{
    const std::string& file = cells.source;
    const std::size_t n = cells.types.size();
    if (cells.offsets.size() != n + 1)
        throw InputError(file, "cell offsets hold " + std::to_string(cells.offsets.size()) + " entries for " +
                                   std::to_string(n) + " cells");
    for (const ScalarField& f : cells.cell_fields)
        if (f.values.size() != n)
            throw InputError(file, "cell field '" + f.name + "' has " + std::to_string(f.values.size()) +
                                       " values for " + std::to_string(n) + " cells");
}

// The split of a 3D cell of VTK type `type` (null for a tetrahedron, which is kept as it is) and its point count.
const CellShape* cell_shape(const std::string& file, std::size_t c, int type, int& expected)
{
    const CellShape* shape = nullptr;
    switch (type) {
    case kVtkTetra: expected = 4; break;
    case kVtkVoxel:
    case kVtkHexahedron: expected = 8; shape = &hexahedron_shape(); break;
    case kVtkWedge: expected = 6; shape = &wedge_shape(); break;
    case kVtkPyramid: expected = 5; shape = &pyramid_shape(); break;
    default:
        throw InputError(file, "cell " + std::to_string(c) + " has unknown cell type " + std::to_string(type));
    }
    return shape;
}

// Cell c's points `g` (checked against the file's points) and their canonical keys, a voxel's in a hexahedron's order.
void cell_corners(const UnstructuredCells& cells, const std::vector<uint32_t>& canonical, std::size_t c, int type,
                  int64_t begin, int expected, uint32_t g[8], uint32_t key[8])
{
    const std::string& file = cells.source;
    const int64_t np = static_cast<int64_t>(cells.points.size());
    for (int k = 0; k < expected; ++k) {
        const int64_t idx = cells.connectivity[static_cast<std::size_t>(begin + k)];
        if (idx < 0 || idx >= np)
            throw InputError(file, "cell " + std::to_string(c) + " uses point " + std::to_string(idx) +
                                       ", but the file has " + std::to_string(np) + " points");
        g[k] = static_cast<uint32_t>(idx);
        key[k] = canonical[g[k]];
    }
    if (type == kVtkVoxel) {
        // A voxel orders its corners by (x, y, z) bits; the hexahedron goes around each quad.
        std::swap(g[2], g[3]);
        std::swap(g[6], g[7]);
        std::swap(key[2], key[3]);
        std::swap(key[6], key[7]);
    }
}

// The cell fields carried to the tetrahedra, each tetrahedron taking its source cell's value.
void add_cell_fields(const UnstructuredCells& cells, const std::vector<uint32_t>& source_cell, TetMesh& mesh)
{
    for (const ScalarField& f : cells.cell_fields) {
        ScalarField t{f.name, {}, FieldAssociation::cell};
        t.values.reserve(source_cell.size());
        for (uint32_t c : source_cell) t.values.push_back(f.values[c]);
        mesh.fields.push_back(std::move(t));
    }
}

// How many tetrahedra the split below makes of a cell of this type: the cone from one corner over the faces that do not
// hold it (a hexahedron's three quadrilaterals, a wedge's quadrilateral and triangle, a pyramid's two faces).
std::size_t tetrahedra_of_type(int type)
{
    switch (type) {
    case kVtkTetra: return 1;
    case kVtkVoxel:
    case kVtkHexahedron: return 6;
    case kVtkWedge: return 3;
    case kVtkPyramid: return 2;
    default: return 0;  // not rendered, or refused by the split
    }
}


// The point index of corner v of a structured grid's cell (i, j, k): bits (v & 1, v >> 1 & 1, v >> 2 & 1) along i,
// j, k.
std::size_t grid_corner(const StructuredGrid& grid, int64_t i, int64_t j, int64_t k, int v)
{
    const int64_t ni = grid.dims[0], nj = grid.dims[1];
    return std::size_t((i + (v & 1)) + ni * ((j + (v >> 1 & 1)) + nj * (k + (v >> 2 & 1))));
}

// Whether a blanked point touches the cell (i, j, k): the splits and the census leave it out.
bool cell_blanked(const StructuredGrid& grid, int64_t i, int64_t j, int64_t k)
{
    if (grid.iblank.empty()) return false;
    for (int v = 0; v < 8; ++v)
        if (grid.iblank[grid_corner(grid, i, j, k, v)] == 0) return true;
    return false;
}

// The cells of a structured grid that no blanked point touches (each is split into five tetrahedra).
std::size_t unblanked_cells(const StructuredGrid& grid)
{
    const int64_t ni = grid.dims[0], nj = grid.dims[1], nk = grid.dims[2];
    if (grid.iblank.empty()) return std::size_t(ni - 1) * std::size_t(nj - 1) * std::size_t(nk - 1);
    std::size_t n = 0;
    for (int64_t k = 0; k + 1 < nk; ++k)
        for (int64_t j = 0; j + 1 < nj; ++j)
            for (int64_t i = 0; i + 1 < ni; ++i) n += cell_blanked(grid, i, j, k) ? 0 : 1;
    return n;
}

// The Jacobian determinant of the trilinear map of corners c (bit v of a corner's index: (i, j, k) = (v & 1, v >> 1 &
// 1, v >> 2 & 1)) at parameters (u, v, w).
double trilinear_jacobian(const glm::dvec3 c[8], double u, double v, double w)
{
    const double a[2] = {1.0 - u, u}, b[2] = {1.0 - v, v}, g[2] = {1.0 - w, w};
    glm::dvec3 du(0.0), dv(0.0), dw(0.0);
    for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) {
            du += b[j] * g[k] * (c[1 | j << 1 | k << 2] - c[j << 1 | k << 2]);
            dv += a[j] * g[k] * (c[j | 2 | k << 2] - c[j | k << 2]);
            dw += a[j] * b[k] * (c[j | k << 1 | 4] - c[j | k << 1]);
        }
    return glm::dot(du, glm::cross(dv, dw));
}


}  // namespace


TetMesh tetrahedralize_cells(const UnstructuredCells& cells, std::vector<std::string>& warnings)
{
    const std::string& file = cells.source;
    const std::size_t n = cells.types.size();
    check_cell_arrays(cells);
    std::size_t tet_count = 0;
    for (int type : cells.types) tet_count += tetrahedra_of_type(type);
    check_tetrahedron_count(file, tet_count);
    TetMesh mesh;
    mesh.source = file;
    mesh.points = cells.points;
    mesh.fields = cells.point_fields;
    mesh.tets.reserve(n);
    const std::vector<uint32_t> canonical = canonical_points(cells.points);
    std::vector<uint32_t> source_cell;  // per tetrahedron, the cell it came from (cell fields only)
    std::map<int, std::size_t> skipped;  // type -> count, sorted so warnings come in a fixed order
    uint32_t g[8], key[8];
    for (std::size_t c = 0; c < n; ++c) {
        const int type = cells.types[c];
        const int64_t begin = cells.offsets[c], end = cells.offsets[c + 1];
        if (begin < 0 || end < begin || end > static_cast<int64_t>(cells.connectivity.size()))
            throw InputError(file, "cell " + std::to_string(c) + " has invalid offsets " + std::to_string(begin) +
                                       ".." + std::to_string(end));
        if (is_lower_dimensional(type)) {
            ++skipped[type];
            continue;
        }
        if (is_unsupported_3d(type))
            throw InputError(file, "cell " + std::to_string(c) + " has VTK cell type " + std::to_string(type) +
                                       ", a 3D cell uvr does not support (linear tetrahedra, hexahedra, voxels, "
                                       "wedges and pyramids only)");
        int expected = 0;
        const CellShape* shape = cell_shape(file, c, type, expected);
        if (end - begin != expected)
            throw InputError(file, "cell " + std::to_string(c) + " (type " + std::to_string(type) + ") has " +
                                       std::to_string(end - begin) + " points, expected " + std::to_string(expected));
        cell_corners(cells, canonical, c, type, begin, expected, g, key);
        if (shape)
            cone_split(*shape, g, key, mesh.tets);
        else
            mesh.tets.push_back({g[0], g[1], g[2], g[3]});
        if (!cells.cell_fields.empty()) source_cell.resize(mesh.tets.size(), uint32_t(c));
    }
    add_cell_fields(cells, source_cell, mesh);
    for (const auto& [type, count] : skipped)
        warnings.push_back(file + ": skipped " + std::to_string(count) + " " + type_name(type) +
                           " cell(s) (VTK type " + std::to_string(type) + "): only 3D cells are rendered");
    if (mesh.tets.empty()) throw InputError(file, "the file has no 3D cell (a surface-only or empty mesh)");
    const std::size_t flipped = finalize_mesh(mesh);
    if (flipped)
        warnings.push_back(file + ": re-oriented " + std::to_string(flipped) + " inverted tetrahedra");
    return mesh;
}


TetMesh tetrahedralize_structured(const StructuredGrid& grid)
{
    const std::string& file = grid.source;
    const int64_t ni = grid.dims[0], nj = grid.dims[1], nk = grid.dims[2];
    if (ni < 2 || nj < 2 || nk < 2)
        throw InputError(file, "grid dimensions " + std::to_string(ni) + "x" + std::to_string(nj) + "x" +
                                   std::to_string(nk) + " hold no cell (each must be at least 2)");
    const uint64_t np = uint64_t(ni) * uint64_t(nj) * uint64_t(nk);
    if (grid.points.size() != np)
        throw InputError(file, "grid holds " + std::to_string(grid.points.size()) + " points, expected " +
                                   std::to_string(np));
    if (!grid.iblank.empty() && grid.iblank.size() != np)
        throw InputError(file, "iblank holds " + std::to_string(grid.iblank.size()) + " values, expected " +
                                   std::to_string(np));
    if (np > UINT32_MAX) throw InputError(file, "grid has more than 2^32 points");
    check_tetrahedron_count(file, 5 * unblanked_cells(grid));
    TetMesh mesh;
    mesh.source = file;
    mesh.points = grid.points;
    mesh.fields = grid.point_fields;
    mesh.tets.reserve(std::size_t(ni - 1) * std::size_t(nj - 1) * std::size_t(nk - 1) * 5);
    // Corner v of a cell has bits (di, dj, dk) = (v & 1, v >> 1 & 1, v >> 2 & 1). The even split keeps the corner
    // tetrahedra at 000, 110, 101, 011 and the central one on the other four corners; the odd split is its mirror.
    // Both cut each face along the diagonal that joins the two corners of the central tetrahedron on that face, and the
    // parity flip makes neighbouring cells pick the same diagonal.
    static const int kEvenCorners[4] = {0, 3, 5, 6};
    static const int kOddCorners[4] = {1, 2, 4, 7};
    for (int64_t k = 0; k + 1 < nk; ++k)
        for (int64_t j = 0; j + 1 < nj; ++j)
            for (int64_t i = 0; i + 1 < ni; ++i) {
                if (cell_blanked(grid, i, j, k)) continue;
                uint32_t g[8];
                for (int v = 0; v < 8; ++v) g[v] = static_cast<uint32_t>(grid_corner(grid, i, j, k, v));
                const bool odd = ((i + j + k) & 1) != 0;
                const int* corners = odd ? kOddCorners : kEvenCorners;
                const int* central = odd ? kEvenCorners : kOddCorners;
                for (int c = 0; c < 4; ++c) {
                    const int v = corners[c];
                    mesh.tets.push_back({g[v], g[v ^ 1], g[v ^ 2], g[v ^ 4]});
                }
                mesh.tets.push_back({g[central[0]], g[central[1]], g[central[2]], g[central[3]]});
            }
    if (mesh.tets.empty()) throw InputError(file, "every cell of the grid is blanked (iblank 0)");
    finalize_mesh(mesh, DegenerateCells::keep);
    return mesh;
}


HexahedronCensus hexahedron_census(const StructuredGrid& grid)
{
    HexahedronCensus census;
    const int64_t ni = grid.dims[0], nj = grid.dims[1], nk = grid.dims[2];
    for (int64_t k = 0; k + 1 < nk; ++k)
        for (int64_t j = 0; j + 1 < nj; ++j)
            for (int64_t i = 0; i + 1 < ni; ++i) {
                if (cell_blanked(grid, i, j, k)) continue;
                glm::dvec3 c[8];
                for (int v = 0; v < 8; ++v) c[v] = grid.points[grid_corner(grid, i, j, k, v)];
                ++census.hexahedra;
                bool repeated = false;
                for (int p = 0; p < 8 && !repeated; ++p)
                    for (int q = p + 1; q < 8 && !repeated; ++q) repeated = c[p] == c[q];
                census.collapsed += repeated ? 1 : 0;
                bool positive = false, negative = false;
                for (int s = 0; s < 27; ++s) {
                    const double det = trilinear_jacobian(c, 0.5 * (s % 3), 0.5 * (s / 3 % 3), 0.5 * (s / 9));
                    positive = positive || det > 0.0;
                    negative = negative || det < 0.0;
                }
                census.folded += positive && negative ? 1 : 0;
            }
    return census;
}

}  // namespace uvr
