#include "gpu/vicp/gl_vicp.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gpu/gl/gl_framebuffer.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "gpu/vicp/gl_vicp_fragment.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

namespace {

// The storage buffers of shaders/vicp.vert, by binding.
enum Binding : GLuint { kStream = 0, kPointsF = 1, kPointsD = 2, kScalars = 3, kSnapped = 4, kFans = 5, kBindings = 6 };

static_assert(sizeof(VicpCell) == 5 * sizeof(uint32_t), "shaders/vicp.vert reads a VicpCell as five uints");

GLint64 max_block_bytes(const GlContext& ctx)
{
    GLint64 block = 0;
    ctx.gl().GetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    return block;
}

const VicpOptions& checked_gl_options(const GlContext& ctx, const TetMesh& mesh, std::size_t field,
                                      const VicpOptions& o, FramebufferAccess access)
{
    const GlInfo& info = ctx.info();
    choose_fragment_access(info, access, "VICP");
    GLint blocks = 0;
    ctx.gl().GetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &blocks);
    if (blocks < GLint(kBindings))
        throw InputError("", "the GL context (" + info.summary() + ") has " + std::to_string(blocks) +
                                 " storage buffers in the vertex stage; the GL backend of VICP needs " +
                                 std::to_string(int(kBindings)) + "; use --backend emu");
    if (o.segment == SegmentMode::exact)
        throw InputError("", "--segment exact runs only in the emulation (--backend emu): on a GPU the fragment "
                             "program samples the pre-integrated table");
    if (o.coverage == Coverage::exact)
        throw InputError("", "--coverage exact runs only in the emulation (--backend emu): a GPU's rasterizer snaps");
    // The per-point arrays are read at any index by every draw: each must fit one storage block. A cell field is
    // drawn on four points a cell (gpu/pipeline/drawn_mesh.h).
    const bool cell_field = mesh.fields.at(field).association == FieldAssociation::cell;
    const std::size_t points = cell_field ? 4 * mesh.tets.size() : mesh.points.size();
    const double point_bytes = 3.0 * sizeof(double) * double(points);
    if (point_bytes > double(max_block_bytes(ctx)))
        throw InputError("", "the mesh's " + std::to_string(points) +
                                 " points exceed what the GL backend of VICP holds on " + info.renderer + " (" +
                                 std::to_string(max_block_bytes(ctx) / 24) +
                                 " points: one storage block of doubles); use --backend emu");
    return o;
}

}  // namespace

struct GlVicpRenderer::Objects {
    const GlFunctions& gl;
    std::unique_ptr<GlProgram> program;
    GLuint vao = 0;
    GLuint buffers[kBindings] = {};
    // --interpolation gpu: the published program and ProjectTet's records as vertex attributes, a chunk at a time.
    std::unique_ptr<GlProgram> published_program;
    GLuint published_vao = 0, published_vbo = 0;
    std::vector<VicpPublishedVertex> records;  // the chunk being sent
    std::vector<uint32_t> first_face;
    std::vector<uint8_t> faces;
    GLuint table_texture = 0;
    std::unique_ptr<GlFloatFramebuffer> framebuffer;  // colour, diagnostics

    explicit Objects(const GlFunctions& g) : gl(g) {}
    ~Objects()
    {
        framebuffer.reset();
        program.reset();
        published_program.reset();
        gl.DeleteBuffers(kBindings, buffers);
        if (vao) gl.DeleteVertexArrays(1, &vao);
        if (published_vao) gl.DeleteVertexArrays(1, &published_vao);
        if (published_vbo) gl.DeleteBuffers(1, &published_vbo);
        if (table_texture) gl.DeleteTextures(1, &table_texture);
    }
    void upload(Binding b, const void* data, std::size_t bytes, GLenum usage)
    {
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[b]);
        gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), data, usage);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, buffers[b]);
    }
};

std::size_t GlVicpRenderer::cells_per_draw() const
{
    if (cells_per_draw_) return cells_per_draw_;
    return std::max<std::size_t>(1, std::size_t(max_block_bytes(ctx_)) / sizeof(VicpCell));
}

