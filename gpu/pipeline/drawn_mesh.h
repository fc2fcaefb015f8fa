// The mesh a GPU algorithm draws for a field. A point field (continuous or per-cell vertex data) is drawn on the
// mesh as it is; a cell field as per-cell vertex data whose four values are equal (reference/field.h
// per_cell_vertex_mesh), as a GPU draws cell data: each cell's own vertices carry its value. docs/data-model.md,
// "Fields".
#pragma once

#include <memory>

#include "reference/mesh.h"
#include "reference/topology.h"

namespace uvr::gpu {

class DrawnMesh {
public:
    DrawnMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field);
    const TetMesh& mesh() const { return *mesh_; }
    const MeshTopology& topology() const { return *topo_; }
    std::size_t field() const { return field_; }

private:
    std::unique_ptr<TetMesh> own_mesh_;
    std::unique_ptr<MeshTopology> own_topo_;
    const TetMesh* mesh_;
    const MeshTopology* topo_;
    std::size_t field_;
};

}  // namespace uvr::gpu
