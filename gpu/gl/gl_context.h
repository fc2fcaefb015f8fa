// A headless OpenGL 4.5 core-profile context for the GL backend, and the few helpers every GL stage
// needs: a function table, shader programs built from the source files in shaders/, framebuffer checks.
// Platforms, both without a window: OSMesa (llvmpipe) or EGL (a device with a DRM node first, else Mesa's surfaceless
// platform); every stage renders into its own float FBOs. Entry points go into GlFunctions, a table of our own (no
// loader library). Every failure a user can meet is an InputError with the reason; nothing here aborts.
// Twins: none (the GL context layer); GlProgram builds every GL driver's and harness's program from shaders/.
// Details: docs/gl-backend.md, "The two platforms".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <GL/glcorearb.h>
#include "reference/choice.h"

namespace uvr::gpu {

enum class GlPlatform { osmesa, egl };
inline constexpr Choices<GlPlatform, 2> kGlPlatforms{
    {{GlPlatform::osmesa, "osmesa", "Mesa's off-screen library"}, {GlPlatform::egl, "egl", "EGL without a display"}}};
const char* gl_platform_name(GlPlatform p);                   // "osmesa", "egl"
GlPlatform parse_gl_platform(const std::string& name);        // throws InputError for anything else

// The entry points the GL stages use. X(type, name): the member `name` holds "gl" #name.
#define UVR_GL_FUNCTIONS(X)                                      \
    X(PFNGLGETSTRINGPROC, GetString)                             \
    X(PFNGLGETSTRINGIPROC, GetStringi)                           \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                         \
    X(PFNGLGETINTEGER64VPROC, GetInteger64v)                     \
    X(PFNGLGETERRORPROC, GetError)                               \
    X(PFNGLFINISHPROC, Finish)                                   \
    X(PFNGLENABLEPROC, Enable)                                   \
    X(PFNGLDISABLEPROC, Disable)                                 \
    X(PFNGLVIEWPORTPROC, Viewport)                               \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                         \
    X(PFNGLCREATESHADERPROC, CreateShader)                       \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                       \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                     \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                         \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)               \
    X(PFNGLDELETESHADERPROC, DeleteShader)                       \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                     \
    X(PFNGLATTACHSHADERPROC, AttachShader)                       \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                         \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                       \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)             \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                     \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                           \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)           \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                             \
    X(PFNGLUNIFORM1UIPROC, Uniform1ui)                           \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                             \
    X(PFNGLUNIFORM1DPROC, Uniform1d)                             \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)               \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)         \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                       \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                 \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                 \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)           \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                           \
    X(PFNGLMULTIDRAWARRAYSPROC, MultiDrawArrays)                 \
    X(PFNGLGENTEXTURESPROC, GenTextures)                         \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                   \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                         \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                     \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                     \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                           \
    X(PFNGLTEXIMAGE3DPROC, TexImage3D)                           \
    X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                     \
    X(PFNGLTEXSUBIMAGE3DPROC, TexSubImage3D)                     \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                 \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)           \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                 \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)       \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)   \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)               \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)         \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)               \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)         \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer) \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                             \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                         \
    X(PFNGLREADBUFFERPROC, ReadBuffer)                           \
    X(PFNGLREADPIXELSPROC, ReadPixels)                           \
    X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                     \
    X(PFNGLCLEARBUFFERUIVPROC, ClearBufferuiv)                   \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                           \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                     \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                           \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                   \
    X(PFNGLBUFFERDATAPROC, BufferData)                           \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)               \
    X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                     \
    X(PFNGLBINDIMAGETEXTUREPROC, BindImageTexture)               \
    X(PFNGLCOLORMASKPROC, ColorMask)                             \
    X(PFNGLUNIFORM3DPROC, Uniform3d)                             \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                             \
    X(PFNGLCULLFACEPROC, CullFace)                               \
    X(PFNGLFRONTFACEPROC, FrontFace)                             \
    X(PFNGLPROVOKINGVERTEXPROC, ProvokingVertex)                 \
    X(PFNGLTEXBUFFERPROC, TexBuffer)                             \
    X(PFNGLFENCESYNCPROC, FenceSync)                             \
    X(PFNGLCLIENTWAITSYNCPROC, ClientWaitSync)                   \
    X(PFNGLDELETESYNCPROC, DeleteSync)                           \
    X(PFNGLGENQUERIESPROC, GenQueries)                           \
    X(PFNGLDELETEQUERIESPROC, DeleteQueries)                     \
    X(PFNGLBEGINQUERYPROC, BeginQuery)                           \
    X(PFNGLENDQUERYPROC, EndQuery)                               \
    X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)

struct GlFunctions {
#define UVR_GL_MEMBER(type, name) type name = nullptr;
    UVR_GL_FUNCTIONS(UVR_GL_MEMBER)
#undef UVR_GL_MEMBER
};

