#include "reference/partition.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <glm/common.hpp>
#include <metis.h>
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "reference/error.h"

namespace uvr {

namespace {

struct Bisection {
    const std::vector<glm::dvec3>& centroid;
    const std::vector<uint64_t>* weights;  // null: the sets' sizes are counted in cells
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
        // A strict total order (coordinate, then cell index): the two sets are the same whatever the sort's order.
        const auto before = [&](uint32_t a, uint32_t b) {
            const double ca = centroid[a][axis], cb = centroid[b][axis];
            return ca < cb || (ca == cb && a < b);
        };
        const std::size_t n = std::size_t(end - begin);
        std::size_t left = 0;
        if (!weights) {
            // The left set's share of the cells, rounded down; every part keeps at least one cell (parts <= cells).
            left = std::max<std::size_t>(left_parts, n * left_parts / parts);
            std::nth_element(begin, begin + left, end, before);
        } else {
            std::sort(begin, end, before);
            left = weighted_cut(begin, end, left_parts, parts);
        }
        split(begin, begin + left, first_part, left_parts);
        split(begin + left, end, first_part + left_parts, parts - left_parts);
    }

    // Of the cells [begin, end) in order along the axis: how many go left so that their weight is nearest
    // left_parts / parts of the whole, each side keeping at least one cell per part.
    std::size_t weighted_cut(const uint32_t* begin, const uint32_t* end, uint32_t left_parts, uint32_t parts) const
    {
        const std::size_t n = std::size_t(end - begin);
        long double total = 0.0L;
        for (const uint32_t* c = begin; c != end; ++c) total += (*weights)[*c];
        const long double target = total * left_parts / parts;
        std::size_t k = 0;
        long double below = 0.0L;  // the weight of the first k cells
        while (k < n && below + (*weights)[begin[k]] <= target) below += (*weights)[begin[k++]];
        // The cut after k cells leaves the left short of the target by less than cell k's weight; after k + 1 cells
        // it is over: take the nearer.
        if (k < n && (below + (*weights)[begin[k]]) - target < target - below) ++k;
        return std::clamp<std::size_t>(k, left_parts, n - (parts - left_parts));
    }
};

void check_parts(const TetMesh& mesh, uint32_t parts)
{
    const std::size_t n = mesh.tets.size();
    if (parts < 1 || parts > n)
        throw InputError(mesh.source, "cannot split " + std::to_string(n) + " tetrahedra into " +
                                          std::to_string(parts) + " parts (1 to the number of tetrahedra)");
}

void check_weights(const TetMesh& mesh, const std::vector<uint64_t>* weights)
{
    if (weights && weights->size() != mesh.tets.size())
        throw std::invalid_argument("partition weights: one per tetrahedron");
}

// METIS's two constraints per tetrahedron, interleaved: 1 (its cell) and its steps. METIS's weights are idx_t (32-bit)
// and it sums them: the steps are scaled down by the least integer that keeps their sum within kMetisWeightSum.
std::vector<idx_t> metis_cells_and_steps(const std::vector<uint64_t>& steps)
{
    // Half of idx_t's range: METIS adds a part's weights and compares sums with headroom.
    constexpr uint64_t kMetisWeightSum = uint64_t(std::numeric_limits<idx_t>::max()) / 2;
    uint64_t total = 0;
    for (uint64_t w : steps) total += w;
    const uint64_t divisor = total / kMetisWeightSum + 1;
    std::vector<idx_t> out(2 * steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) {
        out[2 * i] = 1;
        out[2 * i + 1] = idx_t(steps[i] / divisor);
    }
    return out;
}

}  // namespace

std::vector<uint32_t> partition_mesh(const TetMesh& mesh, uint32_t parts, PartitionMethod method,
                                     const std::vector<uint64_t>* view_steps)
{
    if (method == PartitionMethod::metis) return partition_metis(mesh, parts, view_steps);
    if (!view_steps) return partition_rcb(mesh, parts);
    std::vector<uint64_t> weights(*view_steps);  // partition_rcb checks their count
    for (uint64_t& w : weights) w += kCellWorkInSteps;
    return partition_rcb(mesh, parts, &weights);
}

std::vector<uint32_t> partition_rcb(const TetMesh& mesh, uint32_t parts, const std::vector<uint64_t>* weights)
{
    check_parts(mesh, parts);
    check_weights(mesh, weights);
    const std::size_t n = mesh.tets.size();
    std::vector<glm::dvec3> centroid(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Tet& t = mesh.tets[i];
        centroid[i] = 0.25 * (((mesh.points[t[0]] + mesh.points[t[1]]) + mesh.points[t[2]]) + mesh.points[t[3]]);
    }
    std::vector<uint32_t> cells(n);
    std::iota(cells.begin(), cells.end(), 0u);
    std::vector<uint32_t> part_of(n, 0);
    Bisection{centroid, weights, part_of}.split(cells.data(), cells.data() + n, 0, parts);
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

std::vector<uint32_t> partition_metis(const TetMesh& mesh, uint32_t parts, const std::vector<uint64_t>* steps)
{
    check_parts(mesh, parts);
    check_weights(mesh, steps);
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
    idx_t vertices = idx_t(n), constraints = steps ? 2 : 1, nparts = idx_t(parts), cut = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // METIS's random choices from a fixed seed: the same parts on every run
    options[METIS_OPTION_NUMBERING] = 0;
    std::vector<idx_t> vertex_weight;
    if (steps) vertex_weight = metis_cells_and_steps(*steps);
    std::vector<idx_t> part(n, 0);
    const int status =
        METIS_PartGraphKway(&vertices, &constraints, xadj.data(), adjncy.data(), steps ? vertex_weight.data() : nullptr,
                            nullptr, nullptr, &nparts, nullptr, nullptr, options, &cut, part.data());
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

std::vector<uint64_t> view_steps(const RayIntegrator& integrator, std::size_t tetrahedra, const Camera& camera,
                                 int width, int height)
{
    // 16x16 tiles, as render_reference; each thread counts into its own array, summed after (integers: the same
    // result whatever the threads' order).
    tbb::enumerable_thread_specific<std::vector<uint32_t>> counts(
        [tetrahedra] { return std::vector<uint32_t>(tetrahedra, 0); });
    const CameraRays rays(camera, width, height);
    tbb::parallel_for(tbb::blocked_range2d<int>(0, height, 16, 0, width, 16), [&](const tbb::blocked_range2d<int>& r) {
        std::vector<uint32_t>& visits = counts.local();
        RayStats stats;
        for (int j = r.rows().begin(); j < r.rows().end(); ++j)
            for (int i = r.cols().begin(); i < r.cols().end(); ++i)
                integrator.integrate_counting(rays(i, j), stats, visits);
    });
    std::vector<uint64_t> steps(tetrahedra, 0);
    for (const std::vector<uint32_t>& visits : counts)
        for (std::size_t t = 0; t < tetrahedra; ++t) steps[t] += visits[t];
    return steps;
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
