#include "gpu/havs/gl_havs.h"

#include <algorithm>
#include <cstddef>
#include <chrono>
#include <string>
#include <vector>

#include "gpu/gl/gl_framebuffer.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "gpu/havs/gl_havs_fragment.h"
#include "gpu/havs/gl_havs_stream.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

namespace {

int entry_targets(int k) { return (k + 1) / 2; }

// The face constants of one draw, at most: 16 MiB (116,508 faces). Each draw's constants and element indices are
// uploaded just before it, and llvmpipe keeps a draw's buffers until the scene that reads it is rasterized, so
// what the GL side holds grows with this size: at 10.1 M tetrahedra (20.3 M faces) the whole frame's element buffer
// (12 bytes a face, twice: the CPU's and Mesa's) and 128 MiB chunks (the block size) peaked at 266 bytes per
// tetrahedron, 16 MiB chunks with per-chunk indices at 187 (8 MiB: 186). The frame time does not move with it (Blunt
// Fin, 512 x 512: 0.69-0.73 s with 128, 16 or 8 MiB). docs/results.md, "Memory".
constexpr std::size_t kFaceBytesPerDraw = std::size_t(16) << 20;

// --interpolation gpu: what the paper's vertex program reads per vertex. The vertices are not shared (a face's three
// carry its side, a per-face attribute), so a triangle sends 3 x 20 bytes.
struct PaperVertex {
    float position[3];
    float scalar;
    float side;
};
static_assert(sizeof(PaperVertex) == 20);

}  // namespace

struct GlHavsRenderer::Objects {
    const GlFunctions& gl;
    std::unique_ptr<GlProgram> geometry, flush;
    GLuint mesh_vao = 0, empty_vao = 0, paper_vao = 0;
    GLuint vertex_buffer = 0, element_buffer = 0, face_buffer = 0, paper_buffer = 0;
    GLuint table_texture = 0, face_texture = 0;
    std::unique_ptr<GlFloatFramebuffer> framebuffer;  // colour, k-buffer targets, diagnostics

    explicit Objects(const GlFunctions& g) : gl(g) {}
    ~Objects()
    {
        framebuffer.reset();
        geometry.reset();
        flush.reset();
        const GLuint buffers[] = {vertex_buffer, element_buffer, face_buffer, paper_buffer};
        gl.DeleteBuffers(4, buffers);
        const GLuint vaos[] = {mesh_vao, empty_vao, paper_vao};
        gl.DeleteVertexArrays(3, vaos);
        if (table_texture) gl.DeleteTextures(1, &table_texture);
        if (face_texture) gl.DeleteTextures(1, &face_texture);
    }
};

