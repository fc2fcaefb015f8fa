// Meshes carrying the fields of reference/field.h, shared by the tests of the reference, HAVS and VICP on them: a seam
// where per-cell vertex data jumps, a box of cell data, and a real mesh whose points are repeated per cell with a
// field that jumps across a surface through it.
#pragma once

#include <string>
#include <vector>

#include "mesh_scenes.h"
#include "reference/cells.h"
#include "reference/field.h"

namespace uvr::test {

// The VTK hexahedron's corners of the unit cube at `o`.
// Its points are written from corner `first` on (corner k at index base + (k - first) mod 8), so that two cubes can
// number a shared face's points in different orders.
inline void add_cube(UnstructuredCells& c, glm::dvec3 o, int first = 0)
{
    const int64_t base = int64_t(c.points.size());
    const glm::dvec3 corner[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int i = 0; i < 8; ++i) c.points.push_back(o + corner[(i + first) % 8]);
    c.types.push_back(kVtkHexahedron);
    for (int k = 0; k < 8; ++k) c.connectivity.push_back(base + (k - first + 8) % 8);
    c.offsets.push_back(int64_t(c.connectivity.size()));
}

// Two unit cubes side by side along x, each written with its own eight points (the shared face's points twice, the
// right cube's numbered from its corner (1, 1, 0), so that by raw index the two would cut the shared square along
// different diagonals), the left cube's scalar 0.2 + 0.5 y, the right cube's 0.9 - 0.5 z: per-cell vertex data that
// jumps across the seam x = 1.
inline double left_field(const glm::dvec3& p) { return 0.2 + 0.5 * p.y; }
inline double right_field(const glm::dvec3& p) { return 0.9 - 0.5 * p.z; }
inline TetMesh two_cube_seam()
{
    UnstructuredCells c;
    c.source = "two-cube seam";
    c.offsets.push_back(0);
    add_cube(c, {0, 0, 0});
    add_cube(c, {1, 0, 0}, 3);
    ScalarField f{"f", {}};
    for (std::size_t i = 0; i < c.points.size(); ++i)
        f.values.push_back(i < 8 ? left_field(c.points[i]) : right_field(c.points[i]));
    c.point_fields.push_back(f);
    std::vector<std::string> warnings;
    return tetrahedralize_cells(c, warnings);
}

// A 3 x 3 x 3 box of unit hexahedra sharing their points, with one value per cell.
// Values in [0.05, 0.95], inside the transfer functions' nodes; face neighbours always differ.
inline double cell_value(int i, int j, int k) { return 0.25 + 0.2 * i - 0.1 * j + 0.15 * ((i + 2 * j + k) % 3); }
inline TetMesh cell_data_box()
{
    UnstructuredCells c;
    c.source = "cell-data box";
    c.offsets.push_back(0);
    for (int k = 0; k <= 3; ++k)
        for (int j = 0; j <= 3; ++j)
            for (int i = 0; i <= 3; ++i) c.points.push_back({i, j, k});
    ScalarField f{"cell", {}};
    const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                for (const auto& d : corner) c.connectivity.push_back((i + d[0]) + 4 * ((j + d[1]) + 4 * (k + d[2])));
                c.types.push_back(kVtkHexahedron);
                c.offsets.push_back(int64_t(c.connectivity.size()));
                f.values.push_back(cell_value(i, j, k));
            }
    c.cell_fields.push_back(f);
    std::vector<std::string> warnings;
    return tetrahedralize_cells(c, warnings);
}

// `s` with its points repeated per cell (reference/field.h per_cell_vertex_mesh) and its field raised by `jump` in
// the tetrahedra whose centroid lies beyond the plane x = the bounds' centre: per-cell vertex data that jumps across
// the faces of a surface through the mesh.
inline Scene with_jump(const Scene& s, double jump)
{
    TetMesh m = per_cell_vertex_mesh(s.mesh, s.field);
    const double cut = mesh_bounds(m).center().x;
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
        const Tet& v = m.tets[t];
        const double cx = 0.25 * (m.points[v[0]].x + m.points[v[1]].x + m.points[v[2]].x + m.points[v[3]].x);
        if (cx > cut)
            for (uint32_t p : v) m.fields[0].values[p] += jump;
    }
    m.source = s.mesh.source + " (points repeated per cell, a jump at x = " + std::to_string(cut) + ")";
    return make_scene(std::move(m), 0);
}

}  // namespace uvr::test
