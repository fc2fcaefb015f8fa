#include "gpu/raycast/gl_raycast.h"

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include "gpu/gl/gl_framebuffer.h"
#include "gpu/gl/gl_preintegration_table.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

namespace {

enum Texture { kVolumeTexture = 0, kClassificationTexture = 1, kTableTexture = 2 };

const RaycastOptions& checked_gl_options(const GlContext& ctx, const Volume& volume, const RaycastOptions& o)
{
    if (o.preintegrate && o.segment == SegmentMode::exact)
        throw InputError("", "--segment exact runs only in the emulation (--backend emu): on a GPU the march samples "
                             "the pre-integrated table");
    GLint max3d = 0;
    ctx.gl().GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
    for (int i = 0; i < 3; ++i)
        if (volume.dims[std::size_t(i)] > max3d)
            throw InputError(volume.source, "has " + std::to_string(volume.dims[std::size_t(i)]) +
                                                " samples along an axis; " + ctx.info().renderer + " holds 3D textures of " +
                                                std::to_string(max3d) + " at most; use --backend emu");
    return o;
}

void linear_clamped(const GlFunctions& gl, GLenum target)
{
    for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) gl.TexParameteri(target, p, GL_LINEAR);
    for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        gl.TexParameteri(target, p, GL_CLAMP_TO_EDGE);
}

}  // namespace

void set_raycast_frame_uniforms(const GlContext& ctx, const GlProgram& program, const RaycastFrameConstants& fc)
{
    const GlFunctions& gl = ctx.gl();
    // A uniform the compiler removed (unused by a pass) has location -1, which glUniform ignores.
    auto d1 = [&](const char* name, double v) { gl.Uniform1d(program.uniform(name), v); };
    auto d3 = [&](const char* name, const glm::dvec3& v) { gl.Uniform3d(program.uniform(name), v.x, v.y, v.z); };
    auto f1 = [&](const char* name, float v) { gl.Uniform1f(program.uniform(name), v); };
    auto f3 = [&](const char* name, const glm::vec3& v) { gl.Uniform3f(program.uniform(name), v.x, v.y, v.z); };
    auto i1 = [&](const char* name, int v) { gl.Uniform1i(program.uniform(name), v); };
    d1("rc_two_over_width", fc.two_over_width);
    d1("rc_two_over_height", fc.two_over_height);
    d3("rc_eye", fc.eye);
    d3("rc_ray_ox", fc.ray_ox);
    d3("rc_ray_oy", fc.ray_oy);
    d3("rc_ray_d0", fc.ray_d0);
    d3("rc_ray_dx", fc.ray_dx);
    d3("rc_ray_dy", fc.ray_dy);
    d3("rc_box_lo", fc.box_lo);
    d3("rc_box_hi", fc.box_hi);
    d3("rc_tex_scale", fc.tex_scale);
    d3("rc_tex_half", fc.tex_half);
    f3("rc_tex_extent", fc.tex_extent);
    d1("rc_step", fc.step);
    i1("rc_max_samples", fc.max_samples);
    i1("rc_preintegrate", fc.preintegrate);
    f1("rc_threshold", fc.threshold);
    f1("rc_scalar_scale", fc.scalar_scale);
    f1("rc_scalar_bias", fc.scalar_bias);
    f1("rc_step_f", fc.step_f);
    f1("rc_length_scale", fc.length_scale);
    f1("rc_length_bias", fc.length_bias);
    i1("rc_shade", fc.shade);
    d3("rc_light", fc.light);
    d1("rc_ambient", fc.ambient);
    d1("rc_diffuse", fc.diffuse);
    d1("rc_specular", fc.specular);
    i1("rc_shininess", fc.shininess);
    f3("rc_texel", fc.texel);
    f3("rc_gradient_scale", fc.gradient_scale);
    ctx.check_error("setting the ray caster's frame uniforms");
}

void upload_raycast_textures(const GlContext& ctx, const RaycastVolume& rv, GLuint textures[3])
{
    const GlFunctions& gl = ctx.gl();
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (!textures[kVolumeTexture]) gl.GenTextures(1, &textures[kVolumeTexture]);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_3D, textures[kVolumeTexture]);
    GLenum internal = GL_R32F, type = GL_FLOAT;
    if (rv.texel_format() == TexelFormat::u16) internal = GL_R16, type = GL_UNSIGNED_SHORT;
    if (rv.texel_format() == TexelFormat::u8) internal = GL_R8, type = GL_UNSIGNED_BYTE;
    const auto& dims = rv.volume().dims;
    gl.TexImage3D(GL_TEXTURE_3D, 0, GLint(internal), GLsizei(dims[0]), GLsizei(dims[1]), GLsizei(dims[2]), 0, GL_RED,
                  type, rv.texels());
    linear_clamped(gl, GL_TEXTURE_3D);
    if (const ClassificationTable* cls = rv.classification()) {
        if (!textures[kClassificationTexture]) gl.GenTextures(1, &textures[kClassificationTexture]);
        gl.ActiveTexture(GL_TEXTURE1);
        gl.BindTexture(GL_TEXTURE_2D, textures[kClassificationTexture]);
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, cls->size(), 1, 0, GL_RGBA, GL_FLOAT, cls->texels().data());
        linear_clamped(gl, GL_TEXTURE_2D);
    }
    if (const PreintegrationTable* table = rv.table())
        upload_preintegration_table(ctx, *table, TextureFilter::linear, textures[kTableTexture]);
    gl.ActiveTexture(GL_TEXTURE0);
    ctx.check_error("uploading the ray caster's textures");
}

