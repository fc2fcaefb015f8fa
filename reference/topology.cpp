#include "reference/topology.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "reference/error.h"

namespace uvr {

std::array<uint32_t, 3> tet_face(const Tet& t, int i)
{
    // With positive orientation (vertex 3 above face 0 1 2), these orders make each face's normal point outward.
    switch (i) {
    case 0: return {t[1], t[2], t[3]};
    case 1: return {t[0], t[3], t[2]};
    case 2: return {t[0], t[1], t[3]};
    default: return {t[0], t[2], t[1]};
    }
}

namespace {

struct FaceRef {
    std::array<uint32_t, 3> key;  // sorted vertex indices
    uint32_t tet;
    uint8_t local;
};

bool same_face(const FaceRef& a, const FaceRef& b)
{
    return a.key[0] == b.key[0] && a.key[1] == b.key[1] && a.key[2] == b.key[2];
}

std::array<uint32_t, 3> sorted3(std::array<uint32_t, 3> a)
{
    std::sort(a.begin(), a.end());
    return a;
}

std::string face_text(const std::array<uint32_t, 3>& k)
{
    return "(points " + std::to_string(k[0]) + " " + std::to_string(k[1]) + " " + std::to_string(k[2]) + ")";
}

// The four faces of every tetrahedron that is not flat (counted in `flat`), keyed by their sorted canonical points,
// in the order (key, tetrahedron, corner): a total order, so the result is the same on any number of threads. The
// references are placed by their least point first (a counting sort over the points: one pass to count, one to
// place), then each point's few references are sorted, which costs less than one sort of them all (docs/data-model.md).
std::vector<FaceRef> sorted_face_refs(const TetMesh& mesh, const std::vector<uint32_t>& canonical, std::size_t& flat)
{
    const std::size_t nt = mesh.tets.size();
    std::vector<uint8_t> skip(nt, 0);
    const auto key_of = [&](std::size_t t, int i) {
        auto f = tet_face(mesh.tets[t], i);
        for (auto& v : f) v = canonical[v];
        return sorted3(f);
    };
    std::vector<std::size_t> first(mesh.points.size() + 1, 0);  // bucket p: [first[p], first[p + 1])
    for (std::size_t t = 0; t < nt; ++t) {
        skip[t] = is_degenerate(mesh, mesh.tets[t]);
        if (skip[t]) {
            ++flat;
            continue;
        }
        for (int i = 0; i < 4; ++i) ++first[key_of(t, i)[0] + 1];
    }
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<FaceRef> refs(first.back());
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < nt; ++t)
        for (int i = 0; i < (skip[t] ? 0 : 4); ++i) {
            const std::array<uint32_t, 3> key = key_of(t, i);
            refs[next[key[0]]++] = {key, static_cast<uint32_t>(t), static_cast<uint8_t>(i)};
        }
    // Compared field by field: std::array's operators compare through memcmp calls.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mesh.points.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t p = r.begin(); p != r.end(); ++p)
                std::sort(refs.begin() + std::ptrdiff_t(first[p]), refs.begin() + std::ptrdiff_t(first[p + 1]),
                          [](const FaceRef& a, const FaceRef& b) {
                              return std::tie(a.key[1], a.key[2], a.tet, a.local) <
                                     std::tie(b.key[1], b.key[2], b.tet, b.local);
                          });
        });
    return refs;
}

}  // namespace

std::vector<uint32_t> canonical_points(const std::vector<glm::dvec3>& points)
{
    std::vector<uint32_t> order(points.size());
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](uint32_t i) { return std::make_tuple(points[i].x, points[i].y, points[i].z); };
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        const auto ka = key(a), kb = key(b);
        return ka != kb ? ka < kb : a < b;
    });
    std::vector<uint32_t> canon(points.size());
    for (std::size_t r = 0; r < order.size();) {
        std::size_t e = r + 1;
        while (e < order.size() && key(order[e]) == key(order[r])) ++e;
        for (std::size_t k = r; k < e; ++k) canon[order[k]] = order[r];  // order[r] is the smallest index
        r = e;
    }
    return canon;
}

