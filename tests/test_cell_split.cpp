// Splitting hexahedra, voxels, wedges and pyramids into conforming tetrahedra (reference/cells.cpp).
#include <algorithm>
#include <numeric>
#include <random>

#include "reference/cells.h"
#include "reference/topology.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::require_input_error;

namespace {

// Sums of up to a few hundred thousand signed volumes, each with a relative rounding error of a few ulps: 1e-9
// relative leaves three orders of magnitude of margin over the accumulated rounding.
constexpr double kVolumeRelTolerance = 1e-9;

// A gently perturbed n0 x n1 x n2 lattice of points (so no face is exactly planar by accident of the test).
std::vector<glm::dvec3> lattice(int n0, int n1, int n2, std::mt19937& rng)
{
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);
    std::vector<glm::dvec3> p;
    for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j)
            for (int i = 0; i < n0; ++i) p.push_back({i + jitter(rng), j + jitter(rng), k + jitter(rng)});
    return p;
}

std::size_t surface_quads(int c0, int c1, int c2) { return 2u * std::size_t(c0 * c1 + c1 * c2 + c0 * c2); }

void check_conforming(const TetMesh& mesh, std::size_t expected_boundary_faces)
{
    const MeshTopology topo = build_topology(mesh);  // throws if a face had more than two tetrahedra
    INFO("boundary faces " << topo.boundary_faces << ", internal " << topo.internal_faces);
    // Non-conforming diagonals would leave extra boundary triangles inside the mesh.
    CHECK(topo.boundary_faces == expected_boundary_faces);
    CHECK(boundary_open_edges(topo) == 0);
    const double v = total_tet_volume(mesh), enclosed = boundary_enclosed_volume(mesh, topo);
    CHECK(std::fabs(v - enclosed) <= kVolumeRelTolerance * v);
}

}  // namespace

TEST_CASE("structured grids split into five tetrahedra per cell with alternating parity conform")
{
    std::mt19937 rng(7);
    StructuredGrid g;
    g.source = "grid.xyz";
    g.dims = {5, 4, 3};
    g.points = lattice(5, 4, 3, rng);
    const TetMesh mesh = tetrahedralize_structured(g);
    CHECK(mesh.tets.size() == 4u * 3u * 2u * 5u);
    check_conforming(mesh, 2 * surface_quads(4, 3, 2));

    SECTION("a point with iblank 0 drops the cells that touch it")
    {
        g.iblank.assign(g.points.size(), 1);
        g.iblank[1 + 5 * (1 + 4 * 1)] = 0;  // interior point (1, 1, 1): touches 8 cells
        CHECK(tetrahedralize_structured(g).tets.size() == (4u * 3u * 2u - 8u) * 5u);
        g.iblank[0] = -1;  // negative iblank (overset boundary) keeps its cells
        CHECK(tetrahedralize_structured(g).tets.size() == (4u * 3u * 2u - 8u) * 5u);
    }
    SECTION("dimensions without a cell are an error")
    {
        g.dims = {1, 4, 15};
        require_input_error([&] { tetrahedralize_structured(g); }, {"grid.xyz", "no cell"});
    }
}

TEST_CASE("hexahedra with any point numbering split into conforming tetrahedra")
{
    std::mt19937 rng(11);
    const int c0 = 4, c1 = 3, c2 = 3;
    UnstructuredCells cells;
    cells.source = "hexes.vtk";
    std::vector<glm::dvec3> p = lattice(c0 + 1, c1 + 1, c2 + 1, rng);
    // A random global numbering: the diagonal choice depends on the indices, so this exercises all rotations.
    std::vector<uint32_t> perm(p.size());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    cells.points.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) cells.points[perm[i]] = p[i];
    auto id = [&](int i, int j, int k) { return int64_t(perm[std::size_t(i + (c0 + 1) * (j + (c1 + 1) * k))]); };
    cells.offsets.push_back(0);
    for (int k = 0; k < c2; ++k)
        for (int j = 0; j < c1; ++j)
            for (int i = 0; i < c0; ++i) {
                cells.types.push_back(kVtkHexahedron);
                for (int64_t v : {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                                  id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)})
                    cells.connectivity.push_back(v);
                cells.offsets.push_back(int64_t(cells.connectivity.size()));
            }
    std::vector<std::string> warnings;
    const TetMesh mesh = tetrahedralize_cells(cells, warnings);
    CHECK(mesh.tets.size() == std::size_t(c0 * c1 * c2) * 6u);
    check_conforming(mesh, 2 * surface_quads(c0, c1, c2));
}

