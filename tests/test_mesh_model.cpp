// The data model's invariants: what finalize_mesh accepts, repairs and rejects.
#include "reference/mesh.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::require_input_error;

namespace {

TetMesh unit_tet()
{
    TetMesh m;
    m.source = "unit.vtk";
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.tets = {{0, 1, 2, 3}};
    m.fields = {{"s", {0.0, 1.0, 2.0, 3.0}}};
    return m;
}

}  // namespace

TEST_CASE("finalize_mesh re-orients an inverted tetrahedron and keeps a positive one")
{
    TetMesh m = unit_tet();
    m.tets.push_back({0, 2, 1, 3});  // the same cell, inverted
    m.points.push_back({5, 5, 5});   // unused points are allowed
    m.fields[0].values.push_back(4.0);
    const std::size_t flipped = finalize_mesh(m);
    CHECK(flipped == 1);
    for (const Tet& t : m.tets) {
        INFO("tet " << t[0] << " " << t[1] << " " << t[2] << " " << t[3]);
        CHECK(signed_volume6(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) > 0.0);
    }
}

TEST_CASE("finalize_mesh rejects broken cells with the file and the cell named")
{
    SECTION("index out of range")
    {
        TetMesh m = unit_tet();
        m.tets[0][3] = 7;
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "tetrahedron 0", "point 7"});
    }
    SECTION("repeated vertex")
    {
        TetMesh m = unit_tet();
        m.tets[0][3] = 1;
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "tetrahedron 0", "repeats point 1"});
    }
    SECTION("zero volume (four coplanar points)")
    {
        TetMesh m = unit_tet();
        m.points[3] = {0.5, 0.5, 0.0};
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "tetrahedron 0", "zero volume"});
    }
    SECTION("NaN coordinate")
    {
        TetMesh m = unit_tet();
        m.points[2].y = std::nan("");
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "point 2", "non-finite"});
    }
    SECTION("infinite scalar")
    {
        TetMesh m = unit_tet();
        m.fields[0].values[1] = INFINITY;
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "field 's'", "point 1"});
    }
    SECTION("field of the wrong length")
    {
        TetMesh m = unit_tet();
        m.fields[0].values.pop_back();
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "3 values for 4 points"});
    }
    SECTION("no tetrahedron")
    {
        TetMesh m = unit_tet();
        m.tets.clear();
        require_input_error([&] { finalize_mesh(m); }, {"unit.vtk", "no tetrahedron"});
    }
}

TEST_CASE("a sliver far above rounding level is a real cell, not a degenerate one")
{
    TetMesh m = unit_tet();
    // Relative volume 1e-12 of the longest edge cubed: two orders of magnitude above kDegenerateRelativeVolume.
    m.points[3] = {0.2, 0.2, 1e-12};
    CHECK_NOTHROW(finalize_mesh(m));
}

TEST_CASE("find_field picks by name, by index, and lists the fields when neither matches")
{
    TetMesh m = unit_tet();
    m.fields.push_back({"t", {1, 1, 1, 1}});
    CHECK(find_field(m, "") == 0);
    CHECK(find_field(m, "t") == 1);
    CHECK(find_field(m, "1") == 1);
    require_input_error([&] { find_field(m, "pressure"); }, {"unit.vtk", "no field 'pressure'", "0 's'", "1 't'"});
    m.fields.clear();
    require_input_error([&] { find_field(m, ""); }, {"unit.vtk", "no scalar field"});
}

TEST_CASE("a mesh holds fewer than 2^29 tetrahedra: 2^29 - 1 passes the count check, 2^29 is refused")
{
    CHECK_NOTHROW(check_tetrahedron_count("big.ele", (std::size_t(1) << 29) - 1));
    require_input_error([] { check_tetrahedron_count("big.ele", std::size_t(1) << 29); },
                        {"big.ele", "536870912 tetrahedra", "fewer than 2^29"});
}
