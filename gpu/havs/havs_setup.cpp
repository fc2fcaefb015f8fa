#include "gpu/havs/havs_setup.h"

#include <algorithm>
#include <chrono>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "gpu/pipeline/clip_position.h"
#include "gpu/pipeline/clip.h"
#include "gpu/pipeline/face_sort.h"
#include "reference/error.h"
#include "reference/field.h"
#include "reference/timing.h"

namespace uvr::gpu {

HavsMesh::HavsMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                   const HavsOptions& options)
    : drawn_mesh_(mesh, topo, field),
      mesh_(drawn_mesh_.mesh()),
      options_(options),
      integrator_(tf),
      range_(options.scalar_range.value_or(field_range(mesh_.fields.at(drawn_mesh_.field()))))
{
    const double span = range_.hi > range_.lo ? range_.hi - range_.lo : 1.0;
    for (double s : mesh_.fields[drawn_mesh_.field()].values) scalar_n_.push_back((s - range_.lo) / span);
    add_faces(drawn_mesh_.topology());
    if (options_.entries == EntryEncoding::paper &&
        (options_.interpolation != InterpolationMode::gpu || options_.gaps != GapMode::exact))
        throw InputError("",
                         "--entries paper needs the paper's interpolation (--interpolation gpu) and exact gaps "
                         "(--gaps exact): it marks exit faces by a negative scalar, and the paper's program has "
                         "no maximum-gap rule");
    longest_edge_ = longest_tet_edge(mesh_);
    if (!(options_.table_max_length > 0.0)) options_.table_max_length = longest_edge_;
    if (options_.segment == SegmentMode::table)
        table_ = build_segment_table(integrator_, range_, options_.table_size, options_.table_format,
                                     options_.table_max_length, table_ms_);
}

// The unique faces with their boundary marks, then each face across which the field jumps again, with its second
// tetrahedron's points: two coincident faces, each with its own side's scalars, that the k-buffer orders (--ties
// facing: the exact order). A boundary face made only of seam points lies on a seam inside the mesh (the O-grid seam of
// docs/data-model.md), not on the mesh's surface, so it is never a gap's start.
void HavsMesh::add_faces(const MeshTopology& topo)
{
    const std::vector<uint8_t> seam_point = seam_points(mesh_, topo);
    const std::vector<uint8_t> jump = field_jump_faces(mesh_, topo, mesh_.fields[drawn_mesh_.field()]);
    faces_.reserve(topo.faces.size() * 3);
    boundary_.reserve(topo.faces.size());
    for (const Face& f : topo.faces) {
        faces_.insert(faces_.end(), f.v.begin(), f.v.end());
        const bool seam = seam_point[f.v[0]] && seam_point[f.v[1]] && seam_point[f.v[2]];
        boundary_.push_back(options_.gaps == GapMode::exact && f.boundary() && !seam ? 1 : 0);
    }
    for (std::size_t i = 0; i < topo.faces.size(); ++i) {
        if (!jump[i]) continue;
        const auto b = std::size_t(topo.faces[i].tet[1]);
        int local = 0;
        while (topo.tet_faces[b][std::size_t(local)] != int32_t(i)) ++local;
        const auto v = tet_face(mesh_.tets[b], local);
        faces_.insert(faces_.end(), v.begin(), v.end());
        boundary_.push_back(0);
    }
}

namespace {

// The clip stage's frame vertices (ClipVertexBuffer, with HAVS's own per-vertex data) and triangles.
class FrameVertices {
public:
    // points_outside: per mesh point, whether the GPU's frustum test would clip it.
    FrameVertices(HavsFrameSetup& fs, const std::vector<uint8_t>& points_outside)
        : fs_(fs), frame_(camera_frame(fs.camera)),
          buffer_(fs.view, fs.width, fs.height, fs.points_f, fs.win, points_outside)
    {
    }

    // Draws triangle `id` (vertices v), counting it in gpu_clipped when the GPU would clip one of its vertices.
    void draw(uint32_t id, const uint32_t* v)
    {
        fs_.draw.push_back(id);
        if (buffer_.gpu_clips(v[0], v[1], v[2])) ++fs_.gpu_clipped;
    }

