// Faces and adjacency (reference/topology.cpp), checked on synthetic meshes and on the real data sets.
#include <map>

#include "reference/builtin_mesh.h"
#include "reference/cells.h"
#include "reference/dataset.h"
#include "reference/topology.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::data_path;
using uvr::test::require_input_error;

namespace {

// See test_cell_split.cpp: sums of many signed volumes agree to far better than 1e-9 relative.
constexpr double kVolumeRelTolerance = 1e-9;

// Every invariant the renderers rely on.
void check_invariants(const TetMesh& mesh)
{
    const MeshTopology topo = build_topology(mesh);
    INFO(mesh.source << ": " << mesh.tets.size() << " tets, " << topo.faces.size() << " faces");
    REQUIRE(topo.boundary_faces + topo.internal_faces == topo.faces.size());
    // 4 face slots per real tet: internal faces fill two, boundary faces one. Flat tets have none.
    CHECK(topo.flat_tets == count_degenerate(mesh));
    CHECK(2 * topo.internal_faces + topo.boundary_faces == 4 * (mesh.tets.size() - topo.flat_tets));
    std::size_t bad_slots = 0, bad_neighbors = 0, bad_orientation = 0;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        if (is_degenerate(mesh, mesh.tets[t])) {
            for (int i = 0; i < 4; ++i)
                if (topo.tet_faces[t][i] != -1 || topo.neighbor[t][i] != -1) ++bad_slots;
            continue;
        }
        for (int i = 0; i < 4; ++i) {
            const int32_t fi = topo.tet_faces[t][i];
            const Face& f = topo.faces[std::size_t(fi)];
            if (f.tet[0] != int32_t(t) && f.tet[1] != int32_t(t)) ++bad_slots;
            const int32_t nb = topo.neighbor[t][i];
            const int32_t expected = f.tet[0] == int32_t(t) ? f.tet[1] : f.tet[0];
            if (nb != expected) ++bad_neighbors;
            if (nb >= 0) {
                // The neighbour points back through the same face.
                const auto& back = topo.neighbor[std::size_t(nb)];
                if (std::find(back.begin(), back.end(), int32_t(t)) == back.end()) ++bad_neighbors;
            }
        }
    }
    for (const Face& f : topo.faces) {
        if (!f.boundary()) continue;
        // Outward: the owning tet's opposite vertex lies behind the face.
        const Tet& t = mesh.tets[std::size_t(f.tet[0])];
        for (uint32_t v : t)
            if (v != f.v[0] && v != f.v[1] && v != f.v[2] &&
                signed_volume6(mesh.points[f.v[0]], mesh.points[f.v[1]], mesh.points[f.v[2]], mesh.points[v]) >= 0.0)
                ++bad_orientation;
    }
    // Faces are numbered in the order of their sorted canonical points, and a shared face names the lower-numbered
    // tetrahedron first (MeshTopology::faces): the same numbers on every run and thread count.
    std::size_t out_of_order = 0;
    std::array<uint32_t, 3> previous{};
    for (std::size_t i = 0; i < topo.faces.size(); ++i) {
        const Face& f = topo.faces[i];
        std::array<uint32_t, 3> key = {topo.canonical[f.v[0]], topo.canonical[f.v[1]], topo.canonical[f.v[2]]};
        std::sort(key.begin(), key.end());
        if ((i > 0 && !(previous < key)) || (!f.boundary() && f.tet[0] >= f.tet[1])) ++out_of_order;
        previous = key;
    }
    CHECK(out_of_order == 0);
    CHECK(bad_slots == 0);
    CHECK(bad_neighbors == 0);
    CHECK(bad_orientation == 0);
    CHECK(boundary_open_edges(topo) == 0);
    // Where the boundary is not two-manifold, it is only along a seam of welded (coincident) points.
    std::vector<bool> welded(mesh.points.size(), false);
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
        if (topo.canonical[i] != i) welded[i] = welded[topo.canonical[i]] = true;
    std::map<std::pair<uint32_t, uint32_t>, int> edge_faces;
    for (const Face& f : topo.faces)
        if (f.boundary())
            for (int i = 0; i < 3; ++i) {
                const uint32_t a = topo.canonical[f.v[i]], b = topo.canonical[f.v[(i + 1) % 3]];
                ++edge_faces[{std::min(a, b), std::max(a, b)}];
            }
    std::size_t off_seam = 0;
    for (const auto& [e, n] : edge_faces)
        if (n != 2 && !(welded[e.first] && welded[e.second])) ++off_seam;
    CHECK(off_seam == 0);
    const double v = total_tet_volume(mesh), enclosed = boundary_enclosed_volume(mesh, topo);
    INFO("tet volume " << v << ", enclosed by the boundary " << enclosed);
    CHECK(std::fabs(v - enclosed) <= kVolumeRelTolerance * v);
}