std::size_t GlHavsRenderer::faces_per_draw() const
{
    if (faces_per_draw_) return faces_per_draw_;
    GLint64 texels = 0;
    ctx_.gl().GetInteger64v(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    const std::size_t bytes = std::min<std::size_t>(16 * std::size_t(std::max<GLint64>(texels, 0)), kFaceBytesPerDraw);
    return std::max<std::size_t>(1, bytes / sizeof(GlHavsFace));
}

int GlHavsRenderer::max_k(const GlInfo& info, bool diagnostics)
{
    const int targets = std::min(info.max_draw_buffers, info.max_color_attachments) - 1 - (diagnostics ? 1 : 0);
    return std::max(0, 2 * targets);
}

namespace {

const HavsOptions& checked_gl_options(const GlContext& ctx, const HavsOptions& o, bool diagnostics,
                                      FramebufferAccess access)
{
    const GlInfo& info = ctx.info();
    choose_fragment_access(info, access, "HAVS");
    if (o.segment == SegmentMode::exact)
        throw InputError("", "--segment exact runs only in the emulation (--backend emu): on a GPU the fragment "
                             "program samples the pre-integrated table");
    if (o.coverage == Coverage::exact)
        throw InputError("", "--coverage exact runs only in the emulation (--backend emu): a GPU's rasterizer snaps");
    if (o.k == kEveryFragment)
        throw InputError("", "--k all runs only in the emulation (--backend emu): a GPU's k-buffer has a fixed depth");
    const int kmax = GlHavsRenderer::max_k(info, diagnostics);
    if (o.k < 1 || o.k > kmax)
        throw InputError("", "--k must be between 1 and " + std::to_string(kmax) + " with --backend gl on " +
                                 info.renderer + " (" + std::to_string(info.max_draw_buffers) + " draw buffers" +
                                 (diagnostics ? ", one of them for the diagnostics)" : ")"));
    return o;
}
}  // namespace

GlHavsRenderer::HavsProgramSources GlHavsRenderer::program_sources(int k, bool diagnostics, bool paper_entries,
                                                                   bool published, const FragmentAccessPath& path)
{
    std::vector<std::pair<std::string, std::string>> defines = {
        {"HAVS_K", std::to_string(k)}, {"HAVS_TARGETS", std::to_string(entry_targets(k))}};
    if (diagnostics) defines.push_back({"HAVS_DIAGNOSTICS", "1"});
    if (paper_entries) defines.push_back({"HAVS_PAPER_ENTRIES", "1"});
    std::vector<std::string> extensions;
    if (!path.extension.empty()) extensions.push_back(path.extension);
    if (path.images) defines.push_back({"HAVS_KBUFFER_IMAGES", "1"});
    if (!path.interlock.empty()) defines.push_back({"HAVS_INTERLOCK_" + path.interlock, "1"});
    const std::vector<std::string> files = {"preintegration_table.frag", "havs_fragment.frag", "havs.frag"};
    std::vector<std::pair<std::string, std::string>> geometry_defines = defines, vertex_defines;
    if (published) {
        geometry_defines.push_back({"HAVS_PAPER_VARYINGS", "1"});
        vertex_defines.push_back({"HAVS_PAPER_VARYINGS", "1"});
    }
    std::vector<std::pair<std::string, std::string>> flush_defines = defines;
    flush_defines.push_back({"HAVS_PASS_FLUSH", "1"});
    return {{{"clip_position.vert", "havs_vertex.vert"}, vertex_defines, {}},
            {files, geometry_defines, extensions},
            {{"fullscreen.vert"}, {}, {}},
            {files, flush_defines, extensions}};
}

GlHavsRenderer::GlHavsRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                               const TransferFunction& tf, const HavsOptions& options, bool diagnostics,
                               FramebufferAccess access)
    : ctx_(ctx),
      mesh_(mesh, topo, field, tf, checked_gl_options(ctx, options, diagnostics, access)),
      diagnostics_(diagnostics)
{
    const FragmentAccessPath path = choose_fragment_access(ctx.info(), access, "HAVS");
    images_ = path.images;
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    gl_ = std::make_unique<Objects>(gl);
    const int k = mesh_.options().k;

    const HavsProgramSources src =
        program_sources(k, diagnostics_, mesh_.options().entries == EntryEncoding::paper,
                        mesh_.options().interpolation == InterpolationMode::gpu, path);
    gl_->geometry = std::make_unique<GlProgram>(ctx_, src.geometry_vertex, src.geometry_fragment);
    gl_->flush = std::make_unique<GlProgram>(ctx_, src.flush_vertex, src.flush_fragment);

    // The vertex buffer (the frame's float positions relative to the eye, filled each frame) and the element buffer,
    // in one vertex array.
    gl.GenVertexArrays(1, &gl_->mesh_vao);
    gl.GenVertexArrays(1, &gl_->empty_vao);
    gl.BindVertexArray(gl_->mesh_vao);
    gl.GenBuffers(1, &gl_->vertex_buffer);
    gl.BindBuffer(GL_ARRAY_BUFFER, gl_->vertex_buffer);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
    gl.EnableVertexAttribArray(0);
    gl.GenBuffers(1, &gl_->element_buffer);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, gl_->element_buffer);
    // --interpolation gpu: the stream of unshared vertices (PaperVertex), filled per draw.
    gl.GenVertexArrays(1, &gl_->paper_vao);
    gl.BindVertexArray(gl_->paper_vao);
    gl.GenBuffers(1, &gl_->paper_buffer);
    gl.BindBuffer(GL_ARRAY_BUFFER, gl_->paper_buffer);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(PaperVertex), nullptr);
    gl.VertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(PaperVertex),
                           reinterpret_cast<const void*>(offsetof(PaperVertex, scalar)));
    gl.VertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(PaperVertex),
                           reinterpret_cast<const void*>(offsetof(PaperVertex, side)));
    for (GLuint a = 0; a < 3; ++a) gl.EnableVertexAttribArray(a);
    gl.BindVertexArray(0);
    gl.GenBuffers(1, &gl_->face_buffer);
    gl.GenTextures(1, &gl_->face_texture);

    upload_preintegration_table(ctx_, *mesh_.table(), mesh_.options().filter, gl_->table_texture);
    gl_->framebuffer = std::make_unique<GlFloatFramebuffer>(ctx_, 1 + entry_targets(k) + (diagnostics_ ? 1 : 0),
                                                            "the HAVS framebuffer");
    ctx_.check_error("setting up HAVS on GL");
}