    // The clipped polygon as a fan of extra triangles lying on `face`, drawn next.
    void draw_fan(const std::vector<ClipVertex>& poly, uint32_t face)
    {
        if (poly.size() < 3) return;
        buffer_.add(poly, ids_, [&](const ClipVertex& v) {
            glm::dvec3 wd;
            window_position_d(fs_.view, v.p, fs_.width, fs_.height, wd.x, wd.y, wd.z);
            fs_.win_d.push_back(wd);
            fs_.eye.push_back(eye_space(frame_, v.p));
            fs_.extra_s.push_back(v.s);
        });
        for (std::size_t i = 1; i + 1 < ids_.size(); ++i) {
            const uint32_t v[3] = {ids_[0], ids_[i], ids_[i + 1]};
            const uint32_t id = fs_.mesh_faces + uint32_t(fs_.extra_face.size());
            fs_.extra.insert(fs_.extra.end(), v, v + 3);
            fs_.extra_face.push_back(face);
            draw(id, v);
        }
    }

private:
    HavsFrameSetup& fs_;
    CameraFrame frame_;
    ClipVertexBuffer buffer_;
    std::vector<uint32_t> ids_;
};

}  // namespace

namespace {

// The faces front to back by squared centroid distance (fs.points_f: relative to the eye).
std::vector<uint32_t> sorted_faces(const HavsMesh& hm, const HavsFrameSetup& fs)
{
    std::vector<float> keys;
    std::vector<uint32_t> order, scratch;
    face_sort_keys(fs.points_f, hm.faces(), glm::vec3(0.0f), keys);
    radix_sort_faces(keys, order, scratch);
    return order;
}

// The vertex stage for every point, and which planes of the clip stage each point lies outside of (`codes`) and
// whether it lies outside the GPU's own frustum (`gpu_outside`).
void vertex_stage(const HavsMesh& hm, const ClipPlanes& planes, HavsFrameSetup& fs, std::vector<uint8_t>& codes,
                  std::vector<uint8_t>& gpu_outside)
{
    const TetMesh& mesh = hm.mesh();
    const Camera& cam = fs.camera;
    const std::size_t npts = mesh.points.size();
    fs.view = view_setup(cam, fs.width, fs.height, mesh_bounds(mesh), cam.eye);
    // --interpolation gpu runs the paper's vertex program: DP4 rows on the driver's product (clip_position.h).
    if (hm.options().interpolation == InterpolationMode::gpu) fs.view.program = VertexProgram::published;
    const CameraFrame frame = camera_frame(cam);
    const Framebuffer fbuf{fs.width, fs.height, RenderTarget::fbo};
    fs.win.resize(npts);
    fs.win_d.resize(npts);
    fs.eye.resize(npts);
    codes.resize(npts);
    gpu_outside.resize(npts);
    tbb::parallel_for(std::size_t(0), npts, [&](std::size_t i) {
        const auto clip = vertex_position(fs.view, fs.points_f[i]);
        fs.win[i] = viewport_transform(clip.data(), fbuf);
        const glm::dvec3 d = mesh.points[i] - cam.eye;
        window_position_d(fs.view, d, fs.width, fs.height, fs.win_d[i].x, fs.win_d[i].y, fs.win_d[i].z);
        fs.eye[i] = eye_space(frame, d);
        codes[i] = uint8_t(outcode(planes, clip_vertex(fs.view, d, 0.0).c));
        gpu_outside[i] = outside_gpu_frustum(clip) ? 1 : 0;
    });
}

// The clip stage. First the near plane's sections of the cells it cuts (the nearest surfaces, in cell order), then
// the faces in sorted order: inside every plane as they are, wholly outside one plane not at all, the others as the
// fans of their clipped polygons.
void clip_stage(const HavsMesh& hm, const ClipPlanes& planes, const std::vector<uint32_t>& order,
                const std::vector<uint8_t>& codes, const std::vector<uint8_t>& gpu_outside, HavsFrameSetup& fs)
{
    const TetMesh& mesh = hm.mesh();
    FrameVertices frame_vertices(fs, gpu_outside);
    auto clip_vertex_of = [&](uint32_t i) {
        ClipVertex v = clip_vertex(fs.view, mesh.points[i] - fs.camera.eye, hm.scalar_n(i));
        v.id = i;
        return v;
    };
    std::vector<ClipVertex> poly, poly_scratch;
    constexpr unsigned kNearBit = 1u << kClipNear;
    if (fs.view.near_cuts) {
        for (const Tet& t : mesh.tets) {
            const unsigned any = codes[t[0]] | codes[t[1]] | codes[t[2]] | codes[t[3]];
            const unsigned all = codes[t[0]] & codes[t[1]] & codes[t[2]] & codes[t[3]];
            if (!(any & kNearBit) || (all & kNearBit) || (all & ~kNearBit)) continue;
            const ClipVertex v[4] = {clip_vertex_of(t[0]), clip_vertex_of(t[1]), clip_vertex_of(t[2]),
                                     clip_vertex_of(t[3])};
            near_section(fs.view, planes, v, poly);
            clip_polygon(fs.view, planes, poly, poly_scratch, kClipLeft);
            if (poly.size() >= 3) ++fs.near_sections;
            frame_vertices.draw_fan(poly, kNearSection);
        }
    }
    fs.draw.reserve(fs.draw.size() + order.size());
    const std::vector<uint32_t>& faces = hm.faces();
    for (uint32_t f : order) {
        const uint32_t* v = &faces[3 * std::size_t(f)];
        const unsigned any = codes[v[0]] | codes[v[1]] | codes[v[2]];
        const unsigned all = codes[v[0]] & codes[v[1]] & codes[v[2]];
        if (any == 0) {
            frame_vertices.draw(f, v);
        } else if (all != 0) {
            ++fs.culled_faces;
        } else {
            ++fs.clipped_faces;
            poly.assign({clip_vertex_of(v[0]), clip_vertex_of(v[1]), clip_vertex_of(v[2])});
            clip_polygon(fs.view, planes, poly, poly_scratch);
            frame_vertices.draw_fan(poly, f);
        }
    }
}

// The constants every fragment of the frame reads.
HavsFrameConstants frame_constants(const HavsMesh& hm, const Camera& cam, int width, int height)
{
    HavsFrameConstants fc;
    fc.two_over_width = 2.0 / double(width);
    fc.two_over_height = 2.0 / double(height);
    const double aspect = double(width) / double(height);
    fc.orthographic = cam.orthographic;
    if (cam.orthographic) {
        fc.origin_x = 0.5 * cam.ortho_height * aspect;
        fc.origin_y = 0.5 * cam.ortho_height;
    }
    fc.threshold = hm.options().threshold;
    fc.paper_entries = hm.options().entries == EntryEncoding::paper;
    if (const PreintegrationTable* table = hm.table()) {
        fc.length_scale = table->length_scale();
        fc.length_bias = table->length_bias();
    }
    // --gaps maxgap (VTK's heuristic): a segment longer than the mesh's longest edge contributes nothing, since
    // consecutive fragments inside the mesh lie in one tetrahedron and a longer segment can only span a gap. Exact gaps
    // use the exit-face marks alone (0: no limit), so that docs/spec.md §6's comparison of the two compares the rules
    // and not the heuristic with itself plus more: a real segment longer than the longest edge (an ordering error's,
    // when k is too small) is composited.
    fc.max_gap = hm.options().gaps == GapMode::maxgap ? float(hm.longest_edge()) : 0.0f;
    return fc;
}

}  // namespace

