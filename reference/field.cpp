#include "reference/field.h"

#include "reference/error.h"

namespace uvr {

const char* field_kind_name(FieldKind kind)
{
    switch (kind) {
    case FieldKind::point: return "point";
    case FieldKind::cell_vertex: return "cell_vertex";
    default: return "cell";
    }
}

namespace {

// Whether the two sides of internal face `face` carry different values at one of its points.
bool jumps(const TetMesh& mesh, const MeshTopology& topo, const ScalarField& f, const Face& face)
{
    const auto a = uint32_t(face.tet[0]), b = uint32_t(face.tet[1]);
    if (f.association == FieldAssociation::cell) return f.values[a] != f.values[b];
    // The face's points as each side indexes them, matched by canonical point.
    for (uint32_t pa : mesh.tets[a]) {
        const uint32_t ca = topo.canonical[pa];
        for (uint32_t pb : mesh.tets[b])
            if (topo.canonical[pb] == ca && f.values[pa] != f.values[pb]) return true;
    }
    return false;
}

}  // namespace

std::vector<uint8_t> field_jump_faces(const TetMesh& mesh, const MeshTopology& topo, const ScalarField& field)
{
    std::vector<uint8_t> out(topo.faces.size(), 0);
    for (std::size_t i = 0; i < topo.faces.size(); ++i)
        if (!topo.faces[i].boundary()) out[i] = jumps(mesh, topo, field, topo.faces[i]) ? 1 : 0;
    return out;
}

FieldSummary summarize_field(const TetMesh& mesh, const MeshTopology& topo, const ScalarField& field)
{
    FieldSummary s;
    for (uint8_t j : field_jump_faces(mesh, topo, field)) s.jump_faces += j;
    if (field.association == FieldAssociation::cell) s.kind = FieldKind::cell;
    else if (s.jump_faces > 0) s.kind = FieldKind::cell_vertex;
    return s;
}

TetMesh per_cell_vertex_mesh(const TetMesh& mesh, std::size_t field)
{
    const ScalarField& f = mesh.fields.at(field);
    if (mesh.tets.size() > UINT32_MAX / 4)
        throw InputError(mesh.source, "2^30 tetrahedra or more: a field drawn per cell needs four points of its own "
                                      "for each, and point indices are 32-bit");
    TetMesh out;
    out.source = mesh.source;
    out.points.reserve(4 * mesh.tets.size());
    out.tets.reserve(mesh.tets.size());
    ScalarField g{f.name, {}, FieldAssociation::point};
    g.values.reserve(4 * mesh.tets.size());
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        const auto v = tet_values(mesh, f, t);
        const auto base = uint32_t(out.points.size());
        for (int k = 0; k < 4; ++k) {
            out.points.push_back(mesh.points[mesh.tets[t][k]]);
            g.values.push_back(v[k]);
        }
        out.tets.push_back({base, base + 1, base + 2, base + 3});
    }
    out.fields.push_back(std::move(g));
    return out;
}

}  // namespace uvr