TEST_CASE("a cube split into six pyramids around its centre conforms with neighbouring hexahedra")
{
    // Two unit cubes side by side: the left one a hexahedron, the right one six pyramids with apex at its centre.
    UnstructuredCells cells;
    cells.source = "mixed.vtk";
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) cells.points.push_back({double(i), double(j), double(k)});
    auto id = [](int i, int j, int k) { return int64_t(i + 3 * (j + 2 * k)); };
    cells.points.push_back({1.5, 0.5, 0.5});
    const int64_t apex = 12;
    cells.offsets.push_back(0);
    auto add = [&](int type, std::initializer_list<int64_t> v) {
        cells.types.push_back(type);
        cells.connectivity.insert(cells.connectivity.end(), v);
        cells.offsets.push_back(int64_t(cells.connectivity.size()));
    };
    add(kVtkHexahedron, {id(0, 0, 0), id(1, 0, 0), id(1, 1, 0), id(0, 1, 0), id(0, 0, 1), id(1, 0, 1), id(1, 1, 1),
                         id(0, 1, 1)});
    // The six faces of the right cube as pyramid bases (any orientation: finalize_mesh orients the tetrahedra).
    add(kVtkPyramid, {id(1, 0, 0), id(1, 1, 0), id(1, 1, 1), id(1, 0, 1), apex});
    add(kVtkPyramid, {id(2, 0, 0), id(2, 1, 0), id(2, 1, 1), id(2, 0, 1), apex});
    add(kVtkPyramid, {id(1, 0, 0), id(2, 0, 0), id(2, 0, 1), id(1, 0, 1), apex});
    add(kVtkPyramid, {id(1, 1, 0), id(2, 1, 0), id(2, 1, 1), id(1, 1, 1), apex});
    add(kVtkPyramid, {id(1, 0, 0), id(2, 0, 0), id(2, 1, 0), id(1, 1, 0), apex});
    add(kVtkPyramid, {id(1, 0, 1), id(2, 0, 1), id(2, 1, 1), id(1, 1, 1), apex});
    std::vector<std::string> warnings;
    const TetMesh mesh = tetrahedralize_cells(cells, warnings);
    CHECK(mesh.tets.size() == 6u + 6u * 2u);
    check_conforming(mesh, 2 * surface_quads(2, 1, 1));
    CHECK(total_tet_volume(mesh) == Approx(2.0).epsilon(1e-12));
}

TEST_CASE("voxels and wedges split into tetrahedra that fill the cell")
{
    SECTION("voxel: corners in (x, y, z) bit order")
    {
        UnstructuredCells cells;
        cells.source = "voxel.vtu";
        for (int v = 0; v < 8; ++v) cells.points.push_back({double(v & 1), double(v >> 1 & 1), double(v >> 2 & 1)});
        cells.types = {kVtkVoxel};
        cells.offsets = {0, 8};
        cells.connectivity = {0, 1, 2, 3, 4, 5, 6, 7};
        std::vector<std::string> w;
        const TetMesh mesh = tetrahedralize_cells(cells, w);
        CHECK(mesh.tets.size() == 6);
        CHECK(total_tet_volume(mesh) == Approx(1.0).epsilon(1e-12));
        check_conforming(mesh, 12);
    }
    SECTION("wedge")
    {
        UnstructuredCells cells;
        cells.source = "wedge.vtu";
        cells.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
        cells.types = {kVtkWedge};
        cells.offsets = {0, 6};
        cells.connectivity = {3, 4, 5, 0, 1, 2};
        std::vector<std::string> w;
        const TetMesh mesh = tetrahedralize_cells(cells, w);
        CHECK(mesh.tets.size() == 3);
        CHECK(total_tet_volume(mesh) == Approx(1.0).epsilon(1e-12));
        check_conforming(mesh, 2 + 3 * 2);
    }
}

TEST_CASE("lower-dimensional cells are skipped with a warning, and bad cells are named")
{
    UnstructuredCells cells;
    cells.source = "cells.vtk";
    cells.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    cells.types = {kVtkTriangle, kVtkTetra, kVtkLine};
    cells.offsets = {0, 3, 7, 9};
    cells.connectivity = {0, 1, 2, 0, 1, 2, 3, 0, 1};
    std::vector<std::string> warnings;
    CHECK(tetrahedralize_cells(cells, warnings).tets.size() == 1);
    REQUIRE(warnings.size() == 2);
    CHECK_THAT(warnings[0], Catch::Contains("line"));
    CHECK_THAT(warnings[1], Catch::Contains("triangle"));

    SECTION("surface only")
    {
        cells.types = {kVtkTriangle, kVtkTriangle};
        cells.offsets = {0, 3, 6};
        cells.connectivity = {0, 1, 2, 0, 2, 3};
        require_input_error([&] { tetrahedralize_cells(cells, warnings); }, {"cells.vtk", "no 3D cell"});
    }
    SECTION("unknown cell type")
    {
        cells.types[1] = 99;
        require_input_error([&] { tetrahedralize_cells(cells, warnings); }, {"cells.vtk", "cell 1", "unknown cell type 99"});
    }
    SECTION("unsupported 3D cell type")
    {
        cells.types[1] = 24;  // quadratic tetrahedron
        require_input_error([&] { tetrahedralize_cells(cells, warnings); }, {"cells.vtk", "cell 1", "does not support"});
    }
    SECTION("wrong number of points")
    {
        cells.types[1] = kVtkHexahedron;
        require_input_error([&] { tetrahedralize_cells(cells, warnings); }, {"cells.vtk", "cell 1", "expected 8"});
    }
    SECTION("negative and out-of-range indices")
    {
        cells.connectivity[4] = -1;
        require_input_error([&] { tetrahedralize_cells(cells, warnings); }, {"cells.vtk", "cell 1", "point -1"});
        cells.connectivity[4] = 4;
        require_input_error([&] { tetrahedralize_cells(cells, warnings); }, {"cells.vtk", "cell 1", "point 4"});
    }
}