GlVicpRenderer::VicpProgramSources GlVicpRenderer::program_sources(const FragmentAccessPath& path)
{
    // The compositing's route (shaders/vicp_framebuffer.frag).
    std::vector<std::pair<std::string, std::string>> defines;
    if (path.images) defines.push_back({"VICP_IMAGES", "1"});
    if (!path.interlock.empty()) defines.push_back({"VICP_INTERLOCK_" + path.interlock, "1"});
    std::vector<std::string> extensions;
    if (!path.extension.empty()) extensions.push_back(path.extension);
    return {{{"clip_position.vert", "vicp_tet.glsl", "vicp_vertex.vert", "vicp.vert"}, {}, {}},
            {{"vicp_tet.glsl", "preintegration_table.frag", "vicp_fragment.frag", "vicp_framebuffer.frag", "vicp.frag"},
             defines,
             extensions},
            {{"clip_position.vert", "vicp_published.glsl", "vicp_published_vertex.vert", "vicp_published.vert"}, {}, {}},
            {{"vicp_tet.glsl", "preintegration_table.frag", "vicp_fragment.frag", "vicp_published.glsl",
              "vicp_published_fragment.frag", "vicp_framebuffer.frag", "vicp_published.frag"},
             defines,
             extensions}};
}

GlVicpRenderer::GlVicpRenderer(GlContext& ctx, const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                               const TransferFunction& tf, const VicpOptions& options, FramebufferAccess access)
    : ctx_(ctx),
      mesh_(mesh, topo, field, tf, checked_gl_options(ctx, mesh, field, options, access)),
      access_(choose_fragment_access(ctx.info(), access, "VICP"))
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    gl_ = std::make_unique<Objects>(gl);
    const VicpProgramSources src = program_sources(access_);
    gl_->program = std::make_unique<GlProgram>(ctx_, src.exact_vertex, src.exact_fragment);
    if (mesh_.options().interpolation == InterpolationMode::gpu) {
        gl_->published_program = std::make_unique<GlProgram>(ctx_, src.published_vertex, src.published_fragment);
        gl.GenVertexArrays(1, &gl_->published_vao);
        gl.GenBuffers(1, &gl_->published_vbo);
        gl.BindVertexArray(gl_->published_vao);
        gl.BindBuffer(GL_ARRAY_BUFFER, gl_->published_vbo);
        const auto attribute = [&](GLuint location, GLint size, std::size_t offset) {
            gl.EnableVertexAttribArray(location);
            gl.VertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, sizeof(VicpPublishedVertex),
                                   reinterpret_cast<const void*>(offset));
        };
        attribute(0, 3, offsetof(VicpPublishedVertex, position));
        attribute(1, 1, offsetof(VicpPublishedVertex, s));
        attribute(2, 3, offsetof(VicpPublishedVertex, gradient));
        attribute(3, 3, offsetof(VicpPublishedVertex, plane));
        attribute(4, 1, offsetof(VicpPublishedVertex, index));
        gl.BindVertexArray(0);
    }
    gl.GenVertexArrays(1, &gl_->vao);
    gl.GenBuffers(kBindings, gl_->buffers);
    // The resident per-point arrays, three values (or one) a point, packed as the shader reads them.
    const auto& pd = mesh_.points_d();
    const auto& sn = mesh_.scalars_n();
    gl_->upload(kPointsD, pd.data(), pd.size() * sizeof(glm::dvec3), GL_STATIC_DRAW);
    gl_->upload(kScalars, sn.data(), sn.size() * sizeof(double), GL_STATIC_DRAW);
    upload_preintegration_table(ctx_, *mesh_.table(), mesh_.options().filter, gl_->table_texture);
    gl_->framebuffer = std::make_unique<GlFloatFramebuffer>(ctx_, 2, "the VICP framebuffer");
    ctx_.check_error("setting up VICP on GL");
}

GlVicpRenderer::~GlVicpRenderer()
{
    ctx_.make_current();
    gl_.reset();
}

