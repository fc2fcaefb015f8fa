#include "reference/ray_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>
#include <glm/vec2.hpp>
#include <emmintrin.h>
#include <glm/geometric.hpp>

#include "reference/error.h"
#include "reference/field.h"

namespace uvr {

namespace {

// Outward normal (not normalized) of a boundary face.
glm::dvec3 face_normal(const TetMesh& m, const std::array<uint32_t, 3>& f)
{
    return glm::cross(m.points[f[1]] - m.points[f[0]], m.points[f[2]] - m.points[f[0]]);
}

}  // namespace

// Embree holds the boundary faces as float triangles, shifted by the bounds' centre so that float keeps as many bits
// as it can of the geometry. It is asked only "which boundary face does the ray enter next"; every distance the
// integral uses is recomputed in double from that face's plane.
struct RayIntegrator::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    glm::dvec3 shift{0.0};
    std::vector<int32_t> face_of_prim;  // Embree primitive -> index into topo.faces
    double slack = 0.0;                 // how far before t_min a re-entry may lie (rounding of coplanar faces)
    double scale = 0.0;                 // the bounds' diagonal

    ~Embree()
    {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

// The boundary faces one ray has entered or left through: most rays use a few, so they are held in place, and only a
// ray through many gaps allocates.
class RayIntegrator::UsedFaces {
public:
    bool empty() const { return n_ == 0; }
    void push_back(int32_t face)
    {
        if (n_ < kInPlace)
            in_place_[n_] = face;
        else
            more_.push_back(face);
        ++n_;
    }
    bool contains(int32_t face) const
    {
        const std::size_t k = std::min(n_, kInPlace);
        return std::find(in_place_.begin(), in_place_.begin() + std::ptrdiff_t(k), face) !=
                   in_place_.begin() + std::ptrdiff_t(k) ||
               std::find(more_.begin(), more_.end(), face) != more_.end();
    }

private:
    static constexpr std::size_t kInPlace = 16;
    std::array<int32_t, kInPlace> in_place_;
    std::vector<int32_t> more_;
    std::size_t n_ = 0;
};

namespace {

// The intersect context carries what the filter needs to accept only faces the ray really enters next.
struct EntryContext {
    RTCIntersectContext base;  // first member: Embree hands the filter a pointer to it
    const TetMesh* mesh;
    const MeshTopology* topo;
    const std::vector<int32_t>* face_of_prim;
    glm::dvec3 origin, dir;
    double t_min, slack;
    const RayIntegrator::UsedFaces* used;  // boundary faces this ray already entered or left through
};

void entry_filter(const RTCFilterFunctionNArguments* args)
{
    auto* ctx = reinterpret_cast<EntryContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        const int32_t face = (*ctx->face_of_prim)[RTCHitN_primID(args->hit, args->N, i)];
        const Face& f = ctx->topo->faces[std::size_t(face)];
        const glm::dvec3 n = face_normal(*ctx->mesh, f.v);
        const double dn = glm::dot(n, ctx->dir);
        bool ok = dn < 0.0;  // entering: against the outward normal
        if (ok) {
            const double t = glm::dot(n, ctx->mesh->points[f.v[0]] - ctx->origin) / dn;
            ok = t >= ctx->t_min - ctx->slack && !ctx->used->contains(face);
        }
        if (!ok) args->valid[i] = 0;
    }
}

}  // namespace

RayIntegrator::RayIntegrator(const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                             const TransferFunction& tf)
    : mesh_(mesh), topo_(topo), field_(mesh.fields.at(field)), segment_(tf), embree_(std::make_unique<Embree>()),
      bounds_(mesh_bounds(mesh))
{
    check_tetrahedron_count(mesh.source, mesh.tets.size());  // before any array of the walk is allocated
    values_.resize(mesh.tets.size());
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) values_[t] = tet_values(mesh, field_, t);
    walk_tets_ = mesh.tets.data();
    bool repeated = false;
    for (std::size_t i = 0; i < topo.canonical.size() && !repeated; ++i) repeated = topo.canonical[i] != i;
    if (repeated) {
        canonical_tets_ = mesh.tets;
        for (Tet& tet : canonical_tets_)
            for (uint32_t& v : tet) v = topo.canonical[v];
        walk_tets_ = canonical_tets_.data();
    }

