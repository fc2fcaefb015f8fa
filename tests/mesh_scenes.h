// The mesh scenes the tests of HAVS and VICP render (emulated and on GL): a mesh with its topology, field and default
// transfer function, and the views that cut a mesh.
#pragma once

#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "box_mesh.h"
#include "reference/builtin_mesh.h"
#include "reference/camera.h"
#include "reference/dataset.h"
#include "reference/topology.h"
#include "reference/transfer_function.h"
#include "test_support.h"

namespace uvr::test {

struct Scene {
    TetMesh mesh;
    std::size_t field = 0;
    MeshTopology topo;
    TransferFunction tf;
};

inline Scene make_scene(TetMesh mesh, std::size_t field)
{
    Scene s{std::move(mesh), field, {}, {}};
    s.topo = build_topology(s.mesh);
    s.tf = default_transfer_function(field_range(s.mesh.fields[field]), glm::length(mesh_bounds(s.mesh).extent()));
    return s;
}

// A PLOT3D data set of data with the named field ("" for the first).
inline Scene plot3d(const char* xyz, const char* q, const std::string& field)
{
    LoadOptions o;
    o.q_file = data_path(q);
    TetMesh m = *load_dataset(data_path(xyz), o).mesh;
    const std::size_t f = find_field(m, field);
    return make_scene(std::move(m), f);
}

// The real data sets are read once per test program (each of Catch's sections runs the test case again) and copied:
// reading the Oxygen Post with its topology takes a second, four under the sanitizers; a copy, milliseconds.
inline Scene blunt_fin()
{
    static const Scene s = plot3d("vtk-data/bluntfinxyz.bin", "vtk-data/bluntfinq.bin", "");
    return s;
}
// The Oxygen Post's first field (Density) is constant; StagnationEnergy varies.
inline Scene oxygen_post()
{
    static const Scene s = plot3d("vtk-data/postxyz.bin", "vtk-data/postq.bin", "StagnationEnergy");
    return s;
}

// A camera at `eye` looking at `target` with a wide field of view, for views from inside a mesh.
inline Camera looking(const glm::dvec3& eye, const glm::dvec3& target, double fovy = 100.0)
{
    Camera cam;
    cam.eye = eye;
    cam.target = target;
    cam.up = glm::dvec3(0.0, 1.0, 0.0) + glm::dvec3(0.0, 0.0, 0.1);
    cam.fovy_deg = fovy;
    return cam;
}

// The default camera's orbit at (az, el), orthographic, the image as tall as the mesh's bounding diagonal.
inline Camera orthographic_view(const TetMesh& mesh, double az, double el)
{
    Camera cam = default_camera(mesh_bounds(mesh), 1.0, az, el);
    cam.orthographic = true;
    cam.ortho_height = glm::length(mesh_bounds(mesh).extent());
    return cam;
}

// A view of a mesh from inside: from the centroid of its middle cell towards a point above its bounds' centre.
inline Camera inside_view(const Scene& s)
{
    const Bounds b = mesh_bounds(s.mesh);
    const Tet& t = s.mesh.tets[s.mesh.tets.size() / 2];
    const glm::dvec3 eye = 0.25 * (s.mesh.points[t[0]] + s.mesh.points[t[1]] + s.mesh.points[t[2]] + s.mesh.points[t[3]]);
    return looking(eye, b.center() + glm::dvec3(0.0, 0.0, 0.3 * b.extent().z), 70.0);
}

// A box [0, n]^3 of cells (box_mesh, inner points jittered) with the linear field of the reference's inside-camera
// test (test_reference_analytic.cpp), so that a cut first segment's scalar is checked too, and a transfer function
// that makes every ray's opacity large.
inline Scene box_scene(int n, double jitter)
{
    Scene s = make_scene(box_mesh(n, [](const glm::dvec3& p) { return (p.x + 2.0 * p.y + 3.0 * p.z) / 36.0; }, jitter, 9),
                         0);
    s.tf.color = {{0.0, {1, 0, 0}}, {1.0, {0, 0, 1}}};
    s.tf.extinction = {{0.0, 0.05}, {1.0, 0.6}};
    return s;
}

// The views from inside a box_scene or on its boundary that the clip tests of HAVS and VICP render: the cases of the
// reference's own inside-camera test (test_reference_analytic.cpp), which checks the reference against the analytic
// chord.
struct CutView {
    const char* name;
    double jitter;  // box_scene(6, jitter)
    Camera camera;
    int width, height;
};

inline std::vector<CutView> inside_box_views()
{
    Camera ortho = looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0});
    ortho.orthographic = true;
    ortho.ortho_height = 3.0;
    return {{"inside a cell", 0.25, looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0}), 64, 64},
            {"exactly on a grid vertex, rays along edges and faces", 0.0, looking({3.0, 3.0, 3.0}, {6.0, 3.0, 3.0}), 64,
             64},
            {"exactly on a boundary face, looking in", 0.0, looking({3.2, 2.9, 0.0}, {3.0, 3.0, 6.0}), 64, 64},
            {"orthographic, the image plane inside the mesh", 0.25, ortho, 64, 48}};
}

}  // namespace uvr::test
