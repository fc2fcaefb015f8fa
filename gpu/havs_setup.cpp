#include "gpu/havs_setup.h"

#include <algorithm>
#include <chrono>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "gpu/face_sort.h"
#include "reference/error.h"

namespace uvr::gpu {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

double longest_tet_edge(const TetMesh& mesh)
{
    double longest = 0.0;
    for (const Tet& t : mesh.tets) {
        if (is_degenerate(mesh, t)) continue;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b)
                longest = std::max(longest, glm::length(mesh.points[t[a]] - mesh.points[t[b]]));
    }
    return longest;
}

std::unique_ptr<PreintegrationTable> build_segment_table(const SegmentIntegrator& integrator, const Range& range,
                                                         int size, TexelFormat format, double max_length, double& ms)
{
    const auto t0 = Clock::now();
    PreintegrationConfig cfg;
    cfg.scalar_resolution = cfg.length_resolution = size;
    cfg.format = format;
    cfg.max_length = max_length;
    auto table = std::make_unique<PreintegrationTable>(integrator, range, cfg);
    ms = ms_since(t0);
    return table;
}

SegmentShader segment_shader(const PreintegrationTable* table, TextureFilter filter,
                             const SegmentIntegrator& integrator, const Range& range)
{
    if (table) {
        const LlvmpipeCpu cpu = host_llvmpipe_cpu();
        return [table, filter, cpu](float uf, float ub, float tz, float) {
            return table->sample(uf, ub, tz, cpu, filter);
        };
    }
    const double lo = range.lo, span = range.hi > range.lo ? range.hi - range.lo : 1.0;
    return [&integrator, lo, span](float uf, float ub, float, float length) {
        return glm::vec4(integrator.integrate(lo + double(uf) * span, lo + double(ub) * span, double(length)));
    };
}

HavsMesh::HavsMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                   const HavsOptions& options)
    : mesh_(mesh), options_(options), integrator_(tf), range_(field_range(mesh.fields.at(field)))
{
    origin_ = mesh_bounds(mesh).center();
    points_f_.reserve(mesh.points.size());
    for (const auto& p : mesh.points) points_f_.push_back(glm::vec3(p - origin_));
    const double span = range_.hi > range_.lo ? range_.hi - range_.lo : 1.0;
    for (double s : mesh.fields[field].values) scalar_n_.push_back((s - range_.lo) / span);
    // Welded points (a coincident twin exists): a boundary face made only of them lies on a seam inside the mesh (the
    // O-grid seam of docs/data-model.md), not on the mesh's surface, so it is never a gap's start.
    std::vector<uint8_t> welded(mesh.points.size(), 0);
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
        if (topo.canonical[i] != i) welded[i] = welded[topo.canonical[i]] = 1;
    faces_.reserve(topo.faces.size() * 3);
    boundary_.reserve(topo.faces.size());
    for (const Face& f : topo.faces) {
        faces_.insert(faces_.end(), f.v.begin(), f.v.end());
        const bool seam = welded[f.v[0]] && welded[f.v[1]] && welded[f.v[2]];
        boundary_.push_back(options_.gaps == GapMode::exact && f.boundary() && !seam ? 1 : 0);
    }
    longest_edge_ = longest_tet_edge(mesh);
    if (!(options_.table_max_length > 0.0)) options_.table_max_length = longest_edge_;
    if (options_.segment == SegmentMode::table)
        table_ = build_segment_table(integrator_, range_, options_.table_size, options_.table_format,
                                     options_.table_max_length, table_ms_);
}

HavsFrameSetup setup_havs_frame(const HavsMesh& hm, const Camera& cam, int width, int height)
{
    HavsFrameSetup fs;
    fs.camera = cam;
    fs.width = width;
    fs.height = height;

    // Sort the faces front to back by squared centroid distance.
    auto t0 = Clock::now();
    std::vector<float> keys;
    std::vector<uint32_t> scratch;
    face_sort_keys(hm.points_f(), hm.faces(), glm::vec3(cam.eye - hm.origin()), keys);
    radix_sort_faces(keys, fs.order, scratch);
    fs.sort_ms = ms_since(t0);

    // The vertex stage for every point.
    t0 = Clock::now();
    fs.view = view_setup(cam, width, height, mesh_bounds(hm.mesh()), hm.origin());
    const Framebuffer fbuf{width, height, RenderTarget::fbo};
    const auto& pts = hm.points_f();
    fs.win.resize(pts.size());
    fs.win_d.resize(pts.size());
    fs.eye.resize(pts.size());
    tbb::parallel_for(std::size_t(0), pts.size(), [&](std::size_t i) {
        const auto clip = clip_position(fs.view.mvp, pts[i]);
        fs.win[i] = viewport_transform(clip.data(), fbuf);
        window_position_d(fs.view, hm.mesh().points[i] - hm.origin(), width, height, fs.win_d[i].x, fs.win_d[i].y,
                          fs.win_d[i].z);
        fs.eye[i] = eye_position(cam, hm.mesh().points[i]);
    });

    HavsFrameConstants& fc = fs.constants;
    fc.two_over_width = 2.0 / double(width);
    fc.two_over_height = 2.0 / double(height);
    const double aspect = double(width) / double(height);
    if (cam.orthographic) {
        fc.origin_x = 0.5 * cam.ortho_height * aspect;
        fc.origin_y = 0.5 * cam.ortho_height;
    }
    fc.threshold = hm.options().threshold;
    if (const PreintegrationTable* table = hm.table()) {
        fc.length_scale = table->length_scale();
        fc.length_bias = table->length_bias();
    }
    // Both gap modes nullify a segment longer than the mesh's longest edge: consecutive fragments inside the mesh lie
    // in one tetrahedron, so such a segment can only span a gap. With --gaps maxgap that is the whole rule (VTK's
    // heuristic); with exact gaps it is a safety net under the exit-face marking, for a fragment that rounding placed
    // just behind the exit face it belongs before (a ray grazing a silhouette edge).
    fc.max_gap = float(hm.longest_edge());
    fs.vertex_ms = ms_since(t0);
    return fs;
}

HavsFace havs_face_constants(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t f)
{
    const uint32_t* v = &hm.faces()[3 * std::size_t(f)];
    HavsFace face;
    for (int j = 0; j < 3; ++j) {
        face.q[j] = fs.eye[v[j]];
        face.v[j] = glm::dvec2(fs.win_d[v[j]].x, fs.win_d[v[j]].y);
        face.fx[j] = snap_to_fixed(fs.win[v[j]].x);
        face.fy[j] = snap_to_fixed(fs.win[v[j]].y);
        face.inv_w[j] = fs.win_d[v[j]].z;
        face.s[j] = hm.scalar_n(v[j]);
    }
    face.side = hm.exit_capable(f) ? kSideExit : kSideInterior;
    return face;
}

}  // namespace uvr::gpu