    // Whether the field jumps across a face is decided here, once, so that a continuous field costs the walk nothing.
    const std::vector<uint8_t> jump = field_jump_faces(mesh, topo, field_);
    next_.assign(mesh.tets.size(),
                 {Link{kNoNeighbor, 0}, Link{kNoNeighbor, 0}, Link{kNoNeighbor, 0}, Link{kNoNeighbor, 0}});
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
        for (int i = 0; i < 4; ++i) {
            const int32_t nb = topo.neighbor[t][i];
            if (nb < 0) continue;
            const int32_t face = topo.tet_faces[t][i];
            int k = 0;
            while (topo.tet_faces[std::size_t(nb)][k] != face) ++k;
            next_[t][i] = {(uint32_t(nb) << 3) | (jump[std::size_t(face)] ? kJumpBit : 0u) | uint32_t(k),
                           walk_tets_[std::size_t(nb)][k]};
        }

    Embree& E = *embree_;
    E.device = rtcNewDevice(nullptr);
    if (!E.device) throw InputError(mesh.source, "Embree could not create a device");
    E.scene = rtcNewScene(E.device);
    rtcSetSceneFlags(E.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    rtcSetSceneBuildQuality(E.scene, RTC_BUILD_QUALITY_HIGH);
    const Bounds b = mesh_bounds(mesh);
    E.shift = b.center();
    // Coplanar faces of a non-conforming interface give the same plane parameter to a few ulps of the scene size.
    E.slack = 1e-12 * (glm::length(b.extent()) + glm::length(b.center()));
    E.scale = glm::length(b.extent());
    RTCGeometry geom = rtcNewGeometry(E.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.points.size()));
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        const glm::dvec3 p = mesh.points[i] - E.shift;
        vb[3 * i] = float(p.x);
        vb[3 * i + 1] = float(p.y);
        vb[3 * i + 2] = float(p.z);
    }
    for (std::size_t f = 0; f < topo.faces.size(); ++f)
        if (topo.faces[f].boundary()) E.face_of_prim.push_back(int32_t(f));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), E.face_of_prim.size()));
    for (std::size_t k = 0; k < E.face_of_prim.size(); ++k) {
        // Welded points share one float vertex, so Embree sees the surface as closed where the mesh is.
        const Face& f = topo.faces[std::size_t(E.face_of_prim[k])];
        for (int j = 0; j < 3; ++j) ib[3 * k + j] = topo.canonical[f.v[j]];
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(E.scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(E.scene);
}

RayIntegrator::~RayIntegrator() = default;

glm::dvec4 RayIntegrator::gradient(uint32_t t) const
{
    // Solve [e1; e2; e3] g = ds by Cramer's rule: the rows of the inverse are (e2 x e3, e3 x e1, e1 x e2) / det.
    const Tet& tet = walk_tets_[t];
    const std::array<double, 4>& v = values_[t];
    const glm::dvec3 p0 = mesh_.points[tet[0]];
    const glm::dvec3 e1 = mesh_.points[tet[1]] - p0, e2 = mesh_.points[tet[2]] - p0, e3 = mesh_.points[tet[3]] - p0;
    const glm::dvec3 ds(v[1] - v[0], v[2] - v[0], v[3] - v[0]);
    const double det = glm::dot(e1, glm::cross(e2, e3));
    if (det == 0.0) return glm::dvec4(0.0, 0.0, 0.0, v[0]);  // a flat cell: never entered
    const glm::dvec3 g = (ds.x * glm::cross(e2, e3) + ds.y * glm::cross(e3, e1) + ds.z * glm::cross(e1, e2)) / det;
    return glm::dvec4(g, v[0]);
}

// A vertex of the current tetrahedron seen along the ray (Shear): its position (u, v) in the plane across the ray and
// its ray parameter z, its canonical point, the current tetrahedron's value s there and the vertex's local index in
// that tetrahedron.
struct RayIntegrator::Seen {
    double u, v, z, s;
    uint32_t id;
    int local;

    // Twice the signed area of the triangle (ray, p, q) in the plane: > 0 when the ray passes to the left of the edge
    // p -> q. Rounding gives fl(a - b) = -fl(b - a), so an edge has one value, negated with its direction, whichever
    // tetrahedron asks: the walk cannot slip between two cells round an edge.
    static double side(const Seen& p, const Seen& q) { return p.u * q.v - p.v * q.u; }
};

// The ray's shear (Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT 2013): with kz the axis along
// which the direction is largest, a point q relative to the origin is seen at u = q[kx] + sx q[kz],
// v = q[ky] + sy q[kz] in a plane across the ray (the ray itself at (0, 0)), and z = q[kz] / dir[kz] is the ray
// parameter of every point on the ray.
struct RayIntegrator::Shear {
    glm::dvec3 origin;
    int kx, ky, kz;
    double sx, sy, inv_dz;
    // The pixel's motions right and up (Ray::pixel_dx, pixel_dy) seen in the plane; `turns`: they move the direction,
    // about the point at ray parameter `pivot` (the eye, where the ray was started behind it).
    glm::dvec2 mx{0.0}, my{0.0};
    bool turns = false, pixel = false;
    double pivot = 0.0;

    explicit Shear(const Ray& ray, double pivot_t = 0.0) : origin(ray.origin), turns(ray.turns), pivot(pivot_t)
    {
        const glm::dvec3 a = glm::abs(ray.dir);
        kz = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        inv_dz = 1.0 / ray.dir[kz];
        sx = -ray.dir[kx] * inv_dz;
        sy = -ray.dir[ky] * inv_dz;
        mx = plane(ray.pixel_dx);
        my = plane(ray.pixel_dy);
        pixel = mx != glm::dvec2(0.0) || my != glm::dvec2(0.0);
    }

    glm::dvec2 plane(const glm::dvec3& q) const { return {q[kx] + sx * q[kz], q[ky] + sy * q[kz]}; }

    Seen see(const glm::dvec3& p, uint32_t id, double s, int local) const
    {
        const glm::dvec3 q = p - origin;
        return {q[kx] + sx * q[kz], q[ky] + sy * q[kz], q[kz] * inv_dz, s, id, local};
    }

    // How side(p, q) changes when the ray moves by m in the plane (or, turning, by m per unit of the ray parameter):
    // (m_q x p) - (m_p x q), m_p the motion at p's depth. Antisymmetric in p and q, bit for bit.
    double side_change(const glm::dvec2& m, const Seen& p, const Seen& q) const
    {
        const glm::dvec2 mp = turns ? (p.z - pivot) * m : m, mq = turns ? (q.z - pivot) * m : m;
        return (mq.x * p.v - mq.y * p.u) - (mp.x * q.v - mp.y * q.u);
    }

    // Whether the ray passes left of p -> q, where `e` = side(p, q). An exact zero (the ray through the edge's line)
    // is decided as if the ray were moved (simulation of simplicity): for a pixel's ray, as the pixel moved by
    // (e, e^2) in the window (y up), the rasterizer's fill rule and the exact coverage's (docs/spec.md §7); where that
    // leaves the side at zero, or for a ray no pixel made, by (e^3, e^4) in the plane. Two points on one line of sight
    // (an edge along the ray) by their canonical indices. Every decision is antisymmetric in p and q, so a tie is
    // broken the same way in every tetrahedron round the edge.
    bool passes_left(const Seen& p, const Seen& q, double e) const
    {
        if (e != 0.0) return e > 0.0;
        if (pixel) {
            if (const double cx = side_change(mx, p, q); cx != 0.0) return cx > 0.0;
            if (const double cy = side_change(my, p, q); cy != 0.0) return cy > 0.0;
        }
        // A ray no pixel made; or a perspective ray through the eye at a point of the edge, which turning the ray
        // about the eye cannot move off.
        if (p.v != q.v) return p.v > q.v;
        if (p.u != q.u) return q.u > p.u;
        return p.id < q.id;
    }
};

namespace {

// The part of a step's segment (ray parameter t_in to t1, scalar s_in to s_out) at t >= t_clip: its scalars and
// length, the length 0 where none of it lies there. The scalar is linear along the segment inside one tetrahedron.
struct ClippedSegment {
    double s0 = 0.0, s1 = 0.0, length = 0.0;
};
ClippedSegment clip_segment(double t_in, double t1, double s_in, double s_out, double t_clip)
{
    if (!(t1 > t_in && t1 > t_clip)) return {};
    const double t0 = std::max(t_in, t_clip);
    return {t0 == t_in ? s_in : s_in + (s_out - s_in) * ((t0 - t_in) / (t1 - t_in)), s_out, t1 - t0};
}

// Counts a step of zero length in zero_steps (resets it otherwise); false once there are more than
// kMaxZeroLengthSteps in a row.
bool count_zero_step(double t_in, double t1, int& zero_steps)
{
    if (t1 > t_in) {
        zero_steps = 0;
        return true;
    }
    return ++zero_steps <= kMaxZeroLengthSteps;
}

}  // namespace

bool RayIntegrator::composite_step(double t_in, double t1, double s_in, double s_out, double t_clip, glm::dvec4& acc,
                                   int& zero_steps) const
{
    const ClippedSegment c = clip_segment(t_in, t1, s_in, s_out, t_clip);
    if (c.length > 0.0) acc = composite_over(acc, segment_.integrate(c.s0, c.s1, c.length));
    return count_zero_step(t_in, t1, zero_steps);
}

namespace {
// A turn round an edge passes each cell that shares the edge once; a mesh's edges are shared by a few tens at most.
constexpr int kMaxEdgeTurn = 256;
// Boundary faces met one after another on the edges and vertex a ray passes through before it enters one: a fan round
// a vertex has a few tens.
constexpr int kMaxTieHops = 64;
}  // namespace

int32_t RayIntegrator::boundary_face_across(int32_t face, uint32_t p, uint32_t q) const
{
    int32_t t = topo_.faces[std::size_t(face)].tet[0], through = face;
    for (int step = 0; step < kMaxEdgeTurn; ++step) {
        const std::array<int32_t, 4>& faces = topo_.tet_faces[std::size_t(t)];
        const Tet& tv = walk_tets_[std::size_t(t)];
        int r = -1;  // the third point of the face turned through: the next face is the one opposite it
        for (int i = 0; i < 4; ++i)
            if (faces[i] != through && tv[i] != p && tv[i] != q) r = i;
        if (r < 0) return -1;
        const int32_t next = topo_.neighbor[std::size_t(t)][r];
        if (next < 0) return faces[r];
        through = faces[r];
        t = next;
    }
    return -1;
}

template <class OnStep>
int32_t RayIntegrator::walk(const Ray& ray, const Shear& sh, int32_t face, double t_in, double t_clip, glm::dvec4& acc,
                            double& t_out, RayStats& stats, OnStep on_step, bool strict,
                            std::array<uint32_t, 2>& tie) const
{
    const uint32_t tet = uint32_t(topo_.faces[std::size_t(face)].tet[0]);
    int entry_local = 0;
    while (topo_.tet_faces[tet][entry_local] != face) ++entry_local;
    // The entry face's vertices, ordered counter-clockwise as the ray sees them.
    Seen f[3];
    for (int i = 0, n = 0; i < 4; ++i)
        if (i != entry_local) f[n++] = sh.see(mesh_.points[walk_tets_[tet][i]], walk_tets_[tet][i], values_[tet][i], i);
    double e[3] = {Seen::side(f[0], f[1]), Seen::side(f[1], f[2]), Seen::side(f[2], f[0])};
    if (e[0] + e[1] + e[2] < 0.0) {
        std::swap(f[1], f[2]);
        e[0] = Seen::side(f[0], f[1]);
        e[1] = Seen::side(f[1], f[2]);
        e[2] = Seen::side(f[2], f[0]);
    }
    const double w = e[0] + e[1] + e[2];
    const bool left[3] = {sh.passes_left(f[0], f[1], e[0]), sh.passes_left(f[1], f[2], e[1]),
                          sh.passes_left(f[2], f[0], e[2])};
    if (w > 0.0 && left[0] && left[1] && left[2]) {
        // The ray's point on the face by its barycentric weights, each the side of the edge opposite its vertex.
        const double s_in = (e[1] * f[0].s + e[2] * f[1].s + e[0] * f[2].s) / w;
        return walk_seen(sh, tet, f, e, t_in, s_in, t_clip, acc, t_out, stats, on_step);
    }
    // The ray meets the face on an edge or a vertex, and the tie-break hands it to the face beyond (another boundary
    // face, which the caller looks for next, or none: the ray passes the mesh by).
    tie = {kNoNeighbor, kNoNeighbor};
    if (w > 0.0 && (left[0] || e[0] == 0.0) && (left[1] || e[1] == 0.0) && (left[2] || e[2] == 0.0)) {
        const int i = !left[0] ? 0 : !left[1] ? 1 : 2;
        tie = {f[i].id, f[(i + 1) % 3].id};
        return kPassesBy;
    }
    if (strict) return kPassesBy;
    // Embree decides the entry in float: a ray within its rounding of the face's edge may pass just outside the face
    // by the walk's tests. Such a run is walked by the faces' planes, which need no inside.
    ++stats.plane_walks;
    return walk_planes(ray, tet, entry_local, t_in, t_clip, acc, t_out, stats, on_step);
}

// The walk by the points seen along the ray. The ray enters `tet` through face f (counter-clockwise, the ray inside it
// by passes_left; e[i] = side(f[i], f[i+1])); the tetrahedron's fourth vertex d splits the face's view into the three
// faces it makes with f's edges, and the ray leaves through (f[i], f[i+1], d) where it passes right of f[i] -> d and
// left of f[i+1] -> d. The line from d through the ray separates f's vertices into two non-empty groups (the ray is
// inside f), so exactly one i qualifies, and the ray is inside the exit face as it was inside the entry face: the walk
// needs no other test and cannot fail. One new point a step.
namespace {

// Steps of the walk by points whose segments' integrals are deferred (walk_seen), by step: the part at t >= t_clip,
// from scalar s0 to s1 over `length` (0: nothing to composite), the step's exit t1, its tetrahedron and exit face.
constexpr std::size_t kWalkBatch = 16;
struct StepBatch {
    double s0[kWalkBatch], s1[kWalkBatch], length[kWalkBatch], t1[kWalkBatch];
    uint32_t tet[kWalkBatch];
    int exit_local[kWalkBatch];
    glm::dvec4 rgba[kWalkBatch];
};

}  // namespace

template <class OnStep>
int32_t RayIntegrator::walk_seen(const Shear& sh, uint32_t tet, Seen f[3], double e[3], double t_in, double s_in,
                                 double t_clip, glm::dvec4& acc, double& t_out, RayStats& stats, OnStep on_step) const
{
    int zero_steps = 0;
    int ld = 6 - f[0].local - f[1].local - f[2].local;  // the fourth vertex: its local index and canonical point
    uint32_t id = walk_tets_[tet][ld];
    // Steps are walked kWalkBatch at a time and their segments integrated after, in order: the walk's unpredictable
    // exit choices then do not discard integrals in flight. What the integrals decide (opacity) is applied in step
    // order, so the colour, the counts and the end of the walk are those of one step at a time.
    StepBatch batch;
    std::size_t n = 0;
    std::size_t opaque = kWalkBatch;  // the step that made the ray opaque
    const auto flush = [&] {
        segment_.integrate_many(n, batch.s0, batch.s1, batch.length, batch.rgba);
        for (std::size_t b = 0; b < n; ++b) {
            ++stats.segments;
            on_step(batch.tet[b]);
            if (batch.length[b] > 0.0) acc = composite_over(acc, batch.rgba[b]);
            if (acc.a >= kReferenceOpaque) {
                opaque = b;
                n = 0;
                return true;
            }
        }
        n = 0;
        return false;
    };
    for (;;) {
        const Seen d = sh.see(mesh_.points[id], id, values_[tet][ld], ld);
        const double ed[3] = {Seen::side(f[0], d), Seen::side(f[1], d), Seen::side(f[2], d)};
        const bool left[3] = {sh.passes_left(f[0], d, ed[0]), sh.passes_left(f[1], d, ed[1]),
                              sh.passes_left(f[2], d, ed[2])};
        const int i = !left[0] && left[1] ? 0 : !left[1] && left[2] ? 1 : 2;
        const int j = i == 2 ? 0 : i + 1, k = j == 2 ? 0 : j + 1;  // f[k] is the vertex the exit face leaves out
        // Barycentric weights of the ray's point on the exit face (f[i], f[j], d), all >= 0.
        const double wi = ed[j], wj = -ed[i], wd = e[i];
        const double w = wi + wj + wd;
        const double inv_w = w > 0.0 ? 1.0 / w : 0.0;
        const double t_exit = w > 0.0 ? (wi * f[i].z + wj * f[j].z + wd * d.z) * inv_w : t_in;
        const double s_out = w > 0.0 ? (wi * f[i].s + wj * f[j].s + wd * d.s) * inv_w : s_in;
        const double t1 = std::max(t_in, t_exit);
        const int exit_local = f[k].local;
        batch.tet[n] = tet;
        batch.exit_local[n] = exit_local;
        batch.t1[n] = t1;
        const ClippedSegment c = clip_segment(t_in, t1, s_in, s_out, t_clip);
        batch.s0[n] = c.s0;
        batch.s1[n] = c.s1;
        batch.length[n] = c.length;
        ++n;
        if (!count_zero_step(t_in, t1, zero_steps)) {
            if (flush()) break;
            ++stats.failures;
            t_out = t1;
            return -1;
        }
        const Link link = next_[tet][exit_local];
        const uint32_t next = link.next;
        t_in = t1;
        if (next == kNoNeighbor) {
            if (flush()) break;
            t_out = t1;
            return topo_.tet_faces[tet][exit_local];
        }
        if (n == kWalkBatch && flush()) break;
        tet = next >> 3;
        ld = int(next & 3u);
        id = link.vertex;
        const Seen fi = f[i], fj = f[j];
        f[0] = fi;
        f[1] = fj;
        f[2] = d;
        const double e0 = e[i];
        e[0] = e0;
        e[1] = ed[j];
        e[2] = -ed[i];
        // The face's vertices by their local indices in the next tetrahedron (its vertex `next & 3` is the new one).
        // Compared four at a time and found from the mask, without a branch: which of the four matches is as
        // unpredictable as the exit face.
        const __m128i nt = _mm_loadu_si128(reinterpret_cast<const __m128i*>(walk_tets_[tet].data()));
        for (int c = 0; c < 3; ++c) {
            const int mask = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(nt, _mm_set1_epi32(int(f[c].id)))));
            f[c].local = __builtin_ctz(unsigned(mask) | 8u);  // 3 if none matched (never, for a conforming face)
        }
        s_in = s_out;
        if (next & kJumpBit) {
            // The field jumps across the face: the next tetrahedron's own values at the same point.
            for (int c = 0; c < 3; ++c) f[c].s = values_[tet][f[c].local];
            if (w > 0.0) s_in = (wi * f[0].s + wj * f[1].s + wd * f[2].s) * inv_w;
        }
    }
    // Opaque: the walk ends where the step that made it so ends.
    t_out = batch.t1[opaque];
    return topo_.tet_faces[batch.tet[opaque]][batch.exit_local[opaque]];
}