// The exact program over stream slots [begin, end): as few chunks as the storage block size allows, each one
// multi-draw: runs of whole cells, and the cut cells' fans in their places.
void GlVicpRenderer::draw_exact(const VicpFrameSetup& fs, std::size_t begin, std::size_t end, VicpStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    auto t0 = Clock::now();
    gl.UseProgram(gl_->program->id());
    gl.BindVertexArray(gl_->vao);
    const GLint whole_vertices = gl_->program->uniform("vicp_whole_vertices", true);
    const GLint slot_base = gl_->program->uniform("vicp_slot_base", true);
    const std::vector<VicpCell>& stream = fs.stream;
    const std::size_t chunk = cells_per_draw();
    // The first cut cell at or after slot `s`, searched from cut `from` on.
    const auto first_cut = [&fs](std::size_t from, std::size_t s) {
        return std::size_t(std::lower_bound(fs.cuts.begin() + std::ptrdiff_t(from), fs.cuts.end(), s,
                                            [](const VicpCut& c, std::size_t slot) { return c.slot < slot; }) -
                           fs.cuts.begin());
    };
    std::size_t cut = first_cut(0, begin);
    std::vector<GLint> firsts;
    std::vector<GLsizei> sizes;
    for (std::size_t c0 = begin; c0 < end; c0 += chunk) {
        const std::size_t n = std::min(chunk, end - c0);
        gl_->upload(kStream, stream.data() + c0, n * sizeof(VicpCell), GL_STREAM_DRAW);
        // The chunk's cut cells and their fans; the fans' vertex IDs start after the whole cells'.
        const std::size_t cut_end = first_cut(cut, c0 + n);
        const std::size_t fan0 = cut < cut_end ? fs.cuts[cut].first : 0;
        const std::size_t fan1 = cut < cut_end ? fs.cuts[cut_end - 1].first + fs.cuts[cut_end - 1].count : 0;
        const uint32_t empty[4] = {0, 0, 0, 0};  // a buffer is never empty
        if (fan1 > fan0)
            gl_->upload(kFans, fs.fans.data() + 4 * fan0, (fan1 - fan0) * 4 * sizeof(uint32_t), GL_STREAM_DRAW);
        else
            gl_->upload(kFans, empty, sizeof empty, GL_STREAM_DRAW);
        const GLint fan_base = GLint(kVicpVerticesPerTet * n);
        firsts.clear();
        sizes.clear();
        std::size_t run = c0;  // the first whole cell not drawn yet
        for (; cut < cut_end; ++cut) {
            const VicpCut& c = fs.cuts[cut];
            if (c.slot > run) {
                firsts.push_back(GLint(kVicpVerticesPerTet * (run - c0)));
                sizes.push_back(GLsizei(kVicpVerticesPerTet * (c.slot - run)));
            }
            if (c.count) {
                firsts.push_back(fan_base + GLint(3 * (c.first - fan0)));
                sizes.push_back(GLsizei(3 * c.count));
            }
            run = c.slot + 1;
        }
        if (c0 + n > run) {
            firsts.push_back(GLint(kVicpVerticesPerTet * (run - c0)));
            sizes.push_back(GLsizei(kVicpVerticesPerTet * (c0 + n - run)));
        }
        gl.Uniform1i(whole_vertices, fan_base);
        gl.Uniform1ui(slot_base, GLuint(c0));
        st.setup_ms += ms_since(t0);
        t0 = Clock::now();
        if (!firsts.empty()) gl.MultiDrawArrays(GL_TRIANGLES, firsts.data(), sizes.data(), GLsizei(firsts.size()));
        st.raster_fragment_ms += ms_since(t0);
        t0 = Clock::now();
        ++st.draws;
    }
}