HavsFrameSetup setup_havs_frame(const HavsMesh& hm, const Camera& cam, int width, int height)
{
    HavsFrameSetup fs;
    fs.camera = cam;
    fs.width = width;
    fs.height = height;
    const TetMesh& mesh = hm.mesh();
    const std::size_t npts = mesh.points.size();
    fs.mesh_faces = uint32_t(hm.face_count());

    // The frame's vertex buffer: positions relative to the eye, in float. Relative to the eye, a clip coordinate's
    // float rounding is a fixed fraction of its w, however near the eye the point lies or far the mesh from the
    // world's origin (coordinates at 1e8 with features at 1e-3 keep their features), as the clip stage needs. Then
    // the faces sorted.
    auto t0 = Clock::now();
    fs.points_f.resize(npts);
    tbb::parallel_for(std::size_t(0), npts,
                      [&](std::size_t i) { fs.points_f[i] = glm::vec3(mesh.points[i] - cam.eye); });
    const std::vector<uint32_t> order = sorted_faces(hm, fs);
    fs.sort_ms = ms_since(t0);

    t0 = Clock::now();
    const ClipPlanes planes = inner_clip_planes(width, height);
    std::vector<uint8_t> codes, gpu_outside;
    vertex_stage(hm, planes, fs, codes, gpu_outside);
    fs.vertex_ms = ms_since(t0);

    t0 = Clock::now();
    clip_stage(hm, planes, order, codes, gpu_outside, fs);
    fs.clip_ms = ms_since(t0);

    // The paper's scalar attribute for every frame vertex (--interpolation gpu).
    if (hm.options().interpolation == InterpolationMode::gpu) {
        fs.s_f.resize(fs.points_f.size());
        for (std::size_t i = 0; i < fs.s_f.size(); ++i)
            fs.s_f[i] = float(i < npts ? hm.scalar_n(i) : fs.extra_s[i - npts]);
    }
    fs.constants = frame_constants(hm, cam, width, height);
    return fs;
}