template <class OnStep>
int32_t RayIntegrator::walk_planes(const Ray& ray, uint32_t tet, int entry_local, double t_in, double t_clip,
                                   glm::dvec4& acc, double& t_out, RayStats& stats, OnStep on_step) const
{
    glm::dvec4 g = gradient(tet);
    const auto scalar_at = [&](const glm::dvec4& grad, uint32_t t, const glm::dvec3& p) {
        return grad.w + glm::dot(glm::dvec3(grad), p - mesh_.points[walk_tets_[t][0]]);
    };
    double s_in = scalar_at(g, tet, ray.origin + t_in * ray.dir);
    int zero_steps = 0;
    for (;;) {
        const Tet& T = walk_tets_[tet];
        // Outward face normals from the edge vectors of vertex 0 (the orders of tet_face): the face opposite vertex
        // i is n[i]. Face 0 does not contain vertex 0; its normal is minus the sum of the others (the area vectors of
        // a closed surface sum to zero).
        const glm::dvec3 a = mesh_.points[T[0]];
        const glm::dvec3 e1 = mesh_.points[T[1]] - a, e2 = mesh_.points[T[2]] - a, e3 = mesh_.points[T[3]] - a;
        glm::dvec3 n[4];
        n[1] = glm::cross(e3, e2);
        n[2] = glm::cross(e1, e3);
        n[3] = glm::cross(e2, e1);
        n[0] = -(n[1] + n[2] + n[3]);
        const glm::dvec3 w = a - ray.origin;  // faces 1, 2, 3 contain vertex 0
        const glm::dvec3 w0 = w + e1;         // face 0 contains vertex 1
        // Exit: among the faces the ray leaves through (outward normal along the ray), the plane it crosses first,
        // t_i = num_i / den_i with den_i > 0, compared by cross-multiplication so that only the winner is divided.
        // Ties (the ray through an edge or a vertex) go to the lowest local face index; a pass through the edge's
        // other tetrahedra then has zero length and moves on round the edge.
        int exit_local = -1;
        double best_num = 0.0, best_den = 1.0;
        for (int i = 0; i < 4; ++i) {
            if (i == entry_local) continue;
            const double den = glm::dot(n[i], ray.dir);
            if (!(den > 0.0)) continue;
            const double num = glm::dot(n[i], i == 0 ? w0 : w);
            if (exit_local < 0 || num * best_den < best_num * den) {
                exit_local = i;
                best_num = num;
                best_den = den;
            }
        }
        ++stats.segments;
        on_step(tet);
        if (exit_local < 0) {
            // Only possible for a ray lying in the entry face's plane with rounding against it; abandon the ray.
            ++stats.failures;
            t_out = t_in;
            return -1;
        }
        const double t1 = std::max(t_in, best_num / best_den);
        const double s_out = g.w + glm::dot(glm::dvec3(g), (t1 * ray.dir) - w);
        if (!composite_step(t_in, t1, s_in, s_out, t_clip, acc, zero_steps)) {
            ++stats.failures;
            t_out = t1;
            return -1;
        }
        const uint32_t next = next_[tet][exit_local].next;
        t_in = t1;
        if (next == kNoNeighbor || acc.a >= kReferenceOpaque) {
            t_out = t1;
            return topo_.tet_faces[tet][exit_local];
        }
        tet = next >> 3;
        entry_local = int(next & 3u);
        g = gradient(tet);
        // Where the field is continuous across the face, the exit value is the next tetrahedron's entry value; where it
        // jumps, the next tetrahedron's own field at the entry point.
        s_in = (next & kJumpBit) ? scalar_at(g, tet, ray.origin + t1 * ray.dir) : s_out;
    }
}

