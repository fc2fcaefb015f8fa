// HAVS (Callahan, Ikits, Comba, Silva 2005; the HAVS paper) emulated on the CPU as a GPU runs it: the faces sorted on
// the CPU (face_sort), each face's vertices through the vertex stage (view_setup, clip_position), the clip stage
// (clip), rasterized with llvmpipe's rules (rasterize), each fragment through the k-buffer program (havs_fragment),
// then the flush passes. Input: a mesh, its topology, a field, a transfer function, HavsOptions; per frame a camera and
// a size. Output: HavsFrame (the image, per-pixel diagnostics, stage times). docs/havs.md. Twins: shaders/havs.frag
// (the passes' main); GL driver gpu/havs/gl_havs.h; GL uniforms gpu/havs/gl_havs_fragment.h; harness
// gpu/havs/gl_havs_harness.h.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gpu/havs/havs_fragment.h"
#include "gpu/havs/havs_setup.h"
#include "reference/camera.h"
#include "reference/image.h"

namespace uvr::gpu {

struct HavsStats {
    uint64_t faces = 0;
    uint64_t fragments = 0;
    uint64_t ordering_errors = 0;
    uint32_t max_fragments = 0;  // most fragments on one pixel
    uint32_t max_held = 0;       // most entries held at once on one pixel
    double sort_ms = 0, setup_ms = 0, raster_fragment_ms = 0, flush_ms = 0, table_ms = 0;
    double readback_ms = 0;  // the GL backend's glReadPixels (0 in the emulation)
    uint32_t draws = 0;      // the GL backend's geometry draw calls
    // The clip stage (gpu/pipeline/clip.h): triangles drawn, faces clipped into fans, faces culled, near-plane sections
    // drawn, and drawn triangles with a vertex the GPU's frustum test would clip (0 unless the clip stage's margins
    // failed: there the GL frame may differ from the emulated one).
    uint64_t triangles = 0, clipped_faces = 0, culled_faces = 0, near_sections = 0, gpu_clipped = 0;
    // The GL backends: drawn triangles not sent because they cover no pixel (havs_sent_triangles; 0 in the emulation,
    // whose tiles skip them).
    uint64_t uncovered = 0;
};

struct HavsFrame {
    Image image;
    // Per pixel, docs/spec.md §2 order (row 0 at the top): fragments, most entries held at once, ordering errors.
    std::vector<uint32_t> fragments, max_held, ordering_errors;
    HavsStats stats;
};

// The end of a frame, for both backends: the per-pixel colour (width * height values) and diagnostics (GL rows, from
// the bottom) into `out` (image rows (row 0 on top)), with the diagnostics summed into out.stats. Without diagnostics
// the frame's vectors stay empty.
void store_havs_frame(const glm::vec4* colour, const std::vector<KBufferDiagnostics>* diagnostics,
                      int width, int height, HavsFrame& out);

// The start of a frame, for every backend: the CPU stage (setup_havs_frame) and what it tells the frame's statistics
// (the table's build time, the faces, the sort's time, the clip stage's counts).
HavsFrameSetup begin_havs_frame(const HavsMesh& mesh, const Camera& cam, int width, int height, HavsStats& st);

class HavsRenderer {
public:
    // Without `diagnostics` the frame has no per-pixel counts (as the GL driver's without its attachment): no
    // bookkeeping per fragment, 16 bytes a pixel fewer. The image's bits are the same.
    HavsRenderer(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                 const HavsOptions& options, bool diagnostics = true);
    ~HavsRenderer();

    HavsFrame render(const Camera& camera, int width, int height) const;

    const HavsOptions& options() const { return mesh_.options(); }
    double longest_edge() const { return mesh_.longest_edge(); }
    const HavsMesh& cpu_stage() const { return mesh_; }

private:
    HavsMesh mesh_;
    bool diagnostics_;
};

}  // namespace uvr::gpu