struct GlRaycastRenderer::Objects {
    const GlFunctions& gl;
    std::unique_ptr<GlProgram> program;      // the march: full-screen (exact) or the published third pass
    std::unique_ptr<GlProgram> box_program;  // the published first two passes
    GLuint vao = 0, box_vbo = 0;
    GLuint textures[3] = {};
    std::unique_ptr<GlFloatFramebuffer> framebuffer;  // colour, samples (and depth for the published third pass)
    std::unique_ptr<GlFloatFramebuffer> positions;    // the published entry and exit targets, with depth

    explicit Objects(const GlFunctions& g) : gl(g) {}
    ~Objects()
    {
        framebuffer.reset();
        positions.reset();
        program.reset();
        box_program.reset();
        if (vao) gl.DeleteVertexArrays(1, &vao);
        if (box_vbo) gl.DeleteBuffers(1, &box_vbo);
        for (GLuint& t : textures)
            if (t) gl.DeleteTextures(1, &t);
    }
};

GlRaycastRenderer::RaycastProgramSources GlRaycastRenderer::program_sources(bool published, bool light)
{
    const GlShaderSource box_vertex{{"clip_position.vert", "raycast_box.vert"}, {}, {}};
    GlShaderSource march{{"classification_table.frag", "preintegration_table.frag", "raycast_fragment.frag",
                          "raycast.frag"},
                         {},
                         {}};
    if (light) march.defines.push_back({"RAYCAST_SHADE", "1"});
    if (published) march.defines.push_back({"RAYCAST_PUBLISHED_PASSES", "1"});
    return {published ? box_vertex : GlShaderSource{{"fullscreen.vert"}, {}, {}}, march, box_vertex,
            GlShaderSource{{"raycast_box.frag"}, {}, {}}};
}

GlRaycastRenderer::GlRaycastRenderer(GlContext& ctx, const Volume& volume, const TransferFunction& tf,
                                     const RaycastOptions& options)
    : ctx_(ctx), volume_(volume, tf, checked_gl_options(ctx, volume, options))
{
    ctx_.make_current();
    gl_ = std::make_unique<Objects>(ctx_.gl());
    const bool published = volume_.options().interpolation == InterpolationMode::gpu;
    const RaycastProgramSources src = program_sources(published, volume_.options().light.has_value());
    gl_->program = std::make_unique<GlProgram>(ctx_, src.march_vertex, src.march_fragment);
    if (published) {
        gl_->box_program = std::make_unique<GlProgram>(ctx_, src.box_vertex, src.box_fragment);
        gl_->positions = std::make_unique<GlFloatFramebuffer>(ctx_, 2, "the ray caster's entry and exit targets",
                                                              GlFloatFramebuffer::Depth::d24);
    }
    const GlFunctions& gl = ctx_.gl();
    gl.GenVertexArrays(1, &gl_->vao);
    if (published) {
        gl.GenBuffers(1, &gl_->box_vbo);
        gl.BindVertexArray(gl_->vao);
        gl.BindBuffer(GL_ARRAY_BUFFER, gl_->box_vbo);
        gl.EnableVertexAttribArray(0);
        gl.EnableVertexAttribArray(1);
        gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(RaycastBoxVertex), nullptr);
        gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(RaycastBoxVertex),
                               reinterpret_cast<const void*>(offsetof(RaycastBoxVertex, tex)));
        gl.BindVertexArray(0);
    }
    upload_raycast_textures(ctx_, volume_, gl_->textures);
    gl_->framebuffer = std::make_unique<GlFloatFramebuffer>(
        ctx_, 2, "the ray caster's framebuffer",
        published ? GlFloatFramebuffer::Depth::d24 : GlFloatFramebuffer::Depth::none);
    ctx_.check_error("setting up the ray caster on GL");
}

GlRaycastRenderer::~GlRaycastRenderer()
{
    ctx_.make_current();
    gl_.reset();
}

