// HAVS (Callahan, Ikits, Comba, Silva 2005; seed 000) emulated on the CPU as a GPU runs it: the faces sorted on the
// CPU (face_sort), each face's vertices through the vertex stage (havs_vertex), rasterized with llvmpipe's rules
// (rasterize), each fragment through the k-buffer program (havs_fragment), then the flush passes. docs/havs.md.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gpu/havs_fragment.h"
#include "gpu/preintegration_table.h"
#include "reference/camera.h"
#include "reference/image.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"
#include "reference/topology.h"

namespace uvr::gpu {

enum class SegmentMode { table, exact };  // --segment: the pre-integrated table, or the exact integral (emulation only)
enum class GapMode { exact, maxgap };     // --gaps: exit faces marked (exact), or VTK's maximum-gap heuristic

struct HavsOptions {
    int k = 6;
    SegmentMode segment = SegmentMode::table;
    GapMode gaps = GapMode::exact;
    float threshold = 0.99f;  // the opacity kill; 1 switches early termination off
    int table_size = 128;     // texels along each of the table's three axes
    TexelFormat table_format = TexelFormat::f32;
    double table_max_length = 0.0;  // 0: the mesh's longest edge (no segment inside one cell is longer)
    TextureFilter filter = TextureFilter::linear;
};

struct HavsStats {
    uint64_t faces = 0;
    uint64_t fragments = 0;
    uint64_t ordering_errors = 0;
    uint32_t max_fragments = 0;  // most fragments on one pixel
    uint32_t max_held = 0;       // most entries held at once on one pixel
    double sort_ms = 0, setup_ms = 0, raster_fragment_ms = 0, flush_ms = 0, table_ms = 0;
};

struct HavsFrame {
    Image image;
    // Per pixel, SPEC §2 order (row 0 at the top): fragments, most entries held at once, ordering errors.
    std::vector<uint32_t> fragments, max_held, ordering_errors;
    HavsStats stats;
};

class HavsRenderer {
public:
    HavsRenderer(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                 const HavsOptions& options);
    ~HavsRenderer();

    HavsFrame render(const Camera& camera, int width, int height) const;

    const HavsOptions& options() const { return options_; }
    double longest_edge() const { return longest_edge_; }

private:
    const TetMesh& mesh_;
    HavsOptions options_;
    SegmentIntegrator integrator_;
    Range range_;
    double longest_edge_ = 0.0;
    std::vector<glm::vec3> points_f_;   // float positions (the vertex buffer)
    std::vector<double> scalar_n_;      // normalized scalar per point
    std::vector<uint32_t> faces_;       // 3 indices per unique face
    std::vector<uint8_t> boundary_;     // 1 for a boundary face that can be an exit face (exact gaps)
    std::unique_ptr<PreintegrationTable> table_;
    double table_ms_ = 0.0;
};

}  // namespace uvr::gpu
