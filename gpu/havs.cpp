#include "gpu/havs.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "gpu/face_sort.h"
#include "gpu/havs_vertex.h"
#include "gpu/rasterize.h"
#include "reference/error.h"

namespace uvr::gpu {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Screen tiles processed in parallel. Within a tile, faces are applied in sorted order to every pixel, exactly as a
// GPU orders fragments per pixel, so the result does not depend on the number of threads.
constexpr int kTile = 64;

}  // namespace

HavsRenderer::HavsRenderer(const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                           const TransferFunction& tf, const HavsOptions& options)
    : mesh_(mesh), options_(options), integrator_(tf), range_(field_range(mesh.fields.at(field)))
{
    if (options_.k < 1 || options_.k > kMaxK)
        throw InputError("", "--k must be between 1 and " + std::to_string(kMaxK));
    points_f_.reserve(mesh.points.size());
    for (const auto& p : mesh.points) points_f_.push_back(glm::vec3(p));
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
        boundary_.push_back(f.boundary() && !seam ? 1 : 0);
    }
    for (const Tet& t : mesh.tets) {
        if (is_degenerate(mesh, t)) continue;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b)
                longest_edge_ = std::max(longest_edge_, glm::length(mesh.points[t[a]] - mesh.points[t[b]]));
    }
    if (options_.segment == SegmentMode::table) {
        const auto t0 = Clock::now();
        PreintegrationConfig cfg;
        cfg.scalar_resolution = cfg.length_resolution = options_.table_size;
        cfg.format = options_.table_format;
        if (!(options_.table_max_length > 0.0)) options_.table_max_length = longest_edge_;
        cfg.max_length = options_.table_max_length;
        table_ = std::make_unique<PreintegrationTable>(integrator_, range_, cfg);
        table_ms_ = ms_since(t0);
    }
}

HavsRenderer::~HavsRenderer() = default;

