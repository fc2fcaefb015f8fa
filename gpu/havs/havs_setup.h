// HAVS's CPU stage, shared by the emulated driver (gpu/havs/havs.cpp) and the GL driver (gpu/havs/gl_havs.cpp), so
// that both draw the same triangles in the same order with the same constants: per mesh (HavsMesh) the normalized
// scalars, the unique faces, their boundary marks, the longest edge and the table; per frame (setup_havs_frame) the
// vertex buffer, the sort, the vertex and clip stages and HavsFrameConstants; per triangle drawn
// (havs_face_constants) its flat HavsFace.
// Twins: none (CPU stage); on GL its outputs feed shaders/havs_vertex.vert and shaders/havs_fragment.frag.
// Details: docs/havs.md, "The CPU stage".
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/vec3.hpp>

#include "gpu/havs/havs_fragment.h"
#include "gpu/pipeline/drawn_mesh.h"
#include "gpu/pipeline/view_setup.h"
#include "gpu/pipeline/exact_coverage.h"
#include "gpu/pipeline/interpolation.h"
#include "gpu/pipeline/preintegration_table.h"
#include "gpu/pipeline/segment.h"
#include "gpu/pipeline/rasterize.h"
#include "reference/camera.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"
#include "reference/topology.h"
#include "reference/choice.h"

namespace uvr::gpu {

enum class GapMode { exact, maxgap };
inline constexpr Choices<GapMode, 2> kGapModes{
    {{GapMode::exact, "exact", "boundary faces marked: a gap between cells contributes nothing"},
     {GapMode::maxgap, "maxgap", "VTK's heuristic: a segment longer than the longest cell edge is a gap"}}};
// --entries: uvr's marked entries (side * (1 + s): exit, entry and extrapolated fragments told apart), or the paper's
// (the scalar itself, an exit face's negative: the program as printed, which the ARB witness runs). docs/havs-arb.md.
enum class EntryEncoding { marked, paper };
inline constexpr Choices<EntryEncoding, 2> kEntryEncodings{
    {{EntryEncoding::marked, "marked", "exit, entry and extrapolated fragments told apart; default"},
     {EntryEncoding::paper, "paper",
      "the HAVS paper's program as printed: the scalar itself, exit faces negative; the default with --backend arb"}}};
// The spellings --entries had before.
inline constexpr std::array<RenamedChoice, 1> kEntryEncodingsRenamed{{{"seed", "paper"}}};

// --k all: the k-buffer as deep as each pixel's fragments (every fragment held until the flush; the emulation's
// only). docs/spec.md §6's exact sort, at the memory of the fragments themselves: gpu/havs/havs_pixel_sort.h.
inline constexpr int kEveryFragment = 0;
// --ties, with --k all: the order of a pixel's fragments at one distance. arrival: the older first, as any k-buffer
// deeper than the pixel's fragments takes them (the paper's tie); facing: back faces first (a ray leaves a cell before
// it enters the next), exact where a seam's two coincident faces carry different scalars. docs/havs.md, "k = all".
enum class TieOrder { arrival, facing };
inline constexpr Choices<TieOrder, 2> kTieOrders{
    {{TieOrder::arrival, "arrival", "at one distance the older fragment first, as a k-buffer takes them"},
     {TieOrder::facing, "facing", "back faces first: exact where a seam's coincident faces carry two scalars"}}};

struct HavsOptions {
    int k = 6;  // entries a pixel, or kEveryFragment
    TieOrder ties = TieOrder::arrival;  // facing only with kEveryFragment
    SegmentMode segment = SegmentMode::table;
    GapMode gaps = GapMode::exact;
    float threshold = 0.99f;  // the opacity kill; 1 switches early termination off
    int table_size = 128;     // texels along each of the table's three axes
    TexelFormat table_format = TexelFormat::f32;
    double table_max_length = 0.0;  // 0: the mesh's longest edge (no segment inside one cell is longer)
    // The range the scalars are normalized over and the table spans; empty: the drawn field's own. A part of a larger
    // mesh (sort-last) is given the whole's, as its table_max_length.
    std::optional<Range> scalar_range;
    TextureFilter filter = TextureFilter::linear;
    Coverage coverage = Coverage::gpu;  // --coverage exact: the emulation covers pixels without snapping
    InterpolationMode interpolation = InterpolationMode::gpu;  // --interpolation exact: flat constants, double
    EntryEncoding entries = EntryEncoding::marked;
};


// What the CPU stage keeps of the mesh between frames.
class HavsMesh {
public:
    // Throws InputError when an option is out of range (k is checked by each driver against its own limit).
    HavsMesh(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
             const HavsOptions& options);

    const TetMesh& mesh() const { return mesh_; }  // the mesh drawn (gpu/pipeline/drawn_mesh.h)
    const HavsOptions& options() const { return options_; }  // table_max_length filled in
    const SegmentIntegrator& integrator() const { return integrator_; }
    const Range& range() const { return range_; }
    double longest_edge() const { return longest_edge_; }
    // 3 point indices per face drawn: the unique faces, then, for each internal face across which the field jumps,
    // the face again with its second tetrahedron's points (and so its scalars).
    const std::vector<uint32_t>& faces() const { return faces_; }
    std::size_t face_count() const { return faces_.size() / 3; }
    const PreintegrationTable* table() const { return table_.get(); }  // null with --segment exact
    double table_ms() const { return table_ms_; }

    // The normalized scalar of point i and whether face f can be an exit face (exact gaps only). With a cell field,
    // the points are those of mesh(), the per-cell vertex mesh (gpu/pipeline/drawn_mesh.h).
    double scalar_n(std::size_t i) const { return scalar_n_[i]; }
    bool exit_capable(std::size_t f) const { return boundary_[f] != 0; }

private:
    void add_faces(const MeshTopology& topo);  // faces_ and boundary_