// The published program over stream slots [begin, end), all whole cells: ProjectTet's records of a chunk of cells sent
// as vertex attributes (three vertices a sent face, vicp_sent_faces), then drawn; the chunk bounds what the GPU holds
// of them. The records are filled in parallel, each cell at its place in the stream's order (a prefix sum of the faces
// sent), so the draw does not depend on the thread count.
void GlVicpRenderer::draw_published(const VicpFrameSetup& fs, std::size_t begin, std::size_t end, VicpStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    gl.UseProgram(gl_->published_program->id());
    gl.BindVertexArray(gl_->published_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, gl_->published_vbo);
    const std::size_t chunk = cells_per_draw_ ? cells_per_draw_ : kPublishedCellsPerDraw;
    std::vector<VicpPublishedVertex>& records = gl_->records;
    std::vector<uint32_t>& first = gl_->first_face;  // per cell of the chunk: its first sent face; then the total
    std::vector<uint8_t>& faces = gl_->faces;        // per cell of the chunk: vicp_sent_faces
    for (std::size_t c0 = begin; c0 < end; c0 += chunk) {
        const std::size_t n = std::min(chunk, end - c0);
        auto t0 = Clock::now();
        faces.resize(n);
        first.resize(n + 1);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i)
                faces[i] = uint8_t(vicp_sent_faces(fs, fs.stream[c0 + i], submission_));
        });
        first[0] = 0;
        for (std::size_t i = 0; i < n; ++i) first[i + 1] = first[i] + uint32_t(std::popcount(unsigned(faces[i])));
        records.resize(3 * std::size_t(first[n]));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            VicpPublishedVertex cell[kVicpVerticesPerTet];
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                if (!faces[i]) continue;
                mesh_.published_records(fs.stream[c0 + i], fs.points_f, cell);
                VicpPublishedVertex* out = &records[3 * std::size_t(first[i])];
                for (int f = 0; f < 4; ++f)
                    if (faces[i] & (1u << f)) out = std::copy(cell + 3 * f, cell + 3 * f + 3, out);
            }
        });
        st.sent_faces += first[n];
        st.project_ms += ms_since(t0);
        if (records.empty()) continue;
        t0 = Clock::now();
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(records.size() * sizeof(VicpPublishedVertex)), records.data(),
                      GL_STREAM_DRAW);
        st.setup_ms += ms_since(t0);
        t0 = Clock::now();
        gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(records.size()));
        st.raster_fragment_ms += ms_since(t0);
        ++st.draws;
    }
}

// The frame's buffers, the framebuffer cleared, the fixed-function state and each program's uniforms.
void GlVicpRenderer::prepare_frame(const VicpFrameSetup& fs, const Camera& cam, int width, int height)
{
    const GlFunctions& gl = ctx_.gl();
    const bool published = mesh_.options().interpolation == InterpolationMode::gpu;
    // The exact program's per-frame buffers (every cell with --interpolation exact, the cut cells alone with the
    // published program), read at any index by every draw.
    if (!published || !fs.cuts.empty()) {
        if (double(fs.points_f.size()) * sizeof(glm::vec3) > double(max_block_bytes(ctx_)))
            throw InputError(mesh_.mesh().source, "the frame's " + std::to_string(fs.points_f.size()) +
                                                      " vertices exceed one storage block on " +
                                                      ctx_.info().renderer + "; use --backend emu");
        gl_->upload(kPointsF, fs.points_f.data(), fs.points_f.size() * sizeof(glm::vec3), GL_STREAM_DRAW);
        gl_->upload(kSnapped, fs.snapped.data(), fs.snapped.size() * sizeof(glm::dvec3), GL_STREAM_DRAW);
    }
    gl_->framebuffer->bind(width, height);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_DEPTH_TEST);
    // Only the faces the eye sees from outside a cell make fragments (the emulation's Facing::front): not by
    // glCullFace, whose draw-module stage culls slivers on a float determinant that can disagree with the fixed-point
    // area llvmpipe's setup goes by (docs/rasterizer.md, "Not emulated" 2), but by the fragment program, which
    // discards the fragments of back faces on gl_FrontFacing, the setup's own facing (shaders/vicp.frag).
    gl.Disable(GL_CULL_FACE);
    gl.FrontFace(GL_CCW);
    gl.ProvokingVertex(GL_LAST_VERTEX_CONVENTION);  // the vertex that computes the flat constants (vicp.vert)
    const float zero[4] = {0, 0, 0, 0};
    gl.ClearBufferfv(GL_COLOR, 0, zero);
    gl.ClearBufferfv(GL_COLOR, 1, zero);
    if (access_.images) {
        // The attachments as images (unit i for attachment i); the draws write no colour output, so the colour mask
        // keeps the framebuffer from writing undefined values over them.
        for (int i = 0; i < 2; ++i)
            gl.BindImageTexture(GLuint(i), gl_->framebuffer->texture(i), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    }
    // Each program's uniforms, once a frame (a program keeps its own).
    gl.UseProgram(gl_->program->id());
    set_vicp_frame_uniforms(ctx_, *gl_->program, fs.constants);
    gl.UniformMatrix4fv(gl_->program->uniform("vicp_mvp", true), 1, GL_FALSE, &fs.view.mvp[0][0]);
    if (published) {
        const GlProgram& sp = *gl_->published_program;
        gl.UseProgram(sp.id());
        set_vicp_frame_uniforms(ctx_, sp, fs.constants);
        gl.UniformMatrix4fv(sp.uniform("vicp_mvp", true), 1, GL_FALSE, &fs.view.mvp[0][0]);
        const VicpPublishedView view = vicp_published_view(cam);
        gl.Uniform1i(sp.uniform("vicp_published_orthographic", true), view.orthographic);
        gl.Uniform3f(sp.uniform("vicp_published_direction"), view.direction.x, view.direction.y, view.direction.z);
    }
    ctx_.check_error("preparing the VICP draw");
}

