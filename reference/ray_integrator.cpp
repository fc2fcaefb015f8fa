#include "reference/ray_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>
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

namespace {

// The intersect context carries what the filter needs to accept only faces the ray really enters next.
struct EntryContext {
    RTCIntersectContext base;  // first member: Embree hands the filter a pointer to it
    const TetMesh* mesh;
    const MeshTopology* topo;
    const std::vector<int32_t>* face_of_prim;
    glm::dvec3 origin, dir;
    double t_min, slack;
    const std::vector<int32_t>* used;  // boundary faces this ray already entered or left through
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
            ok = t >= ctx->t_min - ctx->slack &&
                 std::find(ctx->used->begin(), ctx->used->end(), face) == ctx->used->end();
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
    // Gradient of the linear field in each tetrahedron: solve [e1; e2; e3] g = ds by Cramer's rule.
    gradient_.resize(mesh.tets.size(), glm::dvec4(0.0));
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        const Tet& tet = mesh.tets[t];
        const glm::dvec3 p0 = mesh.points[tet[0]];
        const glm::dvec3 e1 = mesh.points[tet[1]] - p0, e2 = mesh.points[tet[2]] - p0, e3 = mesh.points[tet[3]] - p0;
        const std::array<double, 4> v = tet_values(mesh, field_, t);
        const double s0 = v[0];
        const glm::dvec3 ds(v[1] - s0, v[2] - s0, v[3] - s0);
        const double det = glm::dot(e1, glm::cross(e2, e3));
        gradient_[t].w = s0;
        if (det == 0.0) continue;  // a flat cell: never entered
        // Rows of the inverse of [e1; e2; e3] are the columns (e2 x e3, e3 x e1, e1 x e2) / det.
        const glm::dvec3 g = (ds.x * glm::cross(e2, e3) + ds.y * glm::cross(e3, e1) + ds.z * glm::cross(e1, e2)) / det;
        gradient_[t] = glm::dvec4(g, s0);
    }

    if (mesh.tets.size() >= (std::size_t(1) << 29))
        throw InputError(mesh.source, "more than 2^29 tetrahedra: the walk packs tetrahedron indices into 29 bits");
    // Whether the field jumps across a face is decided here, once, so that a continuous field costs the walk nothing.
    const std::vector<uint8_t> jump = field_jump_faces(mesh, topo, field_);
    next_.assign(mesh.tets.size(), {kNoNeighbor, kNoNeighbor, kNoNeighbor, kNoNeighbor});
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
        for (int i = 0; i < 4; ++i) {
            const int32_t nb = topo.neighbor[t][i];
            if (nb < 0) continue;
            const int32_t face = topo.tet_faces[t][i];
            int k = 0;
            while (topo.tet_faces[std::size_t(nb)][k] != face) ++k;
            next_[t][i] = (uint32_t(nb) << 3) | (jump[std::size_t(face)] ? kJumpBit : 0u) | uint32_t(k);
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

double RayIntegrator::scalar_at(uint32_t t, const glm::dvec3& p) const
{
    const glm::dvec4& g = gradient_[t];
    return g.w + glm::dot(glm::dvec3(g), p - mesh_.points[mesh_.tets[t][0]]);
}

template <class OnStep>
int32_t RayIntegrator::walk(const Ray& ray, int32_t face, double t_in, double t_clip, glm::dvec4& acc, double& t_out,
                            RayStats& stats, OnStep on_step) const
{
    const Face& entry = topo_.faces[std::size_t(face)];
    uint32_t tet = uint32_t(entry.tet[0]);
    int entry_local = 0;
    while (topo_.tet_faces[tet][entry_local] != face) ++entry_local;
    double s_in = scalar_at(tet, ray.origin + t_in * ray.dir);
    int zero_steps = 0;
    for (;;) {
        const Tet& T = mesh_.tets[tet];
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
        const glm::dvec3 w = a - ray.origin;     // faces 1, 2, 3 contain vertex 0
        const glm::dvec3 w0 = w + e1;            // face 0 contains vertex 1
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
        const glm::dvec4& g = gradient_[tet];
        const double s_out = g.w + glm::dot(glm::dvec3(g), (t1 * ray.dir) - w);
        if (t1 > t_in) {
            if (t1 > t_clip) {
                // The part at t >= t_clip: the scalar is linear along the segment inside one tetrahedron.
                const double t0 = std::max(t_in, t_clip);
                const double s0 = t0 == t_in ? s_in : s_in + (s_out - s_in) * ((t0 - t_in) / (t1 - t_in));
                acc = composite_over(acc, segment_.integrate(s0, s_out, t1 - t0));
            }
            zero_steps = 0;
        } else if (++zero_steps > kMaxZeroLengthSteps) {
            ++stats.failures;
            t_out = t1;
            return -1;
        }
        const uint32_t next = next_[tet][exit_local];
        t_in = t1;
        if (next == kNoNeighbor || acc.a >= kReferenceOpaque) {
            t_out = t1;
            return topo_.tet_faces[tet][exit_local];
        }
        tet = next >> 3;
        entry_local = int(next & 3u);
        // Where the field is continuous across the face, the exit value is the next tetrahedron's entry value; where it
        // jumps, the next tetrahedron's own field at the entry point.
        s_in = (next & kJumpBit) ? scalar_at(tet, ray.origin + t1 * ray.dir) : s_out;
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
    const Ray ray{in.origin - back * in.dir, in.dir};
    glm::dvec4 acc(0.0);
    std::vector<int32_t> used;
    double t_min = 0.0;
    const glm::dvec3 o = ray.origin - E.shift;
    for (;;) {
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
        rh.ray.dir_x = float(ray.dir.x);
        rh.ray.dir_y = float(ray.dir.y);
        rh.ray.dir_z = float(ray.dir.z);
        // Embree's float distances may be off by some float ulps of the distances involved: start the search early by
        // far more than that (1e-5 relative; float carries 6e-8) and let the filter decide in double.
        rh.ray.tnear = float(std::max(0.0, t_min - 1e-5 * (E.scale + t_min + glm::length(o))));
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.flags = 0;
        rh.ray.time = 0.0f;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(E.scene, &ctx.base, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        const int32_t face = E.face_of_prim[rh.hit.primID];
        // The filter may have accepted several candidates on the way; Embree returns the nearest in float, and its
        // parameter is recomputed in double here.
        const Face& f = topo_.faces[std::size_t(face)];
        const glm::dvec3 n = face_normal(mesh_, f.v);
        const double t_in = std::max(t_min, glm::dot(n, mesh_.points[f.v[0]] - ray.origin) / glm::dot(n, ray.dir));
        used.push_back(face);
        ++stats.entries;
        double t_out = t_in;
        glm::dvec4 run(0.0);
        const int32_t left = walk(ray, face, t_in, back, runs ? run : acc, t_out, stats, on_step);
        // A run's own opacity hides what lies behind it on this ray as the whole accumulator's does.
        const double alpha = runs ? run.a : acc.a;
        if (runs && t_out > back) runs->push_back({std::max(t_in, back) - back, t_out - back, run});
        if (left < 0 || alpha >= kReferenceOpaque) break;
        used.push_back(left);
        t_min = t_out;
    }
    return acc;
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