GlHavsRenderer::~GlHavsRenderer()
{
    ctx_.make_current();
    gl_.reset();
}

void GlHavsRenderer::use_program(const GlProgram& p, const HavsFrameSetup& fs)
{
    ctx_.gl().UseProgram(p.id());
    set_havs_frame_uniforms(ctx_, p, fs.constants);
}

void GlHavsRenderer::prepare_frame(const HavsFrameSetup& fs, int width, int height)
{
    const GlFunctions& gl = ctx_.gl();
    const int targets = entry_targets(mesh_.options().k);
    const bool published = mesh_.options().interpolation == InterpolationMode::gpu;
    if (!published) {  // --interpolation exact: the shared vertices, drawn by index (the paper's stream is per draw)
        gl.BindVertexArray(gl_->mesh_vao);
        gl.BindBuffer(GL_ARRAY_BUFFER, gl_->vertex_buffer);
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(fs.points_f.size() * sizeof(glm::vec3)), fs.points_f.data(),
                      GL_STREAM_DRAW);
    }
    gl_->framebuffer->bind(width, height);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_CULL_FACE);
    // Cleared as the emulation starts: colour 0, every entry empty (-1, 0), diagnostics 0.
    const float zero[4] = {0, 0, 0, 0};
    const float empty[4] = {kEmptyEntry.x, kEmptyEntry.y, kEmptyEntry.x, kEmptyEntry.y};
    gl.ClearBufferfv(GL_COLOR, 0, zero);
    for (int t = 0; t < targets; ++t) gl.ClearBufferfv(GL_COLOR, 1 + t, empty);
    if (diagnostics_) gl.ClearBufferfv(GL_COLOR, 1 + targets, zero);
    if (images_) {
        // The attachments as images (unit i for attachment i); the passes write no colour output, so the colour
        // mask keeps the framebuffer from writing undefined values over them.
        for (int i = 0; i < 1 + targets + (diagnostics_ ? 1 : 0); ++i)
            gl.BindImageTexture(GLuint(i), gl_->framebuffer->texture(i), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    }
    use_program(*gl_->geometry, fs);
    const Mat4f& mvp = published ? fs.view.driver_mvp : fs.view.mvp;  // the paper's program reads state.matrix.mvp
    gl.UniformMatrix4fv(gl_->geometry->uniform("havs_mvp", true), 1, GL_FALSE, &mvp[0][0]);
    if (published) gl.UniformMatrix4fv(gl_->geometry->uniform("havs_mv", true), 1, GL_FALSE, &fs.view.view[0][0]);
    ctx_.check_error("preparing the HAVS geometry pass");
}

