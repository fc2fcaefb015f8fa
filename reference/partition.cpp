#include "reference/partition.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include <glm/common.hpp>
#include <metis.h>

#include "reference/error.h"

namespace uvr {

namespace {

struct Bisection {
    const std::vector<glm::dvec3>& centroid;
    std::vector<uint32_t>& part_of;

    // Assigns parts [first_part, first_part + parts) to the cells in [begin, end).
    void split(uint32_t* begin, uint32_t* end, uint32_t first_part, uint32_t parts)
    {
        if (parts == 1) {
            for (uint32_t* c = begin; c != end; ++c) part_of[*c] = first_part;
            return;
        }
        glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (uint32_t* c = begin; c != end; ++c) {
            lo = glm::min(lo, centroid[*c]);
            hi = glm::max(hi, centroid[*c]);
        }
        const glm::dvec3 side = hi - lo;
        const int axis = side.x >= side.y && side.x >= side.z ? 0 : side.y >= side.z ? 1 : 2;
        const uint32_t left_parts = parts / 2;
        // The left set's share of the cells, rounded down; every part keeps at least one cell because parts <= cells.
        const std::size_t n = std::size_t(end - begin);
        const std::size_t left = std::max<std::size_t>(left_parts, n * left_parts / parts);
        // A strict total order (coordinate, then cell index): the two sets are the same whatever nth_element's order.
        std::nth_element(begin, begin + left, end, [&](uint32_t a, uint32_t b) {
            const double ca = centroid[a][axis], cb = centroid[b][axis];
            return ca < cb || (ca == cb && a < b);
        });
        split(begin, begin + left, first_part, left_parts);
        split(begin + left, end, first_part + left_parts, parts - left_parts);
    }
};

void check_parts(const TetMesh& mesh, uint32_t parts)
{
    const std::size_t n = mesh.tets.size();
    if (parts < 1 || parts > n)
        throw InputError(mesh.source, "cannot split " + std::to_string(n) + " tetrahedra into " +
                                          std::to_string(parts) + " parts (1 to the number of tetrahedra)");
}

}  // namespace

std::vector<uint32_t> partition_mesh(const TetMesh& mesh, uint32_t parts, PartitionMethod method)
{
    return method == PartitionMethod::metis ? partition_metis(mesh, parts) : partition_rcb(mesh, parts);
}

std::vector<uint32_t> partition_rcb(const TetMesh& mesh, uint32_t parts)
{
    check_parts(mesh, parts);
    const std::size_t n = mesh.tets.size();
    std::vector<glm::dvec3> centroid(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Tet& t = mesh.tets[i];
        centroid[i] = 0.25 * (((mesh.points[t[0]] + mesh.points[t[1]]) + mesh.points[t[2]]) + mesh.points[t[3]]);
    }
    std::vector<uint32_t> cells(n);
    std::iota(cells.begin(), cells.end(), 0u);
    std::vector<uint32_t> part_of(n, 0);
    Bisection{centroid, part_of}.split(cells.data(), cells.data() + n, 0, parts);
    return part_of;
}

std::vector<PartCounts> count_parts(const MeshTopology& topo, const std::vector<uint32_t>& part_of)
{
    const uint32_t parts = part_of.empty() ? 0 : *std::max_element(part_of.begin(), part_of.end()) + 1;
    std::vector<PartCounts> out(parts);
    for (uint32_t p : part_of) ++out[p].tetrahedra;
    for (const Face& f : topo.faces) {
        const uint32_t a = part_of[std::size_t(f.tet[0])];
        if (f.boundary()) {
            ++out[a].boundary_faces;
        } else if (const uint32_t b = part_of[std::size_t(f.tet[1])]; a != b) {
            ++out[a].cut_faces;
            ++out[b].cut_faces;
        }
    }
    return out;
}

std::vector<uint32_t> partition_metis(const TetMesh& mesh, uint32_t parts)
{
    check_parts(mesh, parts);
    const std::size_t n = mesh.tets.size();
    if (parts == 1) return std::vector<uint32_t>(n, 0);
    if (n > std::size_t(std::numeric_limits<idx_t>::max()) / 4)
        throw InputError(mesh.source, "too many tetrahedra for METIS's 32-bit indices");
    const MeshTopology topo = build_topology(mesh);
    std::vector<idx_t> xadj{0}, adjncy;
    for (std::size_t c = 0; c < n; ++c) {
        for (int32_t other : topo.neighbor[c])
            if (other >= 0) adjncy.push_back(other);
        xadj.push_back(idx_t(adjncy.size()));
    }
    idx_t vertices = idx_t(n), constraints = 1, nparts = idx_t(parts), cut = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // METIS's random choices from a fixed seed: the same parts on every run
    options[METIS_OPTION_NUMBERING] = 0;
    std::vector<idx_t> part(n, 0);
    const int status = METIS_PartGraphKway(&vertices, &constraints, xadj.data(), adjncy.data(), nullptr, nullptr,
                                           nullptr, &nparts, nullptr, nullptr, options, &cut, part.data());
    if (status != METIS_OK)
        throw InputError(mesh.source, "METIS could not split the mesh into " + std::to_string(parts) +
                                          " parts (status " + std::to_string(status) + ")");
    std::vector<std::size_t> size(parts, 0);
    for (idx_t p : part) ++size[std::size_t(p)];
    for (uint32_t p = 0; p < parts; ++p)
        if (size[p] == 0)
            throw InputError(mesh.source, "METIS left part " + std::to_string(p) + " of " + std::to_string(parts) +
                                              " empty: ask for fewer parts");
    return std::vector<uint32_t>(part.begin(), part.end());
}

TetMesh extract_part(const TetMesh& mesh, const std::vector<uint32_t>& part_of, uint32_t part)
{
    TetMesh out;
    out.source = mesh.source + " (part " + std::to_string(part) + ")";
    constexpr uint32_t kUnused = UINT32_MAX;
    std::vector<uint32_t> new_index(mesh.points.size(), kUnused);
    std::vector<uint32_t> cells;
    for (uint32_t c = 0; c < mesh.tets.size(); ++c)
        if (part_of[c] == part) {
            cells.push_back(c);
            for (uint32_t v : mesh.tets[c]) new_index[v] = 0;
        }
    std::vector<uint32_t> points;
    for (uint32_t p = 0; p < mesh.points.size(); ++p)
        if (new_index[p] != kUnused) {
            new_index[p] = uint32_t(points.size());
            points.push_back(p);
        }
    for (uint32_t p : points) out.points.push_back(mesh.points[p]);
    for (uint32_t c : cells) {
        const Tet& t = mesh.tets[c];
        out.tets.push_back({new_index[t[0]], new_index[t[1]], new_index[t[2]], new_index[t[3]]});
    }
    for (const ScalarField& f : mesh.fields) {
        ScalarField g{f.name, {}, f.association};
        const std::vector<uint32_t>& from = f.association == FieldAssociation::point ? points : cells;
        for (uint32_t i : from) g.values.push_back(f.values[i]);
        out.fields.push_back(std::move(g));
    }
    return out;
}

}  // namespace uvr