HavsFrame HavsRenderer::render(const Camera& cam, int width, int height) const
{
    HavsFrame out;
    HavsStats& st = out.stats;
    st.table_ms = table_ms_;
    const std::size_t nfaces = faces_.size() / 3;
    st.faces = nfaces;

    // CPU stage: sort the faces front to back by squared centroid distance.
    auto t0 = Clock::now();
    std::vector<float> keys;
    std::vector<uint32_t> order, scratch;
    face_sort_keys(points_f_, faces_, glm::vec3(cam.eye), keys);
    radix_sort_faces(keys, order, scratch);
    st.sort_ms = ms_since(t0);

    // Vertex stage for every point, and the frame's constants.
    t0 = Clock::now();
    const ViewSetup vs = view_setup(cam, width, height, mesh_bounds(mesh_));
    const Framebuffer fbuf{width, height, RenderTarget::fbo};
    std::vector<WindowCoord> win(points_f_.size());   // what the rasterizer receives (float pipeline)
    std::vector<glm::dvec3> win_d(points_f_.size());  // x, y, 1 / w in double (the fragment stage's geometry)
    tbb::parallel_for(std::size_t(0), points_f_.size(), [&](std::size_t i) {
        const auto clip = clip_position(vs.mvp, points_f_[i]);
        win[i] = viewport_transform(clip.data(), fbuf);
        window_position_d(vs, mesh_.points[i], width, height, win_d[i].x, win_d[i].y, win_d[i].z);
    });
    HavsFrameConstants fc;
    fc.two_over_width = 2.0 / double(width);
    fc.two_over_height = 2.0 / double(height);
    const double aspect = double(width) / double(height);
    if (cam.orthographic) {
        fc.origin_x = 0.5 * cam.ortho_height * aspect;
        fc.origin_y = 0.5 * cam.ortho_height;
    }
    fc.threshold = options_.threshold;
    if (table_) {
        fc.length_scale = table_->length_scale();
        fc.length_bias = table_->length_bias();
    }
    // Both gap modes nullify a segment longer than the mesh's longest edge: consecutive fragments inside the mesh lie
    // in one tetrahedron, so such a segment can only span a gap. With --gaps maxgap that is the whole rule (VTK's
    // heuristic); with exact gaps it is a safety net under the exit-face marking, for a fragment that rounding placed
    // just behind the exit face it belongs before (a ray grazing a silhouette edge).
    fc.max_gap = float(longest_edge_);

    // Bin the sorted faces into screen tiles by their window-space bounding boxes.
    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    std::vector<std::vector<uint32_t>> bins(std::size_t(tiles_x) * std::size_t(tiles_y));
    for (uint32_t f : order) {
        const uint32_t* v = &faces_[3 * std::size_t(f)];
        float x0 = win[v[0]].x, x1 = x0, y0 = win[v[0]].y, y1 = y0;
        for (int j = 1; j < 3; ++j) {
            x0 = std::min(x0, win[v[j]].x);
            x1 = std::max(x1, win[v[j]].x);
            y0 = std::min(y0, win[v[j]].y);
            y1 = std::max(y1, win[v[j]].y);
        }
        if (!(x1 >= 0.0f && y1 >= 0.0f && x0 <= float(width) && y0 <= float(height))) continue;
        const int tx0 = std::clamp(int(std::floor(x0)) / kTile, 0, tiles_x - 1);
        const int tx1 = std::clamp(int(std::floor(x1)) / kTile, 0, tiles_x - 1);
        const int ty0 = std::clamp(int(std::floor(y0)) / kTile, 0, tiles_y - 1);
        const int ty1 = std::clamp(int(std::floor(y1)) / kTile, 0, tiles_y - 1);
        for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx) bins[std::size_t(ty) * std::size_t(tiles_x) + std::size_t(tx)].push_back(f);
    }
    st.setup_ms = ms_since(t0);

    // The segment shader: the table as llvmpipe samples it, or the exact integral in double.
    const LlvmpipeCpu cpu = host_llvmpipe_cpu();
    const double span = range_.hi > range_.lo ? range_.hi - range_.lo : 1.0;
    const SegmentShader shade = table_ ? SegmentShader([&](float uf, float ub, float tz, float) {
        return table_->sample(uf, ub, tz, cpu, options_.filter);
    })
                                       : SegmentShader([&](float uf, float ub, float, float length) {
                                             const glm::dvec4 c = integrator_.integrate(
                                                 range_.lo + double(uf) * span, range_.lo + double(ub) * span,
                                                 double(length));
                                             return glm::vec4(c);
                                         });

    // Per-pixel state, GL rows (from the bottom).
    const int k = options_.k;
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    std::vector<KEntry> kbuf(npix * std::size_t(k), kEmptyEntry);
    std::vector<glm::vec4> fb(npix, glm::vec4(0.0f));
    std::vector<KBufferDiagnostics> diag(npix);

    t0 = Clock::now();
    tbb::parallel_for(std::size_t(0), bins.size(), [&](std::size_t b) {
        const int tx = int(b % std::size_t(tiles_x)), ty = int(b / std::size_t(tiles_x));
        const int px0 = tx * kTile, px1 = std::min(width, px0 + kTile) - 1;
        const int py0 = ty * kTile, py1 = std::min(height, py0 + kTile) - 1;
        for (uint32_t f : bins[b]) {
            const uint32_t* v = &faces_[3 * std::size_t(f)];
            const WindowCoord wv[3] = {win[v[0]], win[v[1]], win[v[2]]};
            const TriangleSetup ts = setup_triangle(wv, fbuf);
            if (ts.empty()) continue;
            // Flat per-face constants, in double, rounded once (what the CPU would upload).
            HavsFace face;
            const glm::dvec3 q0 = eye_position(cam, mesh_.points[v[0]]), q1 = eye_position(cam, mesh_.points[v[1]]),
                             q2 = eye_position(cam, mesh_.points[v[2]]);
            face.q[0] = q0;
            face.q[1] = q1;
            face.q[2] = q2;
            for (int j = 0; j < 3; ++j) {
                face.v[j] = glm::dvec2(win_d[v[j]].x, win_d[v[j]].y);
                face.fx[j] = snap_to_fixed(wv[j].x);
                face.fy[j] = snap_to_fixed(wv[j].y);
                face.inv_w[j] = win_d[v[j]].z;
                face.s[j] = scalar_n_[v[j]];
            }
            // A boundary face is oriented outward, so it is an exit face when the rasterizer sees it back-facing
            // (clockwise in window coordinates: gl_FrontFacing false). The rasterizer's facing comes from the
            // snapped area, so it agrees with the coverage the fragments come from even for slivers.
            if (options_.gaps == GapMode::exact && boundary_[f] && ts.facing == Facing::back) face.side = -1.0f;
            const int ya = std::max(ts.y0, py0), yb = std::min(ts.y1, py1);
            for (int py = ya; py <= yb; ++py) {
                int first = 0, last = -1;
                row_span(ts, py, first, last);
                first = std::max(first, px0);
                last = std::min(last, px1);
                for (int px = first; px <= last; ++px) {
                    const std::size_t p = std::size_t(py) * std::size_t(width) + std::size_t(px);
                    const KEntry e = havs_fragment_entry(fc, face, px, py);
                    havs_kbuffer(fc, e, &kbuf[p * std::size_t(k)], k, fb[p], shade, &diag[p]);
                }
            }
        }
    });
    st.raster_fragment_ms = ms_since(t0);

    // Flush passes: k full-screen passes of the flush fragment composite what is left.
    t0 = Clock::now();
    tbb::parallel_for(std::size_t(0), npix, [&](std::size_t p) {
        for (int pass = 0; pass < k; ++pass)
            havs_kbuffer(fc, kFlushFragment, &kbuf[p * std::size_t(k)], k, fb[p], shade, &diag[p]);
    });
    st.flush_ms = ms_since(t0);

    // Read back, flipping GL rows to SPEC rows.
    out.image = Image(width, height);
    out.fragments.resize(npix);
    out.max_held.resize(npix);
    out.ordering_errors.resize(npix);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
            const int j = height - 1 - y;
            float* px = out.image.pixel(x, j);
            for (int c = 0; c < 4; ++c) px[c] = fb[p][c];
            const std::size_t q = std::size_t(j) * std::size_t(width) + std::size_t(x);
            out.fragments[q] = diag[p].fragments;
            out.max_held[q] = diag[p].max_held;
            out.ordering_errors[q] = diag[p].ordering_errors;
            st.fragments += diag[p].fragments;
            st.ordering_errors += diag[p].ordering_errors;
            st.max_fragments = std::max(st.max_fragments, diag[p].fragments);
            st.max_held = std::max(st.max_held, diag[p].max_held);
        }
    return out;
}

}  // namespace uvr::gpu
