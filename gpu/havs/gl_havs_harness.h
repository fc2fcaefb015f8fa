// Runs GL shader stages alone on chosen inputs, for bit-for-bit comparison with their emulations (docs/spec.md §5,
// stage level). One test case per pixel of a full-screen pass (shaders/fullscreen.vert): the inputs are laid out as
// RGBA32F textures (read with texelFetch: the bits as uploaded) or shader storage buffers, the outputs are float FBO
// attachments read back with glReadPixels (exact for RGBA32F attachments). Large batches go in chunks of kHarnessWidth
// x kHarnessRows cases. Stages: HAVS's fragment program (shaders/havs_fragment.frag through
// shaders/havs_fragment_harness.frag), its two parts separately: havs_fragment_entry (face constants -> entry) and
// havs_kbuffer (stored entries, framebuffer colour, incoming entry -> written entries and colour); and havs_paper_side
// / havs_paper_entry (interpolated varyings -> entry). GlHavsArbHarness: the paper's own ARB fragment program
// (shaders/havs_paper.fp), whole. Twins: shaders/havs_fragment_harness.frag (its mains); emulated stage
// gpu/havs/havs_fragment.h; GL uniforms gpu/havs/gl_havs_fragment.h. Tests only (library uvr_gl_harness).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "gpu/gl/gl_context.h"
#include "gpu/havs/havs_fragment.h"
#include "gpu/pipeline/preintegration_table.h"

namespace uvr::gpu {

// Where havs_kbuffer's segment colour comes from: the case's own colour (isolates the k-buffer logic), or a lookup
// in a real 3D texture holding a PreintegrationTable (GL_LINEAR, CLAMP_TO_EDGE, as the renderer samples it).
enum class HarnessShade { per_case, table };

struct KBufferCases {
    int k = 6;
    std::vector<KEntry> incoming;        // one per case
    std::vector<KEntry> entries;         // k per case, a1..ak
    std::vector<glm::vec4> framebuffer;  // one per case
    std::vector<glm::vec4> shade;        // one per case (HarnessShade::per_case)
    std::size_t size() const { return incoming.size(); }
};

struct KBufferResults {
    std::vector<uint8_t> written;          // 0: the fragment was discarded (every output kept its clear value)
    std::vector<KEntry> entries;           // k per case: the written entries (the inputs where discarded)
    std::vector<glm::vec4> framebuffer;    // the written colour (the input where discarded)
    std::vector<glm::vec4> shade_args;     // (u_front, u_back, t_z, length) of the lookup; all -2 when none was made
};

class GlHavsFragmentHarness {
public:
    explicit GlHavsFragmentHarness(GlContext& ctx);
    ~GlHavsFragmentHarness();

    // The largest k this context's draw buffers allow here: colour, lookup arguments, then two entries per target.
    int max_k() const;

    // havs_kbuffer on every case. `table` is needed for HarnessShade::table.
    KBufferResults run_kbuffer(const HavsFrameConstants& fc, const KBufferCases& cases, HarnessShade shade,
                               const PreintegrationTable* table = nullptr);

    // havs_fragment_entry(fc, faces[i], pixels[i].x, pixels[i].y) for every i. `values`, when given, receives the
    // double fragment values before their rounding to float (havs_fragment_values: side * (1 + s), distance).
    std::vector<KEntry> run_entry(const HavsFrameConstants& fc, const std::vector<HavsFace>& faces,
                                  const std::vector<glm::ivec2>& pixels, std::vector<glm::dvec2>* values = nullptr);

    // --interpolation gpu: havs_paper_entry(fc, v[i]) with the side havs_paper_side(v[i].side, corners[i]) for every
    // i: (x, distance, side) per case.
    std::vector<glm::vec4> run_paper(const HavsFrameConstants& fc, const std::vector<HavsVaryings>& v,
                                     const std::vector<glm::vec3>& corners);

private:
    GlContext& ctx_;
    GLuint vao_ = 0;
    std::map<std::pair<int, int>, std::unique_ptr<GlProgram>>
        programs_;  // (k; 0 entry, -1 the paper's entry; shade mode)
    GLuint table_texture_ = 0;

    const GlProgram& program(int k, int mode);
    void upload_table(const PreintegrationTable& table);
};

// The paper's ARB fragment program (shaders/havs_paper.fp) alone, k = 6, on a compatibility-profile context: one case
// a pixel, drawn as a point of size 1 at the pixel centre (clip w = 1) through a pass-through ARB vertex program, so
// that the fragment receives its texture coordinates unchanged; the framebuffer colour and the stored entries are the
// initial contents of textures 0-3, which are also the render targets (the paper's read-modify-write).
struct ArbKBufferCases {
    std::vector<float> scalar;           // texture coordinate 0's x (the incoming scalar), one per case
    std::vector<glm::vec3> eye;          // texture coordinate 1 (the eye-space position), one per case
    std::vector<KEntry> entries;         // 6 per case, a1..a6
    std::vector<glm::vec4> framebuffer;  // one per case
    std::size_t size() const { return scalar.size(); }
};
struct ArbKBufferResults {
    std::vector<KEntry> entries;         // 6 per case, as the program left them
    std::vector<glm::vec4> framebuffer;  // one per case
};

class GlHavsArbHarness {
public:
    explicit GlHavsArbHarness(GlContext& ctx);  // a compatibility-profile context
    ~GlHavsArbHarness();
    // The program's local parameter sz.zw are `length_scale` and `length_bias`; texture 4 holds `table`.
    ArbKBufferResults run(const PreintegrationTable& table, float length_scale, float length_bias,
                          const ArbKBufferCases& cases);

private:
    struct Objects;
    GlContext& ctx_;
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
