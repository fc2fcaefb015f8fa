// HAVS through the paper's own ARB programs (the HAVS paper, Appendices I and II; docs/spec.md §7, `--backend arb`):
// the witness that the emulated k-buffer program is the paper's. The programs are shaders/havs_paper.vp and
// shaders/havs_paper.fp, the appendices' text but for three repairs of the print, loaded with glProgramStringARB in an
// OSMesa compatibility context; k = 6, the k-buffer in RGBA32F textures bound both as render targets and as textures
// 0-3, the table on texture 4. The CPU stage is HAVS's own (gpu/havs/havs_setup.h) with --entries paper. Twins: the
// emulated driver gpu/havs/havs.h and the GLSL driver gpu/havs/gl_havs.h with the same options give the same bits;
// stage harness GlHavsArbHarness (gpu/havs/gl_havs_harness.h). Details: docs/havs-arb.md.
#pragma once

#include <memory>
#include <string>

#include "gpu/gl/gl_context.h"
#include "gpu/havs/havs.h"

namespace uvr::gpu {

inline constexpr int kArbK = 6;  // the paper's k-buffer: three textures of two entries

// The compatibility profile's names that glcorearb.h leaves out (values from the ARB_vertex_program,
// ARB_fragment_program and OpenGL 1.x specifications).
namespace arb {
constexpr GLenum kVertexProgram = 0x8620, kFragmentProgram = 0x8804, kFormatAscii = 0x8875;
constexpr GLenum kErrorPosition = 0x864B, kErrorString = 0x8874;
constexpr GLenum kModelview = 0x1700, kProjection = 0x1701;
constexpr GLenum kVertexArray = 0x8074, kTexCoordArray = 0x8078;
}  // namespace arb

// The entry points of ARB assembly programs and of the compatibility profile's vertex arrays and matrices.
struct ArbFunctions {
    void (*GenProgramsARB)(GLsizei, GLuint*) = nullptr;
    void (*DeleteProgramsARB)(GLsizei, const GLuint*) = nullptr;
    void (*BindProgramARB)(GLenum, GLuint) = nullptr;
    void (*ProgramStringARB)(GLenum, GLenum, GLsizei, const void*) = nullptr;
    void (*ProgramLocalParameter4fARB)(GLenum, GLuint, GLfloat, GLfloat, GLfloat, GLfloat) = nullptr;
    void (*MatrixMode)(GLenum) = nullptr;
    void (*LoadMatrixf)(const GLfloat*) = nullptr;
    void (*EnableClientState)(GLenum) = nullptr;
    void (*DisableClientState)(GLenum) = nullptr;
    void (*ClientActiveTexture)(GLenum) = nullptr;
    void (*VertexPointer)(GLint, GLenum, GLsizei, const void*) = nullptr;
    void (*TexCoordPointer)(GLint, GLenum, GLsizei, const void*) = nullptr;
    void (*TextureBarrier)() = nullptr;
    void (*PointSize)(GLfloat) = nullptr;
};

// One ARB program (GL_VERTEX_PROGRAM_ARB or GL_FRAGMENT_PROGRAM_ARB) from its text; `name` names it in errors.
// Throws InputError naming the file, the position and Mesa's message when the text does not load.
class ArbProgram {
public:
    ArbProgram(const GlContext& ctx, const ArbFunctions& arb, unsigned target, const std::string& name,
               const std::string& text);
    ~ArbProgram();
    ArbProgram(const ArbProgram&) = delete;
    ArbProgram& operator=(const ArbProgram&) = delete;
    void bind() const;  // binds and enables it on its target

private:
    const ArbFunctions& arb_;
    unsigned target_;
    unsigned id_ = 0;
};

// Loads the ARB entry points from a compatibility-profile context; throws InputError naming a missing one.
std::unique_ptr<ArbFunctions> load_arb_functions(const GlContext& ctx);

// What --backend arb accepts: k = 6, --entries paper, the table, threshold 0.99, the rasterizer's coverage (throws
// InputError naming the option otherwise).
void check_arb_options(const HavsOptions& o);

class ArbHavsRenderer {
public:
    // `ctx` must be a compatibility-profile OSMesa context (GlProfile::compatibility), current on this thread.
    ArbHavsRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                    const TransferFunction& tf, const HavsOptions& options);
    ~ArbHavsRenderer();
    ArbHavsRenderer(const ArbHavsRenderer&) = delete;
    ArbHavsRenderer& operator=(const ArbHavsRenderer&) = delete;

    // Renders one frame (perspective cameras only: the paper's distance is |e|) and reads the colour back. No
    // per-pixel diagnostics (the paper's program writes none).
    HavsFrame render(const Camera& camera, int width, int height);

    // Triangles per draw call, and whether glTextureBarrier follows each draw (docs/havs-arb.md, "Reading the
    // targets"). Neither changes a bit on llvmpipe; tests and the bench set them.
    void set_triangles_per_draw(std::size_t n) { triangles_per_draw_ = n ? n : kDefaultTrianglesPerDraw; }
    void set_barrier_after_each_draw(bool on) { barrier_ = on; }
    // Which triangles are sent (havs_sent_triangles): by default those that cover a pixel.
    void set_submission(TriangleSubmission s) { submission_ = s; }

    const HavsMesh& cpu_stage() const { return mesh_; }

private:
    static constexpr std::size_t kDefaultTrianglesPerDraw = std::size_t(1) << 17;  // 6 MiB of vertices a draw
    struct Objects;
    // The frame's stages (render): the targets cleared, the programs bound with their parameter and matrices; the
    // geometry pass; the k flush draws; the read-back.
    void prepare_frame(const HavsFrameSetup& fs, int width, int height);
    void geometry_pass(const HavsFrameSetup& fs, HavsStats& st);
    void flush_pass(HavsStats& st);
    void read_frame(int width, int height, HavsFrame& out);
    GlContext& ctx_;
    HavsMesh mesh_;
    std::size_t triangles_per_draw_ = kDefaultTrianglesPerDraw;
    bool barrier_ = false;
    TriangleSubmission submission_ = TriangleSubmission::covered;
    std::unique_ptr<Objects> gl_;
};

}  // namespace uvr::gpu
