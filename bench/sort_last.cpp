#include "bench/sort_last.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>

#include "gpu/pipeline/segment.h"
#include "reference/error.h"
#include "reference/partition.h"
#include "reference/segment_integral.h"
#include "reference/timing.h"

namespace uvr::cli {

namespace {

// Appends `ids` back to front (see back_to_front).
void order_boxes(const std::vector<Bounds>& boxes, std::vector<uint32_t> ids, const Camera& camera,
                 std::vector<uint32_t>& out, bool& separated)
{
    if (ids.size() == 1) {
        out.push_back(ids[0]);
        return;
    }
    const glm::dvec3 f = camera_frame(camera).f;
    for (int axis = 0; axis < 3; ++axis) {
        std::sort(ids.begin(), ids.end(), [&](uint32_t a, uint32_t b) {
            return boxes[a].lo[axis] != boxes[b].lo[axis] ? boxes[a].lo[axis] < boxes[b].lo[axis] : a < b;
        });
        double hi = -std::numeric_limits<double>::infinity();
        for (std::size_t i = 1; i < ids.size(); ++i) {
            hi = std::max(hi, boxes[ids[i - 1]].hi[axis]);
            const double plane = boxes[ids[i]].lo[axis];
            if (hi > plane) continue;  // boxes i.. do not all lie beyond a plane
            const std::vector<uint32_t> low(ids.begin(), ids.begin() + std::ptrdiff_t(i));
            const std::vector<uint32_t> high(ids.begin() + std::ptrdiff_t(i), ids.end());
            // The far side first: the high side when the eye is below the plane (orthographic: looking up the axis).
            const bool high_far = camera.orthographic ? f[axis] > 0.0 : camera.eye[axis] < plane;
            order_boxes(boxes, high_far ? high : low, camera, out, separated);
            order_boxes(boxes, high_far ? low : high, camera, out, separated);
            return;
        }
    }
    // No separating plane: by depth of the box centres, farthest first (ties by part index).
    separated = false;
    std::sort(ids.begin(), ids.end(), [&](uint32_t a, uint32_t b) {
        const double da = glm::dot(boxes[a].center() - camera.eye, f), db = glm::dot(boxes[b].center() - camera.eye, f);
        return da != db ? da > db : a < b;
    });
    out.insert(out.end(), ids.begin(), ids.end());
}

// Adds a part's diagnostic image to the sum (max_held: the largest).
void accumulate(std::vector<uint32_t>& sum, const std::vector<uint32_t>& part, bool largest)
{
    if (part.empty()) return;
    if (sum.empty()) sum.assign(part.size(), 0);
    for (std::size_t p = 0; p < part.size(); ++p) sum[p] = largest ? std::max(sum[p], part[p]) : sum[p] + part[p];
}

}  // namespace

std::vector<uint32_t> back_to_front(const std::vector<Bounds>& boxes, const Camera& camera, bool& separated)
{
    separated = true;
    std::vector<uint32_t> ids(boxes.size()), out;
    std::iota(ids.begin(), ids.end(), 0u);
    if (!ids.empty()) order_boxes(boxes, ids, camera, out, separated);
    return out;
}

Bounds centroid_box(const TetMesh& part)
{
    const double inf = std::numeric_limits<double>::infinity();
    Bounds b{glm::dvec3(inf), glm::dvec3(-inf)};
    for (const Tet& T : part.tets) {
        const glm::dvec3 c = 0.25 * (part.points[T[0]] + part.points[T[1]] + part.points[T[2]] + part.points[T[3]]);
        b.lo = glm::min(b.lo, c);
        b.hi = glm::max(b.hi, c);
    }
    return b;
}

Scene part_scene(const Scene& s, TetMesh part)
{
    Scene p;
    p.data.mesh = std::move(part);
    p.field = s.field;
    p.tf = s.tf;
    p.camera = s.camera;
    p.width = s.width;
    p.height = s.height;
    p.whole = s.whole ? *s.whole
                      : SceneExtent{mesh_bounds(s.mesh()), field_range(s.mesh().fields[s.field]),
                                    gpu::longest_tet_edge(s.mesh())};
    p.topology = std::make_unique<MeshTopology>(build_topology(*p.data.mesh));
    return p;
}

nlohmann::json merge_part_stats(const std::vector<nlohmann::json>& parts)
{
    nlohmann::json out = parts.front();
    for (auto& [key, value] : out.items()) {
        std::vector<nlohmann::json> each;
        for (const auto& p : parts) each.push_back(p.at(key));
        if (value.is_object()) {
            value = merge_part_stats(each);
            continue;
        }
        if (!value.is_number() || key == "k") continue;
        if (std::any_of(each.begin(), each.end(), [](const nlohmann::json& v) { return v.is_null(); })) {
            value = nullptr;
            continue;
        }
        const bool integral =
            std::all_of(each.begin(), each.end(), [](const nlohmann::json& v) { return v.is_number_integer(); });
        const auto get = [&](const nlohmann::json& v) { return integral ? nlohmann::json(v.get<uint64_t>()) : v; };
        if (key.starts_with("max_")) {
            value = get(*std::max_element(each.begin(), each.end(), [](const auto& x, const auto& y) {
                return x.template get<double>() < y.template get<double>();
            }));
        } else if (key.ends_with("_per_tet")) {
            double sum = 0.0, cells = 0.0;
            for (const auto& p : parts) {
                sum += p.at("cells").get<double>() * p.at(key).get<double>();
                cells += p.at("cells").get<double>();
            }
            value = sum / cells;
        } else if (integral) {
            uint64_t n = 0;
            for (const auto& v : each) n += v.get<uint64_t>();
            value = n;
        } else {
            double sum = 0.0;
            for (const auto& v : each) sum += v.get<double>();
            value = sum;
        }
    }
    return out;
}

Image blend_back_to_front(const std::vector<Image>& images, const std::vector<uint32_t>& order)
{
    Image out(images[0].width, images[0].height);
    for (std::size_t p = 0; p < out.rgba.size() / 4; ++p) {
        glm::dvec4 acc(0.0);
        for (uint32_t part : order) {
            const float* c = &images[part].rgba[4 * p];
            acc = composite_over(glm::dvec4(c[0], c[1], c[2], c[3]), acc);
        }
        for (int c = 0; c < 4; ++c) out.rgba[4 * p + std::size_t(c)] = float(acc[c]);
    }
    return out;
}

AlgoResult render_sort_last(const Scene& s, const std::string& algo, const AlgoOptions& o)
{
    const auto t0 = Clock::now();
    const TetMesh& mesh = s.mesh();
    const uint32_t parts = uint32_t(o.parts);
    const std::vector<uint32_t> part_of =
        partition_mesh(mesh, parts, parse_choice("--partition", kPartitionMethods, o.partition));
    AlgoOptions one = o;
    one.parts = 1;
    std::vector<Image> images;
    std::vector<Bounds> boxes;
    AlgoResult r;
    nlohmann::json part_ms = nlohmann::json::array();
    std::vector<nlohmann::json> part_stats;
    for (uint32_t p = 0; p < parts; ++p) {
        const Scene ps = part_scene(s, extract_part(mesh, part_of, p));
        boxes.push_back(centroid_box(ps.mesh()));
        AlgoResult pr = run_algorithm(ps, algo, one);
        part_ms.push_back(pr.ms);
        part_stats.push_back(pr.stats);
        accumulate(r.fragments, pr.fragments, false);
        accumulate(r.max_held, pr.max_held, true);
        accumulate(r.ordering_errors, pr.ordering_errors, false);
        accumulate(r.wrong_exits, pr.wrong_exits, false);
        images.push_back(std::move(pr.image));
    }
    bool separated = true;
    const std::vector<uint32_t> order = back_to_front(boxes, s.camera, separated);
    r.image = blend_back_to_front(images, order);
    r.stats = merge_part_stats(part_stats);
    r.stats["sort_last"] = {{"parts", parts},         {"partition", o.partition}, {"order", order},
                            {"separated", separated}, {"part_ms", part_ms},       {"part_stats", part_stats}};
    r.ms = ms_since(t0);
    return r;
}

}  // namespace uvr::cli