template <class OnStep>
glm::dvec4 RayIntegrator::trace(const Ray& in, RayStats& stats, std::vector<RayRun>* runs, OnStep on_step) const
{
    const Embree& E = *embree_;
    // An origin inside the mesh's bounds may lie inside the mesh, where no boundary face is ahead to enter through.
    // Such a ray is traced from `back` units behind, a point outside the bounds (distance to the bounds' centre plus
    // their diagonal), and composited from t = back on: the same line, so the same tetrahedra and segments, with the
    // first segment cut where the real ray starts. Moving the origin costs t some precision (t grows by at most a few
    // diagonals), far below what the reference's tolerances allow.
    const Bounds& bb = bounds_;
    const bool inside_bounds = in.origin.x >= bb.lo.x && in.origin.y >= bb.lo.y && in.origin.z >= bb.lo.z &&
                               in.origin.x <= bb.hi.x && in.origin.y <= bb.hi.y && in.origin.z <= bb.hi.z;
    const double back = inside_bounds ? glm::length(in.origin - bb.center()) + glm::length(bb.extent()) : 0.0;
    Ray ray = in;
    ray.origin = in.origin - back * in.dir;
    glm::dvec4 acc(0.0);
    UsedFaces used;
    double t_min = 0.0;
    const glm::dvec3 o = ray.origin - E.shift;
    const Shear shear(ray, back);
    bool nudged = false;  // the one query for a ray that grazes the mesh's silhouette has been made
    for (;;) {
        int32_t face = next_entry(ray, o, ray.dir, t_min, used);
        bool strict = false;
        if (face < 0 && used.empty() && shear.pixel && !nudged) {
            // Embree may report no face of an edge the ray runs along on the silhouette (a ray in a boundary face's
            // plane): ask again with the ray moved by a few float ulps the way the tie-break moves it; what that
            // query finds is entered only if the exact ray passes through it by the walk's own tests.
            nudged = strict = true;
            face = nudged_entry(ray, o, t_min, used);
        }
        if (face < 0) break;
        double t_in = 0.0, t_out = 0.0;
        glm::dvec4 run(0.0);
        const int32_t left = enter(ray, shear, face, t_min, back, strict, used, runs ? run : acc, t_in, t_out, stats,
                                   on_step);
        if (left == kPassesBy) continue;  // not entered here: look again from the same place, these faces left out
        ++stats.entries;
        // A run's own opacity hides what lies behind it on this ray as the whole accumulator's does.
        const double alpha = runs ? run.a : acc.a;
        if (runs && t_out > back) runs->push_back({std::max(t_in, back) - back, t_out - back, run});
        if (left < 0 || alpha >= kReferenceOpaque) break;
        used.push_back(left);
        t_min = t_out;
    }
    return acc;
}

