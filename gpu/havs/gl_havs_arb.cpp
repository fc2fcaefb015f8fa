#include "gpu/havs/gl_havs_arb.h"

#include <chrono>
#include <cmath>
#include <vector>

#include "gpu/gl/gl_framebuffer.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "gpu/havs/gl_havs_stream.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

std::unique_ptr<ArbFunctions> load_arb_functions(const GlContext& ctx)
{
    auto f = std::make_unique<ArbFunctions>();
    auto load = [&](auto& member, const char* name) {
        member = reinterpret_cast<std::remove_reference_t<decltype(member)>>(ctx.proc_address(name));
        if (!member)
            throw InputError("", std::string("the GL context (") + ctx.info().summary() + ") lacks " + name +
                                     ", which the paper's ARB programs need (--backend arb: an OSMesa "
                                     "compatibility-profile context)");
    };
    load(f->GenProgramsARB, "glGenProgramsARB");
    load(f->DeleteProgramsARB, "glDeleteProgramsARB");
    load(f->BindProgramARB, "glBindProgramARB");
    load(f->ProgramStringARB, "glProgramStringARB");
    load(f->ProgramLocalParameter4fARB, "glProgramLocalParameter4fARB");
    load(f->MatrixMode, "glMatrixMode");
    load(f->LoadMatrixf, "glLoadMatrixf");
    load(f->EnableClientState, "glEnableClientState");
    load(f->DisableClientState, "glDisableClientState");
    load(f->ClientActiveTexture, "glClientActiveTexture");
    load(f->VertexPointer, "glVertexPointer");
    load(f->TexCoordPointer, "glTexCoordPointer");
    load(f->TextureBarrier, "glTextureBarrier");
    load(f->PointSize, "glPointSize");
    return f;
}

ArbProgram::ArbProgram(const GlContext& ctx, const ArbFunctions& arb, unsigned target, const std::string& name,
                       const std::string& text)
    : arb_(arb), target_(target)
{
    const GlFunctions& gl = ctx.gl();
    while (gl.GetError() != GL_NO_ERROR) {
    }
    arb_.GenProgramsARB(1, &id_);
    arb_.BindProgramARB(target_, id_);
    arb_.ProgramStringARB(target_, arb::kFormatAscii, GLsizei(text.size()), text.data());
    if (gl.GetError() != GL_NO_ERROR) {
        GLint position = -1;
        gl.GetIntegerv(arb::kErrorPosition, &position);
        const GLubyte* message = gl.GetString(arb::kErrorString);
        const std::string why = message ? reinterpret_cast<const char*>(message) : "";
        arb_.DeleteProgramsARB(1, &id_);
        throw InputError(name, "the ARB program does not load (character " + std::to_string(position) + "): " + why);
    }
}

ArbProgram::~ArbProgram() { arb_.DeleteProgramsARB(1, &id_); }

void ArbProgram::bind() const { arb_.BindProgramARB(target_, id_); }

void check_arb_options(const HavsOptions& o)
{
    auto refuse = [](const std::string& what) {
        throw InputError("", "--backend arb runs the paper's programs as printed: " + what);
    };
    if (o.k != kArbK) refuse("k is 6 (three textures of two entries), not " +
                                (o.k == kEveryFragment ? std::string("all") : std::to_string(o.k)));
    if (o.entries != EntryEncoding::paper) refuse("they need --entries paper (the scalar is the table coordinate)");
    if (o.segment != SegmentMode::table) refuse("they sample the pre-integrated table (--segment table)");
    if (o.threshold != 0.99f) refuse("their kill is at 0.99 (--threshold 0.99)");
    if (o.coverage != Coverage::gpu) refuse("the rasterizer covers the pixels (--coverage gpu)");
    if (o.interpolation != InterpolationMode::gpu) refuse("the rasterizer interpolates (--interpolation gpu)");
}

namespace {

// What the paper's vertex program reads per vertex: vertex.position (w defaults to 1) and vertex.texcoord[0].x.
struct ArbVertex {
    float position[3];
    float scalar;
};
static_assert(sizeof(ArbVertex) == 16);

const HavsOptions& checked(const GlContext& ctx, const HavsOptions& o)
{
    check_arb_options(o);
    if (ctx.info().version.find("Compatibility") == std::string::npos)
        throw InputError("", "--backend arb needs a compatibility-profile context, not " + ctx.info().summary());
    return o;
}

}  // namespace