TetMesh load_mesh(const std::string& rel, const std::string& q = "")
{
    LoadOptions o;
    if (!q.empty()) o.q_file = data_path(q);
    return *load_dataset(data_path(rel), o).mesh;
}

}  // namespace

TEST_CASE("a single tetrahedron has four outward boundary faces")
{
    TetMesh m;
    m.source = "one";
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.tets = {{0, 1, 2, 3}};
    finalize_mesh(m);
    const MeshTopology topo = build_topology(m);
    CHECK(topo.faces.size() == 4);
    CHECK(topo.boundary_faces == 4);
    CHECK(boundary_is_convex(m, topo));
    check_invariants(m);
}

TEST_CASE("a face shared by three tetrahedra is an error naming the face")
{
    TetMesh m;
    m.source = "fan.vtk";
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {0.1, 0.1, 2}};
    m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
    finalize_mesh(m);
    require_input_error([&] { build_topology(m); }, {"fan.vtk", "shared by 3 tetrahedra"});
}

TEST_CASE("convexity: a box is convex, the torus and two disjoint blocks are not")
{
    StructuredGrid g;
    g.source = "box";
    g.dims = {3, 3, 3};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) g.points.push_back({double(i), double(j), double(k)});
    const TetMesh box = tetrahedralize_structured(g);
    CHECK(boundary_is_convex(box, build_topology(box)));

    TetMesh two = box;
    for (auto p : box.points) two.points.push_back(p + glm::dvec3(5.0, 0.0, 0.0));
    for (auto t : box.tets) {
        for (auto& v : t) v += uint32_t(box.points.size());
        two.tets.push_back(t);
    }
    CHECK_FALSE(boundary_is_convex(two, build_topology(two)));

    const TetMesh torus = load_builtin("builtin:torus-small");
    CHECK_FALSE(boundary_is_convex(torus, build_topology(torus)));
}

TEST_CASE("face and adjacency invariants hold on the built-in torus")
{
    check_invariants(load_builtin("builtin:torus-small"));
}

TEST_CASE("face and adjacency invariants hold on the real data sets")
{
    SECTION("post.vtk: the O-grid's periodic seam is closed but not conforming")
    {
        const TetMesh m = load_mesh("vtk-data/post.vtk");
        check_invariants(m);
        CHECK(boundary_nonmanifold_edges(build_topology(m)) > 0);
    }
    SECTION("tetraMesh.vtk") { check_invariants(load_mesh("vtk-data/tetraMesh.vtk")); }
    SECTION("a_grid.vtk") { check_invariants(load_mesh("vtk-data/a_grid.vtk")); }
    SECTION("Tetrahedron.vtu") { check_invariants(load_mesh("vtk-data/Tetrahedron.vtu")); }
    SECTION("Blunt Fin")
    {
        const TetMesh m = load_mesh("vtk-data/bluntfinxyz.bin", "vtk-data/bluntfinq.bin");
        check_invariants(m);
        // The 39 hexahedra along the collapsed grid line (points (i,0,0) == (i,1,0)) leave flat tetrahedra, which
        // the face graph leaves out while the real tetrahedra on either side meet through the coincident points.
        CHECK(m.tets.size() == 187395);
        CHECK(count_degenerate(m) == 77);
    }
    SECTION("Oxygen Post: the same seam, 38 x 38 welded points")
    {
        const TetMesh m = load_mesh("vtk-data/postxyz.bin", "vtk-data/postq.bin");
        check_invariants(m);
        const MeshTopology topo = build_topology(m);
        std::size_t welded = 0;
        for (std::size_t i = 0; i < m.points.size(); ++i) welded += topo.canonical[i] != i;
        CHECK(welded == 38u * 38u);
    }
    SECTION("hexa.vtk: hexahedra become conforming tetrahedra")
    {
        const TetMesh m = load_mesh("vtk-data/hexa.vtk");
        check_invariants(m);
        // 10648 = 22^3 hexahedra: a conforming split leaves exactly the 6 * 22 * 22 outer quads, two triangles each.
        CHECK(build_topology(m).boundary_faces == 6u * 22u * 22u * 2u);
    }
}
