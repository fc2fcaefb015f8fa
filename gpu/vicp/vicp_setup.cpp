#include "gpu/vicp/vicp_setup.h"

#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "gpu/pipeline/clip_position.h"
#include "gpu/pipeline/pixel_rays.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

VicpMesh::VicpMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                   const VicpOptions& options)
    : drawn_mesh_(mesh, topo, field),
      mesh_(drawn_mesh_.mesh()),
      topo_(drawn_mesh_.topology()),
      options_(options),
      integrator_(tf),
      range_(options.scalar_range.value_or(field_range(mesh_.fields.at(drawn_mesh_.field()))))
{
    if (options_.table_size < 2 || options_.table_size > 1024)
        throw InputError("", "--table-size must be between 2 and 1024");
    if (!(options_.threshold >= 0.0f && options_.threshold <= 1.0f))
        throw InputError("", "--threshold must be in [0, 1]");
    origin_ = mesh_bounds(mesh_).center();
    points_d_.reserve(mesh_.points.size());
    for (const auto& p : mesh_.points) points_d_.push_back(p - origin_);
    const double span = range_.hi > range_.lo ? range_.hi - range_.lo : 1.0;
    scalar_n_.reserve(mesh_.points.size());
    for (double s : mesh_.fields[drawn_mesh_.field()].values) scalar_n_.push_back((s - range_.lo) / span);
    // Orientation by the vertex program's own determinant, so that the sign it sees is the one the CPU checked.
    orientation_.resize(mesh_.tets.size());
    tbb::parallel_for(std::size_t(0), mesh_.tets.size(), [&](std::size_t i) {
        const Tet& t = mesh_.tets[i];
        const glm::dvec3 p[4] = {points_d_[t[0]], points_d_[t[1]], points_d_[t[2]], points_d_[t[3]]};
        const double s[4] = {0, 0, 0, 0};
        const double det = vicp_tet_constants(p, p, s, 0).det;
        orientation_[i] = det > 0.0 ? 1 : det < 0.0 ? 2 : 0;
    });
    for (uint8_t o : orientation_) drawn_ += o ? 1 : 0;
    boundary_.resize(mesh_.tets.size());
    for (std::size_t i = 0; i < mesh_.tets.size(); ++i) {
        uint8_t bits = 0;
        for (int f = 0; f < 4; ++f) {
            const int32_t fi = topo_.tet_faces[i][std::size_t(f)];
            if (fi >= 0 && topo_.faces[std::size_t(fi)].boundary()) bits |= uint8_t(1u << f);
        }
        boundary_[i] = bits;
    }
    if (!(options_.table_max_length > 0.0)) options_.table_max_length = longest_tet_edge(mesh_);
    if (options_.segment == SegmentMode::table)
        table_ = build_segment_table(integrator_, range_, options_.table_size, options_.table_format,
                                     options_.table_max_length, table_ms_);
}

bool VicpMesh::oriented(uint32_t t, VicpCell& out) const
{
    const Tet& c = mesh_.tets[t];
    const uint32_t b = boundary_[t];
    switch (orientation_[t]) {
    case 1: out = {c, b}; return true;
    case 2:  // swapping two points negates the determinant exactly; their faces' bits swap with them
        out = {{c[0], c[1], c[3], c[2]}, (b & 3u) | ((b & 4u) << 1) | ((b & 8u) >> 1)};
        return true;
    default: return false;
    }
}

VicpTet VicpMesh::constants(const VicpCell& cell, const std::vector<glm::dvec3>& snapped) const
{
    const Tet& t = cell.v;
    const glm::dvec3 shape[4] = {snapped[t[0]], snapped[t[1]], snapped[t[2]], snapped[t[3]]};
    const glm::dvec3 exact[4] = {points_d_[t[0]], points_d_[t[1]], points_d_[t[2]], points_d_[t[3]]};
    const double s[4] = {scalar_n_[t[0]], scalar_n_[t[1]], scalar_n_[t[2]], scalar_n_[t[3]]};
    return vicp_tet_constants(shape, exact, s, cell.boundary);
}