// The stream's cells drawn in order (draw_exact, draw_published), then waited for.
void GlVicpRenderer::draw_cells(const VicpFrameSetup& fs, VicpStats& st)
{
    const GlFunctions& gl = ctx_.gl();
    const bool published = mesh_.options().interpolation == InterpolationMode::gpu;
    if (!published) {
        draw_exact(fs, 0, fs.stream.size(), st);
    } else {
        // Runs of whole cells through the published program, the cut cells between them in their places through the
        // exact program (docs/vicp.md, "The cells a view cuts, with the published program"); GL keeps primitive order
        // across draws.
        std::size_t slot = 0;
        for (std::size_t i = 0; i < fs.cuts.size();) {
            const std::size_t first = fs.cuts[i].slot;
            std::size_t last = first + 1;  // a run of consecutive cut cells, one exact draw
            for (++i; i < fs.cuts.size() && fs.cuts[i].slot == last; ++i) ++last;
            if (first > slot) draw_published(fs, slot, first, st);
            draw_exact(fs, first, last, st);
            slot = last;
        }
        if (fs.stream.size() > slot) draw_published(fs, slot, fs.stream.size(), st);
    }
    const auto t0 = Clock::now();
    gl.Finish();
    if (access_.images) {
        gl.MemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);  // for glReadPixels
        gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    ctx_.check_error("the VICP draw");
    st.raster_fragment_ms += ms_since(t0);
    gl.BindVertexArray(0);
}

// Read back the colour and the diagnostics (counts as exact floats).
void GlVicpRenderer::read_frame(int width, int height, VicpFrame& out)
{
    const auto t0 = Clock::now();
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    const std::vector<glm::vec4> colour = gl_->framebuffer->read(0), diag = gl_->framebuffer->read(1);
    out.stats.readback_ms = ms_since(t0);

    std::vector<VicpDiagnostics> counts(npix);
    for (std::size_t p = 0; p < npix; ++p)
        counts[p] = {uint32_t(diag[p].x), uint32_t(diag[p].y), diag[p].z, diag[p].w};
    store_vicp_frame(colour, counts, width, height, out);
}

VicpFrame GlVicpRenderer::render(const Camera& cam, int width, int height)
{
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::dvec3) == 3 * sizeof(double),
                  "points are uploaded as packed triples");
    ctx_.make_current();
    VicpFrame out;
    VicpStats& st = out.stats;
    const VicpFrameSetup fs = setup_vicp_frame(mesh_, cam, width, height);
    store_setup_stats(mesh_, fs, st);
    const auto t0 = Clock::now();
    prepare_frame(fs, cam, width, height);
    st.setup_ms = fs.vertex_ms + ms_since(t0);
    draw_cells(fs, st);
    read_frame(width, height, out);
    return out;
}

}  // namespace uvr::gpu
