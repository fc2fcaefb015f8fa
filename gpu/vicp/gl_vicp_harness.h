// Runs VICP's GL shader stages alone on chosen inputs, for bit-for-bit comparison with their emulations (docs/spec.md
// §5, stage level), as gpu/havs/gl_havs_harness.h does for HAVS: the vertex program's constants (a point draw with the
// rasterizer discarding, written to a storage buffer); the fragment program's two parts, vicp_fragment_values and
// vicp_composite (one case per pixel of a full-screen pass); the published vertex program and its fragment program's
// exit (run_published_vertex, run_published_exit: --interpolation gpu). Inputs and outputs travel in storage buffers
// whose std430 layouts are the Gl* structs below (read back exactly). Twins: shaders/vicp_harness.vert and .frag (their
// mains); emulated stages gpu/vicp/vicp_vertex.h, gpu/vicp/vicp_fragment.h, gpu/vicp/vicp_published_vertex.h,
// gpu/vicp/vicp_published_fragment.h; GL uniforms gpu/vicp/gl_vicp_fragment.h. Tests only (library uvr_gl_harness).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "gpu/gl/gl_context.h"
#include "gpu/pipeline/preintegration_table.h"
#include "gpu/vicp/vicp_fragment.h"
#include "gpu/vicp/vicp_published_vertex.h"

namespace uvr::gpu {

// One case of the vertex program: vicp_tet_constants(shape, exact, s, boundary).
struct VicpVertexCase {
    glm::dvec3 shape[4], exact[4];
    double s[4] = {0, 0, 0, 0};
    uint32_t boundary = 0;
};

// `struct HarnessTet` of the harness shaders: VicpTet under std430, scalar arrays only.
struct GlVicpTet {
    double p0[3], m[9], det, base[3], me[9], g[3], s0;
    uint32_t boundary, pad;
};
static_assert(sizeof(GlVicpTet) == 240 && offsetof(GlVicpTet, det) == 96 && offsetof(GlVicpTet, boundary) == 232,
              "GlVicpTet must match the std430 layout of HarnessTet in shaders/vicp_harness.*");
GlVicpTet pack_vicp_tet(const VicpTet& t);
VicpTet unpack_vicp_tet(const GlVicpTet& g);

// One case of vicp_composite: the segment, the framebuffer colour and the diagnostics before it, and the colour
// vicp_shade returns (HarnessShade::per_case).
struct VicpCompositeCase {
    VicpSegment segment;
    glm::vec4 framebuffer{0.0f};
    VicpDiagnostics diagnostics;
    glm::vec4 shade{0.0f};
};
struct VicpCompositeResult {
    bool written = false;                 // false: killed (the renderer discards; nothing is written)
    glm::vec4 framebuffer{0.0f};          // the written colour (the input where killed)
    VicpDiagnostics diagnostics;          // the written diagnostics (the input where killed)
    glm::vec4 shade_args{-2.0f};          // (u_front, u_back, t_z, length) of the lookup; all -2 when none was made
};

class GlVicpHarness {
public:
    // Throws InputError when the context lacks storage buffers in the vertex stage.
    explicit GlVicpHarness(GlContext& ctx);
    ~GlVicpHarness();

    std::vector<VicpTet> run_vertex(const std::vector<VicpVertexCase>& cases);

    std::vector<VicpPublishedVaryings> run_published_vertex(const VicpPublishedView& view,
                                                            const std::vector<VicpPublishedVertex>& cases);
    std::vector<VicpPublishedExit> run_published_exit(const std::vector<VicpPublishedVaryings>& cases);

    std::vector<VicpSegment> run_values(const VicpFrameConstants& fc, const std::vector<VicpTet>& tets,
                                        const std::vector<glm::ivec2>& pixels);

    // With `table`, vicp_shade samples it as the renderer does (GL_LINEAR, CLAMP_TO_EDGE); without, it returns each
    // case's own colour.
    std::vector<VicpCompositeResult> run_composite(const VicpFrameConstants& fc,
                                                   const std::vector<VicpCompositeCase>& cases,
                                                   const PreintegrationTable* table = nullptr);

private:
    GlContext& ctx_;
    GLuint vao_ = 0;
    GLuint table_texture_ = 0;
    std::map<int, std::unique_ptr<GlProgram>> programs_;  // 0 vertex, 1 values, 2 composite, 3 composite + table,
                                                          // 4 published vertex, 5 published exit

    const GlProgram& program(int which);
};

}  // namespace uvr::gpu
