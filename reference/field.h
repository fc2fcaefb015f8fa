// The three kinds of field a mesh carries, and what a renderer reads of them.
//
// A point field is continuous when coincident points agree; when they do not, it is per-cell vertex data: each
// tetrahedron keeps its own values and the field jumps across the faces where its two sides disagree. A cell field is
// constant in each tetrahedron. Welding (MeshTopology::canonical) decides which cells are neighbours; it never merges
// values. docs/data-model.md, "Fields".
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "reference/mesh.h"
#include "reference/topology.h"

namespace uvr {

enum class FieldKind { point, cell_vertex, cell };
const char* field_kind_name(FieldKind kind);  // "point", "cell_vertex", "cell"

// The field's values at tetrahedron t's four vertices, in t's vertex order.
inline std::array<double, 4> tet_values(const TetMesh& mesh, const ScalarField& f, std::size_t t)
{
    if (f.association == FieldAssociation::cell) return {f.values[t], f.values[t], f.values[t], f.values[t]};
    const Tet& v = mesh.tets[t];
    return {f.values[v[0]], f.values[v[1]], f.values[v[2]], f.values[v[3]]};
}

// Per unique face of topo: 1 where the face is internal and its two tetrahedra disagree at one of its points.
std::vector<uint8_t> field_jump_faces(const TetMesh& mesh, const MeshTopology& topo, const ScalarField& field);

struct FieldSummary {
    FieldKind kind = FieldKind::point;
    std::size_t jump_faces = 0;  // internal faces across which the field jumps
};
// A cell field is `cell`; a point field with a jump face is `cell_vertex`, else `point`.
FieldSummary summarize_field(const TetMesh& mesh, const MeshTopology& topo, const ScalarField& field);

// The mesh with one field, `field`, as point data on points of its own: each tetrahedron gets four points, carrying
// its values (a cell field's value at all four). Cell data as the GPU algorithms draw it: per-cell vertex data whose
// four values are equal. Tetrahedra keep their indices and vertex order.
TetMesh per_cell_vertex_mesh(const TetMesh& mesh, std::size_t field);

}  // namespace uvr