struct ArbHavsRenderer::Objects {
    const GlFunctions& gl;
    std::unique_ptr<ArbFunctions> arb;
    std::unique_ptr<ArbProgram> vertex, fragment;
    GLuint buffer = 0, table_texture = 0;
    std::unique_ptr<GlFloatFramebuffer> framebuffer;  // colour (texture 0), the k-buffer (textures 1-3)

    explicit Objects(const GlFunctions& g) : gl(g) {}
    ~Objects()
    {
        framebuffer.reset();
        vertex.reset();
        fragment.reset();
        if (buffer) gl.DeleteBuffers(1, &buffer);
        if (table_texture) gl.DeleteTextures(1, &table_texture);
    }
};

ArbHavsRenderer::ArbHavsRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                                 const TransferFunction& tf, const HavsOptions& options)
    : ctx_(ctx), mesh_(mesh, topo, field, tf, checked(ctx, options))
{
    ctx_.make_current();
    gl_ = std::make_unique<Objects>(ctx_.gl());
    gl_->arb = load_arb_functions(ctx_);
    gl_->vertex = std::make_unique<ArbProgram>(ctx_, *gl_->arb, arb::kVertexProgram, shader_dir() + "/havs_paper.vp",
                                               read_shader_file("havs_paper.vp"));
    gl_->fragment = std::make_unique<ArbProgram>(ctx_, *gl_->arb, arb::kFragmentProgram,
                                                 shader_dir() + "/havs_paper.fp", read_shader_file("havs_paper.fp"));
    ctx_.gl().GenBuffers(1, &gl_->buffer);
    upload_preintegration_table(ctx_, *mesh_.table(), mesh_.options().filter, gl_->table_texture);
    gl_->framebuffer = std::make_unique<GlFloatFramebuffer>(ctx_, 1 + kArbK / 2, "the ARB HAVS framebuffer");
    ctx_.check_error("setting up the paper's ARB programs");
}

ArbHavsRenderer::~ArbHavsRenderer()
{
    ctx_.make_current();
    gl_.reset();
}

// Targets and textures: attachment i is texture i of the program (the paper's pbuffer and k-buffer), cleared to
// colour 0 and empty entries (-1, 0); the table on texture 4. Then the programs, their parameter and matrices, and the
// vertex arrays.
void ArbHavsRenderer::prepare_frame(const HavsFrameSetup& fs, int width, int height)
{
    const GlFunctions& gl = ctx_.gl();
    const ArbFunctions& arb = *gl_->arb;
    gl_->framebuffer->bind(width, height);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_CULL_FACE);
    const float zero[4] = {0, 0, 0, 0};
    const float empty[4] = {kEmptyEntry.x, kEmptyEntry.y, kEmptyEntry.x, kEmptyEntry.y};
    gl.ClearBufferfv(GL_COLOR, 0, zero);
    for (int t = 1; t <= kArbK / 2; ++t) gl.ClearBufferfv(GL_COLOR, t, empty);
    for (int i = 0; i <= kArbK / 2; ++i) {
        gl.ActiveTexture(GLenum(GL_TEXTURE0 + i));
        gl.BindTexture(GL_TEXTURE_2D, gl_->framebuffer->texture(i));
    }
    gl.ActiveTexture(GL_TEXTURE4);
    gl.BindTexture(GL_TEXTURE_3D, gl_->table_texture);

    // The programs, their parameter sz = {1/w, 1/h, (1 - 1/L) / max_len, 1/(2L)} and the matrices the vertex
    // program reads (state.matrix.mvp is the driver's product of these two: ViewSetup::driver_mvp).
    gl.Enable(arb::kVertexProgram);
    gl.Enable(arb::kFragmentProgram);
    gl_->vertex->bind();
    gl_->fragment->bind();
    const HavsFrameConstants& fc = fs.constants;
    arb.ProgramLocalParameter4fARB(arb::kFragmentProgram, 0, 1.0f / float(width), 1.0f / float(height),
                                   fc.length_scale, fc.length_bias);
    arb.MatrixMode(arb::kProjection);
    arb.LoadMatrixf(&fs.view.projection[0][0]);
    arb.MatrixMode(arb::kModelview);
    arb.LoadMatrixf(&fs.view.view[0][0]);
    gl.BindVertexArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, gl_->buffer);
    arb.EnableClientState(arb::kVertexArray);
    arb.VertexPointer(3, GL_FLOAT, sizeof(ArbVertex), nullptr);
    arb.ClientActiveTexture(GL_TEXTURE0);
    arb.EnableClientState(arb::kTexCoordArray);
    arb.TexCoordPointer(1, GL_FLOAT, sizeof(ArbVertex), reinterpret_cast<const void*>(offsetof(ArbVertex, scalar)));
    ctx_.check_error("preparing the paper's ARB programs");
}