int32_t RayIntegrator::next_entry(const Ray& ray, const glm::dvec3& o, const glm::dvec3& dir, double t_min,
                                  const UsedFaces& used) const
{
    const Embree& E = *embree_;
    EntryContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.base.filter = entry_filter;
    ctx.mesh = &mesh_;
    ctx.topo = &topo_;
    ctx.face_of_prim = &E.face_of_prim;
    ctx.origin = ray.origin;
    ctx.dir = ray.dir;
    ctx.t_min = t_min;
    ctx.slack = E.slack;
    ctx.used = &used;
    RTCRayHit rh;
    rh.ray.org_x = float(o.x);
    rh.ray.org_y = float(o.y);
    rh.ray.org_z = float(o.z);
    rh.ray.dir_x = float(dir.x);
    rh.ray.dir_y = float(dir.y);
    rh.ray.dir_z = float(dir.z);
    // Embree's float distances may be off by some float ulps of the distances involved: start the search early by
    // far more than that (1e-5 relative; float carries 6e-8) and let the filter decide in double.
    rh.ray.tnear = float(std::max(0.0, t_min - 1e-5 * (E.scale + t_min + glm::length(o))));
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(E.scene, &ctx.base, &rh);
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : E.face_of_prim[rh.hit.primID];
}