MeshTopology build_topology(const TetMesh& mesh)
{
    const std::size_t nt = mesh.tets.size();
    MeshTopology topo;
    topo.canonical = canonical_points(mesh.points);
    const std::vector<FaceRef> refs = sorted_face_refs(mesh, topo.canonical, topo.flat_tets);
    topo.tet_faces.assign(nt, {-1, -1, -1, -1});
    topo.neighbor.assign(nt, {-1, -1, -1, -1});
    topo.faces.reserve(nt * 2 + nt / 4);
    for (std::size_t r = 0; r < refs.size();) {
        std::size_t e = r + 1;
        while (e < refs.size() && same_face(refs[e], refs[r])) ++e;
        const std::size_t count = e - r;
        if (count > 2)
            throw InputError(mesh.source, "face " + face_text(refs[r].key) + " is shared by " +
                                              std::to_string(count) + " tetrahedra (" + std::to_string(refs[r].tet) +
                                              ", " + std::to_string(refs[r + 1].tet) + ", " +
                                              std::to_string(refs[r + 2].tet) + "...): cells overlap");
        const int32_t fi = static_cast<int32_t>(topo.faces.size());
        const FaceRef& a = refs[r];
        Face f{tet_face(mesh.tets[a.tet], a.local), {static_cast<int32_t>(a.tet), -1}};
        topo.tet_faces[a.tet][a.local] = fi;
        if (count == 2) {
            const FaceRef& b = refs[r + 1];
            // Two tetrahedra on the same side of their shared face overlap: their outward orders agree.
            const auto fa = tet_face(mesh.tets[a.tet], a.local), fb = tet_face(mesh.tets[b.tet], b.local);
            const glm::dvec3 na = glm::cross(mesh.points[fa[1]] - mesh.points[fa[0]],
                                             mesh.points[fa[2]] - mesh.points[fa[0]]);
            const glm::dvec3 nb = glm::cross(mesh.points[fb[1]] - mesh.points[fb[0]],
                                             mesh.points[fb[2]] - mesh.points[fb[0]]);
            if (glm::dot(na, nb) > 0.0)
                throw InputError(mesh.source, "tetrahedra " + std::to_string(a.tet) + " and " +
                                                  std::to_string(b.tet) + " lie on the same side of their shared face " +
                                                  face_text(a.key) + ": cells overlap");
            f.tet[1] = static_cast<int32_t>(b.tet);
            topo.tet_faces[b.tet][b.local] = fi;
            topo.neighbor[a.tet][a.local] = static_cast<int32_t>(b.tet);
            topo.neighbor[b.tet][b.local] = static_cast<int32_t>(a.tet);
            ++topo.internal_faces;
        } else {
            ++topo.boundary_faces;
        }
        topo.faces.push_back(f);
        r = e;
    }
    return topo;
}

std::vector<uint8_t> seam_points(const TetMesh& mesh, const MeshTopology& topo)
{
    const std::size_t np = mesh.points.size();
    std::vector<uint32_t> parent(np);
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const Face& f : topo.faces) {
        if (f.boundary()) continue;
        for (uint32_t pa : mesh.tets[std::size_t(f.tet[0])])
            for (uint32_t pb : mesh.tets[std::size_t(f.tet[1])])
                if (pa != pb && topo.canonical[pa] == topo.canonical[pb]) parent[root(pa)] = root(pb);
    }
    // A point is on a seam when its position's copies fall into more than one group.
    std::vector<uint32_t> first_group(np, UINT32_MAX);
    std::vector<uint8_t> split(np, 0);
    for (std::size_t i = 0; i < np; ++i) {
        const uint32_t c = topo.canonical[i], g = root(uint32_t(i));
        if (first_group[c] == UINT32_MAX) first_group[c] = g;
        else if (first_group[c] != g) split[c] = 1;
    }
    std::vector<uint8_t> out(np, 0);
    for (std::size_t i = 0; i < np; ++i) out[i] = split[topo.canonical[i]];
    return out;
}