// The geometry: each triangle's three vertices (an exit face's scalars negated: havs_paper_exit), in sorted order.
void ArbHavsRenderer::geometry_pass(const HavsFrameSetup& fs, HavsStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    const ArbFunctions& arb = *gl_->arb;
    draw_havs_stream<ArbVertex>(
        ctx_, mesh_, fs, triangles_per_draw_, submission_, st,
        [&](uint32_t id, const uint32_t* v, ArbVertex* out) {
            const bool exit = havs_paper_exit(mesh_, fs, id);
            for (std::size_t j = 0; j < 3; ++j) {
                const glm::vec3& p = fs.points_f[v[j]];
                const float s = exit ? paper_exit_scalar(fs.s_f[v[j]]) : fs.s_f[v[j]];
                out[j] = ArbVertex{{p.x, p.y, p.z}, s};
            }
        },
        [&] {
            if (barrier_) arb.TextureBarrier();
        });
    const auto t0 = Clock::now();
    gl.Finish();
    ctx_.check_error("the paper's programs on the geometry");
    st.raster_fragment_ms += ms_since(t0);
}

// The flush: k draws of a triangle over the whole screen whose fragments are kPaperFlushFragment: scalar -1 and the
// eye position (x, y, 2^60), |e| = 2^60 exactly (x and y within 3 vanish below 2^120's rounding). The model-view is
// the identity (so e is the position), the projection keeps x and y and puts z at 0.
void ArbHavsRenderer::flush_pass(HavsStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    const ArbFunctions& arb = *gl_->arb;
    const auto t0 = Clock::now();
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const float flat[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    arb.MatrixMode(arb::kProjection);
    arb.LoadMatrixf(flat);
    arb.MatrixMode(arb::kModelview);
    arb.LoadMatrixf(identity);
    const float far = kPaperFlushFragment.y, s = kPaperFlushFragment.x;
    const ArbVertex flush[3] = {{{-1, -1, far}, s}, {{3, -1, far}, s}, {{-1, 3, far}, s}};
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(sizeof(flush)), flush, GL_STREAM_DRAW);
    for (int run = 0; run < kArbK; ++run) {
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        if (barrier_) arb.TextureBarrier();
    }
    gl.Finish();
    ctx_.check_error("the paper's programs on the flush");
    st.flush_ms = ms_since(t0);
    gl.Disable(arb::kVertexProgram);
    gl.Disable(arb::kFragmentProgram);
    arb.DisableClientState(arb::kTexCoordArray);  // the context may serve another driver or harness next
    arb.DisableClientState(arb::kVertexArray);
}

// Read back the colour (exact for float attachments) into the frame.
void ArbHavsRenderer::read_frame(int width, int height, HavsFrame& out)
{
    const auto t0 = Clock::now();
    const std::vector<glm::vec4> colour = gl_->framebuffer->read(0);
    out.stats.readback_ms = ms_since(t0);
    store_havs_frame(colour.data(), nullptr, width, height, out);
}

HavsFrame ArbHavsRenderer::render(const Camera& cam, int width, int height)
{
    if (cam.orthographic)
        throw InputError("",
                         "--backend arb: the paper's fragment program takes the distance |e| to the eye, which "
                         "an orthographic view does not have; use a perspective camera");
    ctx_.make_current();
    HavsFrame out;
    HavsStats& st = out.stats;
    const HavsFrameSetup fs = begin_havs_frame(mesh_, cam, width, height, st);
    const auto t0 = Clock::now();
    prepare_frame(fs, width, height);
    st.setup_ms = fs.vertex_ms + fs.clip_ms + ms_since(t0);
    geometry_pass(fs, st);
    flush_pass(st);
    read_frame(width, height, out);
    return out;
}

}  // namespace uvr::gpu
