// The published first two passes (Krüger and Westermann): the volume's box drawn with its texture coordinates as
// colour, front faces into one RGBA32F target (GL_LESS, depth cleared to 1), back faces into another (GL_GREATER,
// cleared to 0). raycast_box_frame is the CPU stage both drivers share (the box's triangles after the clip stage, with
// the near plane's section where the near plane cuts the box); raycast_box_pass is the emulated pass (coverage and the
// smooth texture coordinate as llvmpipe interpolates it, gpu/pipeline/interpolation.h). Twins:
// shaders/raycast_box.vert, shaders/raycast_box.frag; GL driver gpu/raycast/gl_raycast.h. Derivation (culling beside
// the depth test, the section, why one fragment a pixel): docs/raycast.md, "The published passes".
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/pipeline/interpolation.h"
#include "gpu/pipeline/view_setup.h"
#include "gpu/raycast/raycast_fragment.h"

namespace uvr::gpu {

// One vertex as the box pass's vertex buffer holds it: float position relative to the eye, texture coordinate.
struct RaycastBoxVertex {
    glm::vec3 position{0.0f};
    glm::vec3 tex{0.0f};
};

struct RaycastBoxFrame {
    int width = 0, height = 0;
    ViewSetup view;                           // origin: the eye; uvr's vertex program (clip_position)
    std::vector<RaycastBoxVertex> vertices;   // three a triangle, in drawing order (glDrawArrays(GL_TRIANGLES))
    std::vector<WindowCoord> win;             // per vertex: where the rasterizer puts it
    std::vector<SetupVertex> setup;           // per vertex: what attribute setup receives
    uint32_t clipped_faces = 0;               // box triangles the clip stage cut (drawn as fans)
    uint32_t culled_faces = 0;                // box triangles wholly outside a clip plane
    uint32_t near_sections = 0;               // triangles of the near plane's section (drawn facing the eye)
    uint32_t gpu_clipped = 0;                 // triangles the GPU would clip (0 unless the clip margins fail)
    std::size_t triangles() const { return vertices.size() / 3; }
};

RaycastBoxFrame raycast_box_frame(const RaycastFrameConstants& fc, const Camera& cam, const glm::dvec3& origin,
                                  int width, int height);

// One pass: per pixel (GL rows, from the bottom) the texture coordinate of the fragment that wrote it, alpha 1, or
// (0, 0, 0, 0) where none did. `overlaps` counts fragments that met a pixel already written: the depth test would
// decide there, which the emulation does not model; the box is drawn so that this cannot happen (docs/raycast.md).
struct RaycastBoxPass {
    std::vector<glm::vec4> position;
    uint64_t covered = 0;
    uint64_t overlaps = 0;
};

// Facing::front: the first pass; Facing::back: the second.
RaycastBoxPass raycast_box_pass(const RaycastBoxFrame& bf, Facing facing);

}  // namespace uvr::gpu