HavsPaperVertices havs_paper_vertices(const HavsFrameSetup& fs)
{
    // The clip position as the paper's vertex program computes it (setup_vertex: the window position and 1 / w), and
    // the eye-space position by the same DP4s with state.matrix.modelview.
    const Framebuffer fbuf{fs.width, fs.height, RenderTarget::fbo};
    HavsPaperVertices out;
    out.eye.resize(fs.points_f.size());
    out.setup.resize(fs.points_f.size());
    tbb::parallel_for(std::size_t(0), fs.points_f.size(), [&](std::size_t i) {
        const auto clip = vertex_position(fs.view, fs.points_f[i]);
        out.setup[i] = setup_vertex(clip.data(), fbuf);
        out.eye[i] = eye_position(fs.view, fs.points_f[i]);
    });
    return out;
}

HavsFace havs_face_constants(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t id)
{
    const uint32_t* v = fs.triangle(hm, id);
    const std::size_t npts = hm.mesh().points.size();
    HavsFace face;
    for (int j = 0; j < 3; ++j) {
        face.q[j] = glm::vec3(fs.eye[v[j]]);  // rounded to float once (HavsFace)
        face.v[j] = glm::dvec2(fs.win_d[v[j]].x, fs.win_d[v[j]].y);
        face.fx[j] = snap_to_fixed(fs.win[v[j]].x);
        face.fy[j] = snap_to_fixed(fs.win[v[j]].y);
        face.inv_w[j] = float(fs.win_d[v[j]].z);
        face.s[j] = float(v[j] < npts ? hm.scalar_n(v[j]) : fs.extra_s[v[j] - npts]);
    }
    face.side = havs_face_side(hm, fs, id);
    return face;
}

float havs_face_side(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t id)
{
    const uint32_t source = id < fs.mesh_faces ? id : fs.extra_face[id - fs.mesh_faces];
    return source != kNearSection && hm.exit_capable(source) ? kSideExit : kSideInterior;
}

bool havs_paper_exit(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t id)
{
    if (havs_face_side(hm, fs, id) != kSideExit) return false;
    const uint32_t* v = fs.triangle(hm, id);
    const WindowCoord wv[3] = {fs.win[v[0]], fs.win[v[1]], fs.win[v[2]]};
    return setup_triangle(wv, Framebuffer{fs.width, fs.height, RenderTarget::fbo}).facing == Facing::back;
}

void havs_sent_triangles(const HavsMesh& hm, const HavsFrameSetup& fs, std::size_t first, std::size_t count,
                         TriangleSubmission submission, std::vector<uint32_t>& out)
{
    const uint32_t* ids = fs.draw.data() + first;
    out.assign(ids, ids + count);
    if (submission == TriangleSubmission::all || fs.gpu_clipped != 0) return;
    const Framebuffer fbuf{fs.width, fs.height, RenderTarget::fbo};
    std::vector<uint8_t> covered(count);
    for_each_triangle(hm, fs, ids, count, [&](std::size_t i, const uint32_t* v) {
        const WindowCoord wv[3] = {fs.win[v[0]], fs.win[v[1]], fs.win[v[2]]};
        covered[i] = may_cover_pixel(wv) && covers_any_pixel(setup_triangle(wv, fbuf)) ? 1 : 0;
    });
    std::size_t n = 0;
    for (std::size_t i = 0; i < count; ++i)
        if (covered[i]) out[n++] = ids[i];
    out.resize(n);
}

}  // namespace uvr::gpu