// The triangles in drawing order, in draws of faces_per_draw() (GL keeps primitive order across draws, so the pixels
// see the same sequence as from one draw). Each draw's data are built and uploaded just before it: neither the CPU
// nor Mesa holds more than a few chunks of them.
void GlHavsRenderer::geometry_pass(const HavsFrameSetup& fs, HavsStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    const std::size_t chunk = faces_per_draw();
    if (mesh_.options().interpolation == InterpolationMode::gpu) {
        // --interpolation gpu: each triangle's three vertices with the paper's attributes, drawn in order.
        const bool paper_entries = mesh_.options().entries == EntryEncoding::paper;
        gl.BindVertexArray(gl_->paper_vao);
        gl.BindBuffer(GL_ARRAY_BUFFER, gl_->paper_buffer);
        draw_havs_stream<PaperVertex>(
            ctx_, mesh_, fs, chunk, submission_, st,
            [&](uint32_t id, const uint32_t* v, PaperVertex* out) {
                float side = havs_face_side(mesh_, fs, id);
                bool exit = false;
                if (paper_entries) {  // the mark travels in the scalar (havs_paper_exit), the side stays interior
                    exit = havs_paper_exit(mesh_, fs, id);
                    side = kSideInterior;
                }
                for (std::size_t j = 0; j < 3; ++j) {
                    const glm::vec3& p = fs.points_f[v[j]];
                    const float s = exit ? paper_exit_scalar(fs.s_f[v[j]]) : fs.s_f[v[j]];
                    out[j] = PaperVertex{{p.x, p.y, p.z}, s, side};
                }
            },
            [] {});
    } else {
        // --interpolation exact: each draw's face records and vertex indices.
        std::vector<GlHavsFace> records(std::min(chunk, fs.draw.size()));
        std::vector<uint32_t> indices(3 * records.size());
        gl.BindBuffer(GL_TEXTURE_BUFFER, gl_->face_buffer);
        draw_havs_chunks(
            ctx_, mesh_, fs, chunk, submission_, st,
            [&](const std::vector<uint32_t>& sent) {
                const std::size_t n = sent.size();
                for_each_triangle(mesh_, fs, sent.data(), n, [&](std::size_t i, const uint32_t* v) {
                    records[i] = pack_havs_face(havs_face_constants(mesh_, fs, sent[i]));
                    for (std::size_t j = 0; j < 3; ++j) indices[3 * i + j] = v[j];
                });
                gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(n * sizeof(GlHavsFace)), records.data(), GL_STREAM_DRAW);
                bind_havs_face_records(ctx_, gl_->face_texture, gl_->face_buffer);
                gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(3 * n * sizeof(uint32_t)), indices.data(),
                              GL_STREAM_DRAW);
            },
            [&](std::size_t n) { gl.DrawElements(GL_TRIANGLES, GLsizei(3 * n), GL_UNSIGNED_INT, nullptr); });
    }
    const auto t0 = Clock::now();
    gl.Finish();
    ctx_.check_error("the HAVS geometry pass");
    st.raster_fragment_ms += ms_since(t0);
}

// One full-screen pass running the program k times on the flush fragment (shaders/havs.frag).
void GlHavsRenderer::flush_pass(const HavsFrameSetup& fs, HavsStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    const auto t0 = Clock::now();
    if (images_) gl.MemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // the geometry pass's stores, for its loads
    use_program(*gl_->flush, fs);
    gl.BindVertexArray(gl_->empty_vao);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.Finish();
    if (images_) {
        gl.MemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);  // for glReadPixels
        gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    ctx_.check_error("the HAVS flush passes");
    st.flush_ms = ms_since(t0);
    gl.BindVertexArray(0);
}

// Read back (exact for float attachments), flipping GL rows to image rows (row 0 on top). The diagnostics attachment
// holds havs_diag: counts as exact floats.
void GlHavsRenderer::read_frame(int width, int height, HavsFrame& out)
{
    const auto t0 = Clock::now();
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    const std::vector<glm::vec4> colour = gl_->framebuffer->read(0);
    std::vector<glm::vec4> diag;
    if (diagnostics_) diag = gl_->framebuffer->read(1 + entry_targets(mesh_.options().k));
    out.stats.readback_ms = ms_since(t0);
    std::vector<KBufferDiagnostics> counts;
    if (diagnostics_) {
        counts.resize(npix);
        for (std::size_t p = 0; p < npix; ++p)
            counts[p] = {uint32_t(diag[p].x), uint32_t(diag[p].y), uint32_t(diag[p].z), diag[p].w};
    }
    store_havs_frame(colour.data(), diagnostics_ ? &counts : nullptr, width, height, out);
}

HavsFrame GlHavsRenderer::render(const Camera& cam, int width, int height)
{
    ctx_.make_current();
    HavsFrame out;
    HavsStats& st = out.stats;
    // CPU stage: sort, vertex stage, clip stage; then the frame's buffers and uniforms.
    const HavsFrameSetup fs = begin_havs_frame(mesh_, cam, width, height, st);
    const auto t0 = Clock::now();
    prepare_frame(fs, width, height);
    st.setup_ms = fs.vertex_ms + fs.clip_ms + ms_since(t0);
    geometry_pass(fs, st);
    flush_pass(fs, st);
    read_frame(width, height, out);
    return out;
}

}  // namespace uvr::gpu