// What the context reports, for reports and docs (docs/spec.md §5: record the Mesa version a claim was checked on).
struct GlInfo {
    GlPlatform platform = GlPlatform::osmesa;
    std::string detail;    // how it was made: "OSMesa 8.0 core 4.5", "EGL 1.5 device 0 (EGL_MESA_device_software)"
    bool hardware = false;  // an EGL device that does not say it is software (egl_device_is_software), nor its renderer
    // GL_VENDOR, GL_RENDERER, GL_VERSION, GL_SHADING_LANGUAGE_VERSION
    std::string vendor, renderer, version, glsl_version;
    std::vector<std::string> extensions;  // less those UVR_GL_HIDE_EXTENSIONS hides
    // UVR_GL_HIDE_EXTENSIONS=EXT1,EXT2: uvr behaves as if the context lacked them (queries and the choice of path),
    // so that every route and every skip is reached on llvmpipe (docs/gpu.md); also names routes (kLlvmpipeImageRoute).
    std::vector<std::string> hidden;
    int max_draw_buffers = 0, max_color_attachments = 0;
    bool has_extension(const std::string& name) const;
    bool hides(const std::string& name) const;
    std::string summary() const;  // "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6 [osmesa]"
};

// core: what every GLSL stage runs on. compatibility (OSMesa only): the profile that keeps ARB assembly programs and
// the fixed-function matrix stacks, for the published programs (--backend arb, gpu/havs/gl_havs_arb.h).
enum class GlProfile { core, compatibility };

// How a device is told to be software: by what it says of itself. An EGL device is software when its extensions name
// EGL_MESA_device_software (Mesa's llvmpipe device); any other counts as hardware, a DRM node or not (an NVIDIA device
// in a container without /dev/dri lists none). Once a context is made, a renderer string naming llvmpipe or softpipe
// makes it software too. docs/gpu.md, "Which device".
bool egl_device_is_software(const std::string& device_extensions);
bool renderer_is_software(const std::string& renderer);

// GlContext's choice of EGL device: any (hardware first), or an index into EGL's device list, of which the first
// kMaxEglDevices are looked at (more GPUs than one machine holds).
inline constexpr int kAnyEglDevice = -1;
inline constexpr int kMaxEglDevices = 16;

class GlContext {
public:
    // Creates the context and makes it current on the calling thread. With EGL, `egl_device` picks a device of EGL's
    // device platform by its index; -1 takes the first hardware device that gives a context, then a software one
    // (Mesa's llvmpipe), and GlInfo::detail says which. Throws InputError when the platform cannot give a 4.5 context
    // of the profile (no library, no display or device, too old a driver), when `egl_device` names no device (the
    // message lists them), or when an entry point is missing.
    explicit GlContext(GlPlatform platform, GlProfile profile = GlProfile::core, int egl_device = kAnyEglDevice);
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    void make_current();  // on the calling thread (one thread uses a context at a time)
    const GlFunctions& gl() const { return gl_; }
    const GlInfo& info() const { return info_; }

    // Throws InputError("", "<what>: GL error 0x....") when glGetError reports one.
    void check_error(const std::string& what) const;
    // An entry point outside GlFunctions (the ARB programs' and the compatibility profile's); null when missing.
    void* proc_address(const char* name) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    GlFunctions gl_;
    GlInfo info_;
};

// ---- Shader programs from shaders/ ----

// Where the .vert / .frag files are: $UVR_SHADER_DIR when set, else the source tree's shaders/ (compile definition).
std::string shader_dir();
// The text of shaders/<name>. Throws InputError naming the path when it cannot be read.
std::string read_shader_file(const std::string& name);

// One stage's source, assembled from a prelude and whole files. The prelude (line 0) is `#version 450 core`, the
// extensions and `#define NAME VALUE` for each define; each file follows behind `#line 1 <n>` so that the compiler's
// log names source string n, which the error message maps back to the file.
struct GlShaderSource {
    std::vector<std::string> files;                             // names under shader_dir(), in order
    std::vector<std::pair<std::string, std::string>> defines;    // NAME, VALUE
    std::vector<std::string> extensions;                         // each becomes `#extension NAME : require`
};

// The stage's source as one text, as GlProgram hands it to the driver (for offline compilers).
std::string assembled_source(const GlShaderSource& src);

// A linked program. Throws InputError naming the shader file(s), with the GLSL log, when compiling or linking fails.
class GlProgram {
public:
    GlProgram(const GlContext& ctx, const GlShaderSource& vertex, const GlShaderSource& fragment);
    ~GlProgram();
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;
    GLuint id() const { return id_; }
    // Uniform location; -1 (ignored by glUniform*) when the compiler removed it. `required` throws instead.
    GLint uniform(const char* name, bool required = false) const;

private:
    const GlContext& ctx_;
    GLuint id_ = 0;
};

// Compiles a program from explicit source strings (tests of the error path; `name` stands for the file in messages).
GLuint compile_program_from_strings(const GlContext& ctx, const std::string& name, const std::string& vertex_text,
                                    const std::string& fragment_text);

// Throws InputError("", "<what>: framebuffer incomplete (GL_FRAMEBUFFER_...)") unless the bound draw framebuffer is
// complete.
void check_framebuffer(const GlContext& ctx, const std::string& what);

}  // namespace uvr::gpu