    DrawnMesh drawn_mesh_;
    const TetMesh& mesh_;
    HavsOptions options_;
    SegmentIntegrator integrator_;
    Range range_;
    double longest_edge_ = 0.0;
    std::vector<double> scalar_n_;
    std::vector<uint32_t> faces_;
    std::vector<uint8_t> boundary_;
    std::shared_ptr<const PreintegrationTable> table_;
    double table_ms_ = 0.0;
};

// What a frame draws, as ids: below the mesh's face count a mesh face drawn as it is; from there on an extra
// triangle of the frame (a piece of a clipped face, or of a near-plane section).
inline constexpr uint32_t kNearSection = 0xFFFFFFFFu;  // extra_face of a near-plane section's triangle

// One frame's CPU work.
struct HavsFrameSetup {
    Camera camera;
    int width = 0, height = 0;
    ViewSetup view;                    // positions relative to the eye (view_setup's origin), near plane clipped
    std::vector<uint32_t> draw;        // what is drawn, front to back (see above)
    // Frame vertices: the mesh's points, then the vertices the clip stage made.
    std::vector<glm::vec3> points_f;   // the vertex buffer: float positions relative to the eye
    std::vector<WindowCoord> win;      // what the rasterizer receives (float pipeline, FBO setup space)
    std::vector<glm::dvec3> win_d;     // x, y, 1 / w in double (the fragment stage's geometry)
    std::vector<glm::dvec3> eye;       // eye-space position in double (eye_space)
    std::vector<double> extra_s;       // normalized scalars of the clip stage's vertices
    std::vector<uint32_t> extra;       // 3 frame vertices per extra triangle
    std::vector<uint32_t> extra_face;  // per extra triangle: the mesh face it lies on, or kNearSection
    // Per frame vertex, the scalar as the paper's vertex program receives it (texture coordinate 0; --interpolation
    // gpu only). The rest of that program's output the GL driver's shader computes; the emulation takes it from
    // havs_paper_vertices.
    std::vector<float> s_f;
    uint32_t mesh_faces = 0;           // the mesh's face count: the first extra triangle's id
    HavsFrameConstants constants;
    uint64_t clipped_faces = 0;        // faces that crossed a plane and were drawn as clipped fans
    uint64_t culled_faces = 0;         // faces wholly outside one plane, not drawn
    uint64_t near_sections = 0;        // cells cut by the near plane, drawn through their sections
    uint64_t gpu_clipped = 0;          // drawn triangles with a vertex the GPU's frustum test would clip (expected 0)
    double sort_ms = 0.0, vertex_ms = 0.0, clip_ms = 0.0;

    // The three frame vertices of draw id `id`.
    const uint32_t* triangle(const HavsMesh& hm, uint32_t id) const
    {
        return id < mesh_faces ? &hm.faces()[3 * std::size_t(id)] : &extra[3 * std::size_t(id - mesh_faces)];
    }
};

// Sorts the faces, runs the vertex stage and the clip stage.
HavsFrameSetup setup_havs_frame(const HavsMesh& hm, const Camera& camera, int width, int height);

// The paper's vertex program per frame vertex, emulated (--interpolation gpu): the eye-space position (the model-view
// times the float position, as shaders/havs_vertex.vert computes it) and what triangle setup receives (window
// position, 1 / w). Only the emulated driver needs them, so the GL driver does not hold them.
struct HavsPaperVertices {
    std::vector<glm::vec3> eye;
    std::vector<SetupVertex> setup;
};
HavsPaperVertices havs_paper_vertices(const HavsFrameSetup& fs);

// The flat constants of draw id `id`. `side` is kSideExit when it lies on a boundary face (exact gaps): each driver
// keeps it where the rasterizer sees the triangle back-facing and makes it kSideEntry otherwise (the emulation from its
// setup's facing, the shader from gl_FrontFacing). A near-plane section is interior.
HavsFace havs_face_constants(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t id);
// The side alone (kSideExit or kSideInterior), for --interpolation gpu, where it travels as a flat attribute.
float havs_face_side(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t id);
// --entries paper: whether draw id `id` is an exit face, i.e. lies on a boundary face (exact gaps) the rasterizer sees
// back-facing (the sign of its fixed-point area, setup_triangle): its vertices then carry paper_exit_scalar(s).
bool havs_paper_exit(const HavsMesh& hm, const HavsFrameSetup& fs, uint32_t id);

// Runs f(i, v) in parallel (TBB) for every i in [0, count), v being the three frame vertices of draw id ids[i]. In
// depth order each triangle's vertex indices are a cache miss, so each task fetches them kPrefetchAhead triangles
// ahead: about one memory latency (~100 ns) of the GL drivers' work per triangle.
inline constexpr std::size_t kPrefetchAhead = 16;
template <class F>
void for_each_triangle(const HavsMesh& hm, const HavsFrameSetup& fs, const uint32_t* ids, std::size_t count, F&& f)
{
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            if (i + kPrefetchAhead < r.end()) __builtin_prefetch(fs.triangle(hm, ids[i + kPrefetchAhead]));
            f(i, fs.triangle(hm, ids[i]));
        }
    });
}

// The draw ids of fs.draw[first, first + count) that `submission` sends, in drawing order, into `out`. With covered,
// a triangle is left out when setup_triangle and covers_any_pixel find no pixel, except when the GPU would clip a
// vertex of the frame (fs.gpu_clipped): its coverage is not the emulation's there, and every triangle is sent.
void havs_sent_triangles(const HavsMesh& hm, const HavsFrameSetup& fs, std::size_t first, std::size_t count,
                         TriangleSubmission submission, std::vector<uint32_t>& out);

}  // namespace uvr::gpu
