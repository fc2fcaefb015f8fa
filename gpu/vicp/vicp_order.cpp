#include "gpu/vicp/vicp_order.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "gpu/pipeline/face_sort.h"
#include "reference/error.h"

namespace uvr::gpu {

const char* cell_order_name(CellOrder o)
{
    return choice_name(kCellOrders, o).data();
}

CellOrder parse_cell_order(const std::string& name)
{
    return parse_choice("--order", kCellOrders, name);
}

void centroid_cell_order(const std::vector<glm::vec3>& pts, const std::vector<Tet>& tets, const glm::vec3& eye,
                         const glm::vec3& dir, std::vector<uint32_t>& order)
{
    // Depth keys in float, shifted by their minimum so that the radix sort's non-negative keys hold for any eye.
    std::vector<float> keys(tets.size());
    tbb::parallel_for(std::size_t(0), tets.size(), [&](std::size_t i) {
        const Tet& t = tets[i];
        const glm::vec3 c = (((pts[t[0]] + pts[t[1]]) + pts[t[2]]) + pts[t[3]]) * 0.25f;
        keys[i] = ((c.x - eye.x) * dir.x + (c.y - eye.y) * dir.y) + (c.z - eye.z) * dir.z;
    });
    float lo = INFINITY;
    for (float k : keys) lo = std::min(lo, k);
    // k - lo rounds, but rounding is monotone: keys keep their order (two that differ by less than the rounding may
    // become equal, and the sort's stability then decides), and k >= lo gives k - lo >= 0 exactly.
    for (float& k : keys) k = k - lo;
    std::vector<uint32_t> scratch;
    radix_sort_faces(keys, order, scratch);
}

namespace {

struct Crossing {
    uint32_t pixel;
    double t;
    uint32_t tet;
    bool entry;
};

// The distance along pixel (px, py)'s ray to the plane through `a` with normal `n` (in the rays' frame), as a
// multiple of the ray's (unnormalized) direction: the order along one ray is all that matters.
double crossing_distance(const VicpFrameConstants& fc, const glm::dvec3& a, const glm::dvec3& n, int px, int py)
{
    const double ndc_x = (double(px) + 0.5) * fc.two_over_width - 1.0;
    const double ndc_y = (double(py) + 0.5) * fc.two_over_height - 1.0;
    const glm::dvec3 o = fc.eye + ndc_x * fc.ray_ox + ndc_y * fc.ray_oy;
    const glm::dvec3 d = fc.ray_d0 + ndc_x * fc.ray_dx + ndc_y * fc.ray_dy;
    return glm::dot(n, a - o) / glm::dot(n, d);
}

// XMPVO's relations: along each pixel's ray, the cell behind an exit face precedes the cell behind the next entry.
std::vector<std::pair<uint32_t, uint32_t>> ray_dependencies(const TetMesh& mesh, const MeshTopology& topo,
                                                            const CellOrderFrame& fr)
{
    const std::vector<WindowCoord>& win = *fr.win;
    const Framebuffer fbuf{fr.width, fr.height, RenderTarget::fbo};
    std::vector<Crossing> xs;
    std::vector<ClipVertex> poly, scratch;
    auto project = [&](const WindowCoord wv[3], const Face& f, const glm::dvec3& a, const glm::dvec3& n) {
        const TriangleSetup ts = setup_triangle(wv, fbuf);
        if (ts.empty()) return;
        const bool entry = ts.facing == Facing::front;  // outward faces: seen from outside, the ray enters
        for (int py = ts.y0; py <= ts.y1; ++py) {
            int first = 0, last = -1;
            row_span(ts, py, first, last);
            for (int px = first; px <= last; ++px)
                xs.push_back({uint32_t(py) * uint32_t(fr.width) + uint32_t(px),
                              crossing_distance(*fr.fc, a, n, px, py), uint32_t(f.tet[0]), entry});
        }
    };
    for (const Face& f : topo.faces) {
        if (!f.boundary()) continue;
        const glm::dvec3 a = mesh.points[f.v[0]] - fr.origin;
        const glm::dvec3& p0 = mesh.points[f.v[0]];
        const glm::dvec3 n = glm::cross(mesh.points[f.v[1]] - p0, mesh.points[f.v[2]] - p0);
        const VicpClipper* clip = fr.clipper;
        if (!clip || (clip->code(f.v[0]) | clip->code(f.v[1]) | clip->code(f.v[2])) == 0) {
            const WindowCoord wv[3] = {win[f.v[0]], win[f.v[1]], win[f.v[2]]};
            project(wv, f, a, n);
            continue;
        }
        if (clip->code(f.v[0]) & clip->code(f.v[1]) & clip->code(f.v[2])) continue;  // wholly outside one plane
        clip->clip_triangle(f.v.data(), poly, scratch);
        const auto window = [&](const ClipVertex& v) {
            return v.id != ClipVertex::kNewVertex ? win[v.id] : frame_window_coord(clip->view(), fbuf, glm::vec3(v.p));
        };
        for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
            const WindowCoord wv[3] = {window(poly[0]), window(poly[i]), window(poly[i + 1])};
            project(wv, f, a, n);
        }
    }
    // Along each ray: by distance, an exit before an entry at the same distance, then by cell (deterministic).
    std::sort(xs.begin(), xs.end(), [](const Crossing& p, const Crossing& q) {
        if (p.pixel != q.pixel) return p.pixel < q.pixel;
        if (p.t != q.t) return p.t < q.t;
        if (p.entry != q.entry) return !p.entry;
        return p.tet < q.tet;
    });
    // Coinciding crossings that rounding put entry first are swapped (kCoincidentCrossing).
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
        Crossing& p = xs[i];
        Crossing& q = xs[i + 1];
        if (p.pixel == q.pixel && p.entry && !q.entry && q.t - p.t <= kCoincidentCrossing * std::fabs(q.t))
            std::swap(p, q);
    }
    std::vector<std::pair<uint32_t, uint32_t>> deps;
    int64_t last_exit = -1;
    uint32_t pixel = UINT32_MAX;
    for (const Crossing& x : xs) {
        if (x.pixel != pixel) {
            pixel = x.pixel;
            last_exit = -1;
        }
        if (!x.entry) {
            last_exit = x.tet;
        } else {
            if (last_exit >= 0 && uint32_t(last_exit) != x.tet) deps.push_back({uint32_t(last_exit), x.tet});
            last_exit = -1;
        }
    }
    std::sort(deps.begin(), deps.end());
    deps.erase(std::unique(deps.begin(), deps.end()), deps.end());
    return deps;
}

}  // namespace

