#include "gpu/pipeline/drawn_mesh.h"

#include "reference/field.h"

namespace uvr::gpu {

DrawnMesh::DrawnMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field)
    : mesh_(&mesh), topo_(&topo), field_(field)
{
    if (mesh.fields.at(field).association != FieldAssociation::cell) return;
    own_mesh_ = std::make_unique<TetMesh>(per_cell_vertex_mesh(mesh, field));
    own_topo_ = std::make_unique<MeshTopology>(build_topology(*own_mesh_));
    mesh_ = own_mesh_.get();
    topo_ = own_topo_.get();
    field_ = 0;
}

}  // namespace uvr::gpu
