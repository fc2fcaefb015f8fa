// GPU ray casting of regular grids (Krüger and Westermann) emulated on the CPU as llvmpipe runs it: one full-screen
// pass whose fragment program (raycast_fragment) finds the pixel's ray through the volume's box and marches it through
// the 3D texture. The CPU stage (raycast_setup) is shared with the GL driver (gl_raycast). docs/raycast.md. Twins:
// shaders/raycast.frag (the pass's main); GL driver gpu/raycast/gl_raycast.h; harness gpu/raycast/gl_raycast_harness.h.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/raycast/raycast_box.h"
#include "gpu/raycast/raycast_setup.h"
#include "reference/image.h"

namespace uvr::gpu {

struct RaycastStats {
    uint64_t rays = 0;         // pixels whose ray meets the box
    uint64_t samples = 0;      // texture positions classified, all pixels
    uint32_t max_samples = 0;  // most on one pixel
    // The published passes (--interpolation gpu; gpu/raycast/raycast_box.h): the box's triangles drawn, those the clip
    // stage made or cut, pixels with an entry, pixels with an entry and no exit (no samples), and fragments that met
    // a pixel already written in a pass (0: the depth test never decides; emulation only).
    uint64_t box_triangles = 0, near_sections = 0, clipped_faces = 0, gpu_clipped = 0;
    uint64_t entries = 0, unpaired = 0, overlaps = 0;
    double table_ms = 0, setup_ms = 0, march_ms = 0, readback_ms = 0;
};

struct RaycastFrame {
    Image image;
    std::vector<uint32_t> samples;  // per pixel, docs/spec.md §2 order
    RaycastStats stats;
};

// The box frame's counts into `st` (both backends).
void count_raycast_box(const RaycastBoxFrame& bf, RaycastStats& st);

// The end of a frame, for both backends: colour and samples per pixel (GL rows, from the bottom) into `out`.
void store_raycast_frame(const std::vector<glm::vec4>& colour, const std::vector<uint32_t>& samples, int width,
                         int height, RaycastFrame& out);

class RaycastRenderer {
public:
    RaycastRenderer(const Volume& volume, const TransferFunction& tf, const RaycastOptions& options);
    RaycastFrame render(const Camera& camera, int width, int height) const;
    const RaycastVolume& cpu_stage() const { return volume_; }

private:
    RaycastVolume volume_;
};

}  // namespace uvr::gpu