void mpvonc_cell_order(const TetMesh& mesh, const MeshTopology& topo, const CellOrderFrame& fr,
                       const std::vector<uint32_t>& centroid, std::vector<uint32_t>& order, CellOrderStats& stats)
{
    const std::size_t nt = mesh.tets.size(), nf = topo.faces.size();
    const Camera& cam = *fr.camera;
    const CameraFrame cf = camera_frame(cam);
    // MPVO: which of each internal face's cells comes first. +1: tet[0] first; -1: tet[1] first; 0: the eye lies in
    // the face's plane (no ray crosses it, no relation). The face's normal points out of tet[0].
    std::vector<int8_t> dir(nf, 0);
    tbb::parallel_for(std::size_t(0), nf, [&](std::size_t i) {
        const Face& f = topo.faces[i];
        if (f.boundary()) return;
        const auto point = [&](uint32_t v) { return fr.snapped ? (*fr.snapped)[v] : mesh.points[v] - fr.origin; };
        const glm::dvec3 a = point(f.v[0]), b = point(f.v[1]), c = point(f.v[2]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        // The eye's side: perspective, the sign of n . (eye - a); orthographic, the eye is at infinity behind the
        // image plane, in direction -forward.
        const double side = cam.orthographic ? -glm::dot(n, cf.f) : glm::dot(n, (cam.eye - fr.origin) - a);
        dir[i] = side > 0.0 ? int8_t(-1) : side < 0.0 ? int8_t(1) : int8_t(0);
    });
    std::vector<uint32_t> indegree(nt, 0);
    for (std::size_t i = 0; i < nf; ++i) {
        if (!dir[i]) continue;
        const Face& f = topo.faces[i];
        ++indegree[uint32_t(dir[i] > 0 ? f.tet[1] : f.tet[0])];
        ++stats.face_dependencies;
    }
    // XMPVO's relations along the rays, as adjacency lists (CSR).
    const auto deps = ray_dependencies(mesh, topo, fr);
    stats.ray_dependencies = deps.size();
    std::vector<uint32_t> first(nt + 1, 0), targets(deps.size());
    for (const auto& d : deps) ++first[d.first + 1];
    for (std::size_t i = 0; i < nt; ++i) first[i + 1] += first[i];
    {
        std::vector<uint32_t> fill(first.begin(), first.end() - 1);
        for (const auto& d : deps) {
            targets[fill[d.first]++] = d.second;
            ++indegree[d.second];
        }
    }
    // Kahn's algorithm, first in first out.
    order.clear();
    order.reserve(nt);
    std::vector<uint8_t> done(nt, 0);
    for (uint32_t t = 0; t < nt; ++t)
        if (indegree[t] == 0) order.push_back(t), done[t] = 1;
    std::size_t head = 0, breaker = 0;
    auto release = [&](uint32_t u) {
        if (done[u]) return;  // drawn early by a cycle break
        if (--indegree[u] == 0) order.push_back(u), done[u] = 1;
    };
    while (order.size() < nt) {
        if (head == order.size()) {
            // Stalled: every cell left waits on another, so the relations have a cycle. Draw the nearest one.
            while (done[centroid[breaker]]) ++breaker;
            const uint32_t u = centroid[breaker];
            order.push_back(u);
            done[u] = 1;
            ++stats.cycle_breaks;
        }
        const uint32_t t = order[head++];
        for (int i = 0; i < 4; ++i) {
            const int32_t fi = topo.tet_faces[t][std::size_t(i)];
            if (fi < 0 || !dir[std::size_t(fi)]) continue;
            const Face& f = topo.faces[std::size_t(fi)];
            const uint32_t from = uint32_t(dir[std::size_t(fi)] > 0 ? f.tet[0] : f.tet[1]);
            if (from == t) release(uint32_t(dir[std::size_t(fi)] > 0 ? f.tet[1] : f.tet[0]));
        }
        for (uint32_t j = first[t]; j < first[t + 1]; ++j) release(targets[j]);
    }
}

}  // namespace uvr::gpu