namespace {

struct BoundaryEdge {
    uint32_t a, b;  // directed as the face traverses it
    uint32_t face;
    uint32_t opposite;  // the face's third vertex
};

std::vector<BoundaryEdge> boundary_edges_sorted(const MeshTopology& topo)
{
    std::vector<BoundaryEdge> edges;
    edges.reserve(topo.boundary_faces * 3);
    for (std::size_t f = 0; f < topo.faces.size(); ++f) {
        const Face& face = topo.faces[f];
        if (!face.boundary()) continue;
        for (int i = 0; i < 3; ++i)
            edges.push_back({topo.canonical[face.v[i]], topo.canonical[face.v[(i + 1) % 3]], static_cast<uint32_t>(f),
                             face.v[(i + 2) % 3]});
    }
    // Group each undirected edge: key (min, max), then direction, then face.
    std::sort(edges.begin(), edges.end(), [](const BoundaryEdge& x, const BoundaryEdge& y) {
        const auto kx = std::make_tuple(std::min(x.a, x.b), std::max(x.a, x.b), x.a, x.face);
        const auto ky = std::make_tuple(std::min(y.a, y.b), std::max(y.a, y.b), y.a, y.face);
        return kx < ky;
    });
    return edges;
}

bool same_edge(const BoundaryEdge& x, const BoundaryEdge& y)
{
    return std::min(x.a, x.b) == std::min(y.a, y.b) && std::max(x.a, x.b) == std::max(y.a, y.b);
}

}  // namespace

std::size_t boundary_open_edges(const MeshTopology& topo)
{
    const auto edges = boundary_edges_sorted(topo);
    std::size_t bad = 0;
    for (std::size_t r = 0; r < edges.size();) {
        std::size_t e = r;
        long balance = 0;
        for (; e < edges.size() && same_edge(edges[e], edges[r]); ++e) balance += edges[e].a < edges[e].b ? 1 : -1;
        if (balance != 0) ++bad;
        r = e;
    }
    return bad;
}

std::size_t boundary_nonmanifold_edges(const MeshTopology& topo)
{
    const auto edges = boundary_edges_sorted(topo);
    std::size_t bad = 0;
    for (std::size_t r = 0; r < edges.size();) {
        std::size_t e = r + 1;
        while (e < edges.size() && same_edge(edges[e], edges[r])) ++e;
        if (e - r != 2) ++bad;
        r = e;
    }
    return bad;
}

bool boundary_is_convex(const TetMesh& mesh, const MeshTopology& topo)
{
    const auto edges = boundary_edges_sorted(topo);
    const Bounds b = mesh_bounds(mesh);
    const double tol = kConvexityTolerance * glm::length(b.extent());
    // Connectivity of the boundary surface through shared edges (union-find over boundary faces).
    std::vector<uint32_t> parent(topo.faces.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (std::size_t r = 0; r < edges.size();) {
        std::size_t e = r + 1;
        while (e < edges.size() && same_edge(edges[e], edges[r])) ++e;
        if (e - r != 2) return false;  // not a closed manifold surface: not a convex body's boundary
        const BoundaryEdge &x = edges[r], &y = edges[r + 1];
        parent[root(x.face)] = root(y.face);
        // Reflex when y's far vertex lies outside x's plane (x's outward normal side).
        const Face& fx = topo.faces[x.face];
        const glm::dvec3 p0 = mesh.points[fx.v[0]];
        const glm::dvec3 n = glm::cross(mesh.points[fx.v[1]] - p0, mesh.points[fx.v[2]] - p0);
        const double len = glm::length(n);
        if (len > 0.0 && glm::dot(mesh.points[y.opposite] - p0, n) / len > tol) return false;
        r = e;
    }
    uint32_t first_root = UINT32_MAX;
    for (std::size_t f = 0; f < topo.faces.size(); ++f) {
        if (!topo.faces[f].boundary()) continue;
        const uint32_t rt = root(static_cast<uint32_t>(f));
        if (first_root == UINT32_MAX) first_root = rt;
        if (rt != first_root) return false;  // several components: disjoint pieces, or a cavity
    }
    return true;
}

double boundary_enclosed_volume(const TetMesh& mesh, const MeshTopology& topo)
{
    // Sum of signed tetrahedra from a fixed reference point (the bounds centre, to keep the terms small).
    const glm::dvec3 c = mesh_bounds(mesh).center();
    double v6 = 0.0;
    for (const Face& f : topo.faces)
        if (f.boundary()) v6 += signed_volume6(c, mesh.points[f.v[0]], mesh.points[f.v[1]], mesh.points[f.v[2]]);
    return v6 / 6.0;
}

double total_tet_volume(const TetMesh& mesh)
{
    double v6 = 0.0;
    for (const Tet& t : mesh.tets)
        v6 += signed_volume6(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
    return v6 / 6.0;
}

}  // namespace uvr
