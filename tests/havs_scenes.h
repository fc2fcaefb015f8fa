// The scenes the HAVS tests render (emulated and on GL): a mesh with its topology, field and default transfer function.
#pragma once

#include <string>

#include <glm/geometric.hpp>

#include "reference/builtin_mesh.h"
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

// A PLOT3D data set of ../shared/data with the named field ("" for the first).
inline Scene plot3d(const char* xyz, const char* q, const std::string& field)
{
    LoadOptions o;
    o.q_file = data_path(q);
    TetMesh m = *load_dataset(data_path(xyz), o).mesh;
    const std::size_t f = find_field(m, field);
    return make_scene(std::move(m), f);
}

inline Scene blunt_fin() { return plot3d("vtk-data/bluntfinxyz.bin", "vtk-data/bluntfinq.bin", ""); }
// The Oxygen Post's first field (Density) is constant; StagnationEnergy varies.
inline Scene oxygen_post() { return plot3d("vtk-data/postxyz.bin", "vtk-data/postq.bin", "StagnationEnergy"); }

}  // namespace uvr::test