int32_t RayIntegrator::nudged_entry(const Ray& ray, const glm::dvec3& o, double t_min, const UsedFaces& used) const
{
    // kNudgeUlps float ulps of the origin's size (orthographic) or of a unit direction (perspective), so that Embree's
    // own rounding (a few ulps) cannot undo the move; the second direction by a sixteenth of that, as the tie-break's
    // e^2 stands behind its e.
    constexpr double kNudgeUlps = 64.0;
    const double ulp = double(std::numeric_limits<float>::epsilon());
    const glm::dvec3 move = ray.pixel_dx + ray.pixel_dy / 16.0;
    if (ray.turns) return next_entry(ray, o, ray.dir + kNudgeUlps * ulp * move, t_min, used);
    const double size = embree_->scale + glm::length(o);
    return next_entry(ray, o + kNudgeUlps * ulp * size * move, ray.dir, t_min, used);
}

template <class OnStep>
int32_t RayIntegrator::enter(const Ray& ray, const Shear& shear, int32_t face, double t_min, double back, bool strict,
                             UsedFaces& used, glm::dvec4& acc, double& t_in, double& t_out, RayStats& stats,
                             OnStep on_step) const
{
    // Embree returns the nearest face in float; its parameter is recomputed in double here.
    const auto entry_t = [&](int32_t fi) {
        const Face& f = topo_.faces[std::size_t(fi)];
        const glm::dvec3 n = face_normal(mesh_, f.v);
        return std::max(t_min, glm::dot(n, mesh_.points[f.v[0]] - ray.origin) / glm::dot(n, ray.dir));
    };
    std::array<uint32_t, 2> tie{kNoNeighbor, kNoNeighbor};
    int32_t left = kPassesBy;
    // The ray meets a face on an edge that the tie-break gives to the boundary face beyond: enter that one (Embree
    // need not report both faces of an edge), or, where it does not face the ray, the ray passes the mesh by here.
    for (int hop = 0; hop < kMaxTieHops; ++hop) {
        used.push_back(face);
        t_in = t_out = entry_t(face);
        left = walk(ray, shear, face, t_in, back, acc, t_out, stats, on_step, strict, tie);
        if (left != kPassesBy || tie[0] == kNoNeighbor) break;
        face = boundary_face_across(face, tie[0], tie[1]);
        if (face < 0 || used.contains(face)) break;
        const Face& f = topo_.faces[std::size_t(face)];
        if (!(glm::dot(face_normal(mesh_, f.v), ray.dir) < 0.0)) break;
    }
    return left;
}

namespace {
struct NoStep {
    void operator()(uint32_t) const {}
};
}  // namespace

glm::dvec4 RayIntegrator::integrate(const Ray& ray, RayStats& stats) const
{
    return trace(ray, stats, nullptr, NoStep{});
}

void RayIntegrator::runs(const Ray& ray, RayStats& stats, std::vector<RayRun>& out) const
{
    trace(ray, stats, &out, NoStep{});
}

glm::dvec4 RayIntegrator::integrate_counting(const Ray& ray, RayStats& stats, std::vector<uint32_t>& visits) const
{
    return trace(ray, stats, nullptr, [&visits](uint32_t tet) { ++visits[tet]; });
}

}  // namespace uvr
