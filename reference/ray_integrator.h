// The ground truth: exact emission-absorption integration along rays through a tetrahedral mesh.
//
// Embree finds where a ray enters the mesh through its boundary (and re-enters a non-convex mesh); inside, the ray
// walks from tetrahedron to tetrahedron through shared faces in double precision, deciding each exit face from the
// mesh's points seen along the ray. In each tetrahedron the scalar is linear (constant for a cell field) in the
// tetrahedron's own values, so each step is one segment of docs/spec.md §1, integrated in closed form
// (segment_integral.h) and composited front to back; across a face where the field jumps the next segment starts from
// the next tetrahedron's value. See docs/reference.md for the exit-face rule, its ties and why the walk is watertight.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "reference/camera.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"
#include "reference/topology.h"

namespace uvr {

// What one ray did, for diagnostics and benchmarks.
struct RayStats {
    uint64_t segments = 0;       // tetrahedra traversed (including zero-length passes through edges and vertices)
    uint64_t entries = 0;        // times the ray entered the mesh through its boundary
    uint64_t failures = 0;       // rays abandoned by the walk's guards (must stay 0; reported, never hidden)
    uint64_t plane_walks = 0;    // runs walked by the faces' planes: entered just outside the entry face (walk())
};

// One run of a ray through the mesh: its distances along the ray (t_in <= t_out) and its premultiplied RGBA.
struct RayRun {
    double t_in = 0.0, t_out = 0.0;
    glm::dvec4 rgba{0.0};
};

class RayIntegrator {
public:
    // `field` indexes mesh.fields. The mesh and topology must outlive the integrator.
    RayIntegrator(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf);
    ~RayIntegrator();
    RayIntegrator(const RayIntegrator&) = delete;
    RayIntegrator& operator=(const RayIntegrator&) = delete;

    // Premultiplied RGBA along the ray from t = 0 (the ray's origin) to infinity. Thread-safe. The origin may lie
    // anywhere, inside the mesh or on one of its faces too (a camera inside the mesh): the ray is then traced from a
    // point behind it, outside the mesh's bounds, and only what lies at t >= 0 is composited.
    glm::dvec4 integrate(const Ray& ray, RayStats& stats) const;

    // The same ray as runs: one per maximal stretch of the mesh's cells along it (entry through a boundary face to
    // exit through one), each composited on its own from transparent, appended to `runs` front to back. Compositing
    // the runs front to back gives integrate()'s colour up to the order of the additions: on a part of a mesh (a
    // piece whose boundary includes cut faces) they are the fragments data-parallel rendering exchanges.
    void runs(const Ray& ray, RayStats& stats, std::vector<RayRun>& runs) const;

    // integrate(), also adding one to visits[t] for every step through tetrahedron t (zero-length passes included):
    // the ray work each cell costs, which a partition balanced for a view weighs (reference/partition.h). `visits`
    // holds one count per tetrahedron of the mesh.
    glm::dvec4 integrate_counting(const Ray& ray, RayStats& stats, std::vector<uint32_t>& visits) const;

    // The mesh's bounds: no ray meets a cell outside them.
    const Bounds& bounds() const { return bounds_; }