void VicpMesh::published_records(const VicpCell& cell, const std::vector<glm::vec3>& points_f,
                                 VicpPublishedVertex out[12]) const
{
    const Tet& t = cell.v;
    const glm::dvec3 p[4] = {points_d_[t[0]], points_d_[t[1]], points_d_[t[2]], points_d_[t[3]]};
    const double s[4] = {scalar_n_[t[0]], scalar_n_[t[1]], scalar_n_[t[2]], scalar_n_[t[3]]};
    const glm::vec3 g(vicp_published_gradient(p, s));
    glm::vec3 plane[4];
    for (int v = 0; v < 4; ++v) {
        const int* o = kVicpCorner[v];  // the face opposite v
        plane[v] = glm::vec3(vicp_published_plane(p[v], p[o[0]], p[o[1]], p[o[2]]));
    }
    for (int f = 0; f < 4; ++f)
        for (int j = 0; j < 3; ++j) {
            const int v = kVicpCorner[f][j];
            out[3 * f + j] = VicpPublishedVertex{points_f[t[std::size_t(v)]], float(s[v]), g, plane[v], float(j)};
        }
}

unsigned vicp_sent_faces(const VicpFrameSetup& fs, const VicpCell& cell, TriangleSubmission submission)
{
    if (submission == TriangleSubmission::all || fs.gpu_clipped) return 0xFu;
    const Framebuffer fbuf{fs.width, fs.height, RenderTarget::fbo};
    unsigned faces = 0;
    for (int f = 0; f < 4; ++f) {
        const WindowCoord wv[3] = {fs.win[cell.v[std::size_t(kVicpCorner[f][0])]],
                                   fs.win[cell.v[std::size_t(kVicpCorner[f][1])]],
                                   fs.win[cell.v[std::size_t(kVicpCorner[f][2])]]};
        if (!may_cover_pixel(wv)) continue;
        const TriangleSetup ts = setup_triangle(wv, fbuf);
        if (!ts.empty() && ts.facing == Facing::front && covers_any_pixel(ts)) faces |= 1u << f;
    }
    return faces;
}

VicpPublishedView vicp_published_view(const Camera& cam)
{
    return VicpPublishedView{cam.orthographic ? 1 : 0, glm::vec3(camera_frame(cam).f)};
}

double vicp_resident_bytes_per_cell(const VicpMesh& vm)
{
    const double per_point = 3 * sizeof(double) + sizeof(double);
    return per_point * double(vm.points_d().size()) / double(vm.mesh().tets.size());
}

double vicp_sent_bytes_per_cell(const VicpMesh& vm, uint64_t sent_faces)
{
    if (vm.options().interpolation == InterpolationMode::gpu)
        return double(kPublishedBytesSentPerFace) * double(sent_faces) / double(vm.mesh().tets.size());
    const double per_point = 3.0 * sizeof(double) + sizeof(glm::vec3);
    return (double(sizeof(VicpCell)) * double(vm.drawn_cells()) + per_point * double(vm.points_d().size())) /
           double(vm.mesh().tets.size());
}

namespace {

// The clip stage's additions to the frame: new vertices in the vertex buffer (ClipVertexBuffer), fan triangles of cut
// cells.
class FrameFans {
public:
    FrameFans(VicpFrameSetup& fs, const std::vector<uint8_t>& points_outside)
        : fs_(fs), buffer_(fs.view, fs.width, fs.height, fs.points_f, fs.win, points_outside)
    {
    }

    // The polygon `poly` as a fan of triangles of the cell at `slot`, drawn next.
    void add(const std::vector<ClipVertex>& poly, uint32_t slot)
    {
        if (poly.size() < 3) return;
        buffer_.add(poly, ids_, [](const ClipVertex&) {});
        for (std::size_t i = 1; i + 1 < ids_.size(); ++i) {
            const uint32_t v[4] = {ids_[0], ids_[i], ids_[i + 1], slot};
            fs_.fans.insert(fs_.fans.end(), v, v + 4);
            if (buffer_.gpu_clips(v[0], v[1], v[2])) ++fs_.gpu_clipped;
        }
    }