void GlRaycastRenderer::draw_box_passes(const RaycastBoxFrame& bf, int width, int height)
{
    const GlFunctions& gl = ctx_.gl();
    gl.BindVertexArray(gl_->vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, gl_->box_vbo);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(bf.vertices.size() * sizeof(RaycastBoxVertex)), bf.vertices.data(),
                  GL_STREAM_DRAW);
    gl_->positions->bind(width, height);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.DrawBuffers(2, both);
    const float zero[4] = {0, 0, 0, 0};
    gl.ClearBufferfv(GL_COLOR, 0, zero);
    gl.ClearBufferfv(GL_COLOR, 1, zero);
    gl.UseProgram(gl_->box_program->id());
    gl.UniformMatrix4fv(gl_->box_program->uniform("rc_box_mvp", true), 1, GL_FALSE, &bf.view.mvp[0][0]);
    gl.Enable(GL_DEPTH_TEST);
    gl.Enable(GL_CULL_FACE);
    // The published passes: front faces with GL_LESS over depth 1, back faces with GL_GREATER over depth 0; culling the
    // other facing beside them (docs/raycast.md, "The published passes").
    struct Pass {
        GLenum target, cull, depth_func;
        float clear_depth;
    };
    for (const Pass& pass : {Pass{GL_COLOR_ATTACHMENT0, GL_BACK, GL_LESS, 1.0f},
                             Pass{GL_COLOR_ATTACHMENT1, GL_FRONT, GL_GREATER, 0.0f}}) {
        gl.DrawBuffers(1, &pass.target);
        gl.ClearBufferfv(GL_DEPTH, 0, &pass.clear_depth);
        gl.DepthFunc(pass.depth_func);
        gl.CullFace(pass.cull);
        gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(bf.vertices.size()));
    }
    gl.DrawBuffers(2, both);
    ctx_.check_error("the ray caster's box passes");
}

RaycastFrame GlRaycastRenderer::render(const Camera& cam, int width, int height)
{
    ctx_.make_current();
    const GlFunctions& gl = ctx_.gl();
    RaycastFrame out;
    auto t0 = Clock::now();
    const RaycastFrameConstants fc = raycast_frame_constants(volume_, cam, width, height);
    const bool published = volume_.options().interpolation == InterpolationMode::gpu;
    gl.Disable(GL_BLEND);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_CULL_FACE);
    RaycastBoxFrame bf;
    if (published) {
        bf = raycast_box_frame(fc, cam, volume_.origin(), width, height);
        count_raycast_box(bf, out.stats);
        draw_box_passes(bf, width, height);
    }
    gl_->framebuffer->bind(width, height);
    const float zero[4] = {0, 0, 0, 0};
    gl.ClearBufferfv(GL_COLOR, 0, zero);
    gl.ClearBufferfv(GL_COLOR, 1, zero);
    gl.UseProgram(gl_->program->id());
    set_raycast_frame_uniforms(ctx_, *gl_->program, fc);
    gl.BindVertexArray(gl_->vao);
    if (published) {
        // The published third pass: the box again, front faces (GL_LESS over depth 1), the march at each of their
        // pixels.
        const float one = 1.0f;
        gl.ClearBufferfv(GL_DEPTH, 0, &one);
        gl.DepthFunc(GL_LESS);
        gl.CullFace(GL_BACK);
        gl.UniformMatrix4fv(gl_->program->uniform("rc_box_mvp", true), 1, GL_FALSE, &bf.view.mvp[0][0]);
        gl.ActiveTexture(GL_TEXTURE5);
        gl.BindTexture(GL_TEXTURE_2D, gl_->positions->texture(0));
        gl.ActiveTexture(GL_TEXTURE6);
        gl.BindTexture(GL_TEXTURE_2D, gl_->positions->texture(1));
        gl.ActiveTexture(GL_TEXTURE0);
    }
    ctx_.check_error("preparing the ray caster's draw");
    const double setup_ms = ms_since(t0);

    t0 = Clock::now();
    gl.DrawArrays(GL_TRIANGLES, 0, published ? GLsizei(bf.vertices.size()) : 3);
    gl.Finish();
    ctx_.check_error("the ray caster's draw");
    const double march_ms = ms_since(t0);
    gl.BindVertexArray(0);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_CULL_FACE);

    t0 = Clock::now();
    const std::vector<glm::vec4> colour = gl_->framebuffer->read(0), diag = gl_->framebuffer->read(1);
    const double readback_ms = ms_since(t0);
    std::vector<uint32_t> samples(diag.size());
    for (std::size_t p = 0; p < diag.size(); ++p) samples[p] = uint32_t(diag[p].x);
    store_raycast_frame(colour, samples, width, height, out);
    out.stats.table_ms = volume_.table_ms();
    out.stats.setup_ms = setup_ms;
    out.stats.march_ms = march_ms;
    out.stats.readback_ms = readback_ms;
    return out;
}

}  // namespace uvr::gpu