    class UsedFaces;  // the boundary faces one ray has entered or left through (ray_integrator.cpp)

private:
    struct Embree;
    // The loop over the ray's entries through the boundary: with `runs` null, every walk composites into one
    // accumulator (integrate); otherwise each walk's run starts transparent and is appended. `on_step(t)` is called
    // for every step through tetrahedron t (a no-op but for integrate_counting).
    template <class OnStep>
    glm::dvec4 trace(const Ray& ray, RayStats& stats, std::vector<RayRun>* runs, OnStep on_step) const;
    struct Shear;  // the ray's view of the mesh's points (ray_integrator.cpp)
    struct Seen;   // one point so seen
    // The walk from boundary face `face` entered at ray parameter t_in, compositing into acc what lies at t >= t_clip;
    // returns the boundary face it leaves through and sets t_out. It walks by the points seen along the ray
    // (walk_seen) when the ray passes through the entry face by that walk's own tests, else by the faces' planes;
    // kPassesBy, having composited nothing, when the ray meets the face on its edge or vertex and the tie-break
    // (Shear::passes_left) puts it outside (`tie` is then that edge, in canonical points), or, `strict`, when the
    // ray passes outside the face at all.
    static constexpr int32_t kPassesBy = -2;
    template <class OnStep>
    int32_t walk(const Ray& ray, const Shear& shear, int32_t face, double t_in, double t_clip, glm::dvec4& acc,
                 double& t_out, RayStats& stats, OnStep on_step, bool strict, std::array<uint32_t, 2>& tie) const;
    // The nearest boundary face the float ray from `o` (relative to Embree's shift) along `dir` enters at or after
    // t_min, not in `used` (the filter decides in double on `ray` itself); -1 for none.
    int32_t next_entry(const Ray& ray, const glm::dvec3& o, const glm::dvec3& dir, double t_min,
                       const UsedFaces& used) const;
    // next_entry for the ray moved a few float ulps the way the tie-break moves it (Ray::pixel_dx, pixel_dy).
    int32_t nudged_entry(const Ray& ray, const glm::dvec3& o, double t_min, const UsedFaces& used) const;
    // Enters the mesh through boundary face `face` (walk), or through the faces beyond the edges the tie-break hands
    // the ray on to; each face tried is added to `used`. Returns walk's result for the face entered, or kPassesBy.
    template <class OnStep>
    int32_t enter(const Ray& ray, const Shear& shear, int32_t face, double t_min, double back, bool strict,
                  UsedFaces& used, glm::dvec4& acc, double& t_in, double& t_out, RayStats& stats,
                  OnStep on_step) const;
    // The boundary face across the edge (p, q) of boundary face `face` (canonical points), found by turning round the
    // edge through the cells that share it; -1 when the turn does not end on the boundary within kMaxEdgeTurn cells.
    int32_t boundary_face_across(int32_t face, uint32_t p, uint32_t q) const;
    template <class OnStep>
    int32_t walk_seen(const Shear& shear, uint32_t tet, Seen f[3], double e[3], double t_in, double s_in, double t_clip,
                      glm::dvec4& acc, double& t_out, RayStats& stats, OnStep on_step) const;
    template <class OnStep>
    int32_t walk_planes(const Ray& ray, uint32_t tet, int entry_local, double t_in, double t_clip, glm::dvec4& acc,
                        double& t_out, RayStats& stats, OnStep on_step) const;
    // One step's segment from t_in to t1 (scalar s_in to s_out), composited into acc where it lies at t >= t_clip.
    // Counts consecutive zero-length steps in zero_steps; false once there are more than kMaxZeroLengthSteps.
    bool composite_step(double t_in, double t1, double s_in, double s_out, double t_clip, glm::dvec4& acc,
                        int& zero_steps) const;
    // The linear field of tetrahedron t as its gradient (xyz) and its value at vertex 0 (w).
    glm::dvec4 gradient(uint32_t t) const;

    const TetMesh& mesh_;
    const MeshTopology& topo_;
    const ScalarField& field_;
    SegmentIntegrator segment_;
    // Per tetrahedron: the field's values at its four vertices (equal for a cell field).
    std::vector<std::array<double, 4>> values_;
    // The tetrahedra by canonical point (MeshTopology::canonical), so that a vertex is one point wherever a file
    // repeats it: the mesh's own tetrahedra when no point is repeated, else `canonical_tets_`.
    const Tet* walk_tets_ = nullptr;
    std::vector<Tet> canonical_tets_;
    // Per tetrahedron and local face: the neighbour across it, whether the field jumps across the face, and the shared
    // face's local index in the neighbour, packed as (tet << 3) | jump << 2 | local, or kNoNeighbor on the boundary;
    // and the neighbour's vertex opposite the face (its canonical point), which the walk by points sees next without
    // waiting for the neighbour's vertex indices. Saves the walk a search per step.
    struct Link {
        uint32_t next;
        uint32_t vertex;
    };
    std::vector<std::array<Link, 4>> next_;
    static constexpr uint32_t kNoNeighbor = 0xFFFFFFFFu;
    static constexpr uint32_t kJumpBit = 4u;
    std::unique_ptr<Embree> embree_;
    Bounds bounds_;  // the mesh's, for origins inside them (integrate)
};

// Accumulated alpha beyond which the rest of a ray cannot change any channel by more than 1e-15: the reference stops
// there (it is not the GPU algorithms' early termination, which docs/spec.md §3 sets with --threshold).
inline constexpr double kReferenceOpaque = 1.0 - 1e-15;

// Guard against a walk that stops making progress (a ray circling an edge in rounding noise): after this many
// consecutive zero-length steps the ray is abandoned and counted in RayStats::failures.
inline constexpr int kMaxZeroLengthSteps = 256;

}  // namespace uvr