    const ClipVertexBuffer& buffer() const { return buffer_; }

private:
    VicpFrameSetup& fs_;
    ClipVertexBuffer buffer_;
    std::vector<uint32_t> ids_;
};

// The pixels' rays in the mesh's centred frame, the opacity kill and the table's length scale.
VicpFrameConstants frame_constants(const VicpMesh& vm, const Camera& cam, int width, int height)
{
    VicpFrameConstants fc;
    static_cast<PixelRays&>(fc) = pixel_rays(cam, width, height, vm.origin());
    fc.threshold = vm.options().threshold;
    if (const PreintegrationTable* table = vm.table()) {
        fc.length_scale = table->length_scale();
        fc.length_bias = table->length_bias();
    }
    return fc;
}

// The vertex stage's positions (as HAVS's: the frame's vertex buffer relative to the eye, float clip coordinates,
// llvmpipe's viewport transform). Snapping: each point at its own depth along the view direction, moved to the ray
// through its snapped window position (fixed value 256 * p is pixel p's centre, rasterize.h). Then which of the clip
// stage's planes each point, so moved, lies outside of (`clipper` reads `moved` and `codes`).
void vertex_stage(const VicpMesh& vm, const Camera& cam, const CameraFrame& cf, const VicpClipper& clipper,
                  VicpFrameSetup& fs, std::vector<glm::dvec3>& moved, std::vector<uint8_t>& codes,
                  std::vector<uint8_t>& gpu_outside)
{
    const auto& mesh = vm.mesh();
    const std::size_t npts = mesh.points.size();
    const VicpFrameConstants& fc = fs.constants;
    const Framebuffer fbuf{fs.width, fs.height, RenderTarget::fbo};
    fs.points_f.resize(npts);
    fs.win.resize(npts);
    fs.snapped.resize(npts);
    tbb::parallel_for(std::size_t(0), npts, [&](std::size_t i) {
        fs.points_f[i] = glm::vec3(mesh.points[i] - cam.eye);
        const auto clip = clip_position(fs.view.mvp, fs.points_f[i]);
        fs.win[i] = viewport_transform(clip.data(), fbuf);
        gpu_outside[i] = outside_gpu_frustum(clip) ? 1 : 0;
        if (gpu_outside[i]) {
            fs.snapped[i] = vm.points_d()[i];
        } else {
            const double ndc_x = (double(snap_to_fixed(fs.win[i].x)) / 256.0 + 0.5) * fc.two_over_width - 1.0;
            const double ndc_y = (double(snap_to_fixed(fs.win[i].y)) / 256.0 + 0.5) * fc.two_over_height - 1.0;
            const glm::dvec3 q = vm.points_d()[i] - fc.eye;
            const double depth = (q.x * cf.f.x + q.y * cf.f.y) + q.z * cf.f.z;
            const glm::dvec3 o = fc.eye + ndc_x * fc.ray_ox + ndc_y * fc.ray_oy;
            const glm::dvec3 d = fc.ray_d0 + ndc_x * fc.ray_dx + ndc_y * fc.ray_dy;
            fs.snapped[i] = o + depth * d;
        }
        moved[i] = fs.snapped[i] - fc.eye;
        codes[i] = uint8_t(outcode(clipper.planes(), clip_vertex(fs.view, moved[i], 0.0).c));
    });
}

// The cell order: by centroid, or MPVONC's (which starts from the centroid order).
void cell_order_stage(const VicpMesh& vm, const Camera& cam, const CameraFrame& cf, const VicpClipper& clipper,
                      VicpFrameSetup& fs)
{
    const auto& mesh = vm.mesh();
    const VicpFrameConstants& fc = fs.constants;
    std::vector<uint32_t> centroid;
    centroid_cell_order(fs.points_f, mesh.tets, glm::vec3(0.0f), glm::vec3(cf.f), centroid);
    if (vm.options().order == CellOrder::centroid) {
        fs.order = std::move(centroid);
    } else {
        const CellOrderFrame frame{&cam, vm.origin(), &fc, &fs.win, &fs.snapped, &clipper, fs.width, fs.height};
        mpvonc_cell_order(mesh, vm.topology(), frame, centroid, fs.order, fs.order_stats);
    }
}

// ProjectTet: the drawn cells in order; the clip stage for those the view cuts.
void project_stage(const VicpMesh& vm, const VicpClipper& clipper, const std::vector<uint8_t>& codes,
                   const std::vector<uint8_t>& gpu_outside, VicpFrameSetup& fs)
{
    fs.stream.reserve(vm.drawn_cells());
    FrameFans fans(fs, gpu_outside);
    std::vector<ClipVertex> poly, scratch;
    constexpr unsigned kNearBit = 1u << kClipNear;
    for (uint32_t t : fs.order) {
        VicpCell c;
        if (!vm.oriented(t, c)) continue;
        const Tet& v = c.v;
        const unsigned any = codes[v[0]] | codes[v[1]] | codes[v[2]] | codes[v[3]];
        const unsigned all = codes[v[0]] & codes[v[1]] & codes[v[2]] & codes[v[3]];
        if (any == 0) {
            for (int f = 0; f < 4; ++f)
                if (fans.buffer().gpu_clips(v[kVicpCorner[f][0]], v[kVicpCorner[f][1]], v[kVicpCorner[f][2]]))
                    ++fs.gpu_clipped;
            fs.stream.push_back(c);
            continue;
        }
        if (all != 0) {
            ++fs.culled_cells;
            continue;
        }
        const uint32_t slot = uint32_t(fs.stream.size());
        fs.stream.push_back(c);
        const uint32_t first = uint32_t(fs.fan_triangles());
        for (int f = 0; f < 4; ++f) {
            const uint32_t corners[3] = {v[kVicpCorner[f][0]], v[kVicpCorner[f][1]], v[kVicpCorner[f][2]]};
            clipper.clip_triangle(corners, poly, scratch);
            fans.add(poly, slot);
        }
        if (any & kNearBit) {
            clipper.near_face(v.data(), poly, scratch);
            if (poly.size() >= 3) ++fs.near_sections;
            fans.add(poly, slot);
        }
        fs.cuts.push_back({slot, first, uint32_t(fs.fan_triangles()) - first});
        ++fs.clipped_cells;
    }
}

}  // namespace

VicpFrameSetup setup_vicp_frame(const VicpMesh& vm, const Camera& cam, int width, int height)
{
    VicpFrameSetup fs;
    fs.camera = cam;
    fs.width = width;
    fs.height = height;
    const auto& mesh = vm.mesh();
    const std::size_t npts = mesh.points.size();

    // The frame's constants and view, then the vertex stage; the clipper serves it, the cell order and ProjectTet.
    auto t0 = Clock::now();
    const CameraFrame cf = camera_frame(cam);
    fs.constants = frame_constants(vm, cam, width, height);
    fs.view = view_setup(cam, width, height, mesh_bounds(mesh), cam.eye);
    std::vector<glm::dvec3> moved(npts);  // relative to the eye
    std::vector<uint8_t> codes(npts), gpu_outside(npts);
    const VicpClipper clipper(fs.view, width, height, moved, codes);  // reads moved and codes, filled below
    vertex_stage(vm, cam, cf, clipper, fs, moved, codes, gpu_outside);
    fs.vertex_ms = ms_since(t0);

    t0 = Clock::now();
    cell_order_stage(vm, cam, cf, clipper, fs);
    fs.sort_ms = ms_since(t0);

    t0 = Clock::now();
    project_stage(vm, clipper, codes, gpu_outside, fs);
    fs.project_ms = ms_since(t0);
    return fs;
}

}  // namespace uvr::gpu
