#include "gpu/gl/gl_context.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <dlfcn.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>

#include "reference/error.h"

#ifndef UVR_SHADER_DIR
#error "UVR_SHADER_DIR must name the shaders/ directory (gpu/CMakeLists.txt defines it)"
#endif

namespace uvr::gpu {

namespace {

// Mesa's OSMesa is loaded when the first OSMesa context is made rather than linked: a process that renders through
// EGL, on a GPU, or not at all maps neither llvmpipe nor its LLVM (docs/gl-backend.md). The name's major version is
// OSMesa's ABI in Debian 12's libosmesa6.
constexpr const char* kOsmesaLibrary = "libOSMesa.so.8";

struct OsmesaApi {
    decltype(&OSMesaCreateContextAttribs) create = nullptr;
    decltype(&OSMesaMakeCurrent) make_current = nullptr;
    decltype(&OSMesaGetProcAddress) get_proc = nullptr;
    decltype(&OSMesaDestroyContext) destroy = nullptr;
    std::string error;  // why the library or an entry point could not be loaded
};

template <class F>
void load_symbol(void* lib, const char* name, F& f, std::string& error)
{
    f = reinterpret_cast<F>(dlsym(lib, name));
    if (!f && error.empty()) error = std::string("no ") + name + " in it";
}

// Loaded once per process and never unloaded (Mesa keeps state until exit); InputError where it cannot be.
const OsmesaApi& osmesa_api()
{
    static const OsmesaApi api = [] {
        OsmesaApi a;
        void* lib = dlopen(kOsmesaLibrary, RTLD_NOW | RTLD_LOCAL);
        if (!lib) {
            const char* e = dlerror();
            a.error = e ? e : "dlopen failed";
            return a;
        }
        load_symbol(lib, "OSMesaCreateContextAttribs", a.create, a.error);
        load_symbol(lib, "OSMesaMakeCurrent", a.make_current, a.error);
        load_symbol(lib, "OSMesaGetProcAddress", a.get_proc, a.error);
        load_symbol(lib, "OSMesaDestroyContext", a.destroy, a.error);
        return a;
    }();
    if (!api.error.empty())
        throw InputError("", std::string("OSMesa: cannot load ") + kOsmesaLibrary + " (" + api.error +
                                 "); install Mesa's libosmesa6, or render through EGL (--gl egl)");
    return api;
}

std::string hex(unsigned v)
{
    std::ostringstream s;
    s << "0x" << std::hex << v;
    return s.str();
}

// Splits "4.5 (Core Profile) Mesa 22.3.6" into 4 and 5.
bool parse_version(const std::string& v, int& major, int& minor)
{
    return std::sscanf(v.c_str(), "%d.%d", &major, &minor) == 2;
}

bool has_word(const char* list, const char* word)
{
    if (!list) return false;
    std::istringstream in(list);
    std::string w;
    while (in >> w)
        if (w == word) return true;
    return false;
}

}  // namespace

const char* gl_platform_name(GlPlatform p) { return p == GlPlatform::osmesa ? "osmesa" : "egl"; }

GlPlatform parse_gl_platform(const std::string& name)
{
    return parse_choice("--gl", kGlPlatforms, name);
}

bool GlInfo::hides(const std::string& name) const
{
    for (const auto& h : hidden)
        if (h == name) return true;
    return false;
}

bool GlInfo::has_extension(const std::string& name) const
{
    for (const auto& e : extensions)
        if (e == name) return true;
    return false;
}

std::string GlInfo::summary() const { return renderer + ", " + version + " [" + detail + "]"; }

struct GlContext::Impl {
    GlPlatform platform;
    // OSMesa: the context and its (unused) default colour buffer.
    OSMesaContext osmesa = nullptr;
    std::vector<unsigned char> osmesa_buffer;
    // EGL.
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext egl_context = EGL_NO_CONTEXT;

    void* proc(const char* name) const
    {
        if (platform == GlPlatform::osmesa) return reinterpret_cast<void*>(osmesa_api().get_proc(name));
        return reinterpret_cast<void*>(eglGetProcAddress(name));
    }

    void make_current()
    {
        if (platform == GlPlatform::osmesa) {
            // A 4 x 4 RGBA8 buffer: OSMesa needs one to make a context current; the stages never draw into it.
            if (!osmesa_api().make_current(osmesa, osmesa_buffer.data(), GL_UNSIGNED_BYTE, 4, 4))
                throw InputError("", "OSMesa: OSMesaMakeCurrent failed");
        } else if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context)) {
            throw InputError("", "EGL: eglMakeCurrent without a surface failed (error " + hex(eglGetError()) + ")");
        }
    }

    void create_osmesa(std::string& detail, GlProfile profile)
    {
        // Mesa 22.3's OSMesaCreateContextAttribs crashes (a null dispatch table, in glLabelObjectEXT) when the
        // GALLIUM_DRIVER environment variable names a driver it does not have, instead of failing: refuse first.
        if (const char* d = std::getenv("GALLIUM_DRIVER"); d && *d) {
            const std::string driver = d;
            if (driver != "llvmpipe" && driver != "softpipe")
                throw InputError("", "OSMesa: GALLIUM_DRIVER=" + driver + " names a driver OSMesa does not have "
                                     "(llvmpipe, softpipe); unset it (Mesa 22.3 would crash on it)");
        }
        const bool core = profile == GlProfile::core;
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                               OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, core ? OSMESA_CORE_PROFILE : OSMESA_COMPAT_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        osmesa = osmesa_api().create(attribs, nullptr);
        const std::string name = core ? "core" : "compatibility";
        if (!osmesa)
            throw InputError("", "OSMesa: cannot create an OpenGL 4.5 " + name +
                                     "-profile context (OSMesaCreateContextAttribs failed; is Mesa's llvmpipe "
                                     "available?)");
        osmesa_buffer.assign(4 * 4 * 4, 0);
        make_current();
        detail = "osmesa, " + name + " 4.5";
    }

    // Tries one EGL display: initialize, bind GL, create a 4.5 core context, make it current without a surface.
    bool try_egl_display(EGLDisplay dpy, std::string& why)
    {
        EGLint major = 0, minor = 0;
        if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) {
            why = "eglInitialize failed (error " + hex(eglGetError()) + ")";
            return false;
        }
        const char* exts = eglQueryString(dpy, EGL_EXTENSIONS);
        if (!has_word(exts, "EGL_KHR_surfaceless_context")) {
            why = "no EGL_KHR_surfaceless_context";
            eglTerminate(dpy);
            return false;
        }
        if (!eglBindAPI(EGL_OPENGL_API)) {
            why = "eglBindAPI(EGL_OPENGL_API) failed";
            eglTerminate(dpy);
            return false;
        }
        EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
        if (!has_word(exts, "EGL_KHR_no_config_context")) {
            const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
            EGLint n = 0;
            if (!eglChooseConfig(dpy, want, &config, 1, &n) || n < 1) {
                why = "no EGL config renders OpenGL";
                eglTerminate(dpy);
                return false;
            }
        }
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
        if (ctx == EGL_NO_CONTEXT) {
            why = "eglCreateContext(4.5 core) failed (error " + hex(eglGetError()) + ")";
            eglTerminate(dpy);
            return false;
        }
        if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
            why = "eglMakeCurrent without a surface failed (error " + hex(eglGetError()) + ")";
            eglDestroyContext(dpy, ctx);
            eglTerminate(dpy);
            return false;
        }
        display = dpy;
        egl_context = ctx;
        why = "EGL " + std::to_string(major) + "." + std::to_string(minor);
        return true;
    }

    // One EGL device as the device platform describes it: its index, extensions and whether it is hardware (it does
    // not say it is software).
    struct EglDevice {
        EGLDeviceEXT handle = nullptr;
        std::string name;
        bool hardware = false;
    };

    static std::vector<EglDevice> egl_devices(const char* client)
    {
        auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        auto device_string =
            reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
        std::vector<EglDevice> out;
        if (!has_word(client, "EGL_EXT_platform_device") || !query_devices || !device_string) return out;
        EGLDeviceEXT handles[kMaxEglDevices];
        EGLint n = 0;
        if (!query_devices(kMaxEglDevices, handles, &n)) return out;
        for (EGLint i = 0; i < n; ++i) {
            const char* dexts = device_string(handles[i], EGL_EXTENSIONS);
            const bool hardware = !egl_device_is_software(dexts ? dexts : "");
            out.push_back({handles[i], "device " + std::to_string(i) + " (" + (dexts ? dexts : "") + ")", hardware});
        }
        return out;
    }

    static std::string device_list(const std::vector<EglDevice>& devices)
    {
        if (devices.empty()) return "EGL lists no device";
        std::string list = "EGL's devices: ";
        for (std::size_t i = 0; i < devices.size(); ++i)
            list += (i ? "; " : "") + devices[i].name + (devices[i].hardware ? ", hardware" : ", software");
        return list;
    }

    // `device` < 0: hardware devices first, then software ones, then the surfaceless platform. Otherwise only that
    // device of the device platform.
    void create_egl(std::string& detail, bool& hardware, int device)
    {
        const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        auto platform_display =
            reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
        const std::vector<EglDevice> devices = platform_display ? egl_devices(client) : std::vector<EglDevice>{};
        const auto try_device = [&](const EglDevice& d, std::string& why) {
            if (!try_egl_display(platform_display(EGL_PLATFORM_DEVICE_EXT, d.handle, nullptr), why)) return false;
            detail = "egl, " + why + ", " + d.name + (d.hardware ? ", hardware" : ", software");
            hardware = d.hardware;
            return true;
        };
        if (device >= 0) {
            if (std::size_t(device) >= devices.size())
                throw InputError("", "--gl-device " + std::to_string(device) + ": no such EGL device (" +
                                         device_list(devices) + ")");
            std::string why;
            if (try_device(devices[std::size_t(device)], why)) return;
            throw InputError("",
                             "--gl-device " + std::to_string(device) + ": " + why + " (" + device_list(devices) + ")");
        }
        std::string tried;
        for (const bool pass_hardware : {true, false})
            for (const EglDevice& d : devices) {
                if (d.hardware != pass_hardware) continue;
                std::string why;
                if (try_device(d, why)) return;
                tried += "; " + d.name + ": " + why;
            }
        if (has_word(client, "EGL_MESA_platform_surfaceless") && platform_display) {
            std::string why;
            EGLDisplay dpy = platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
            if (try_egl_display(dpy, why)) {
                detail = "egl, " + why + ", surfaceless platform";
                return;
            }
            tried += "; surfaceless platform: " + why;
        }
        throw InputError("", "EGL: cannot create an OpenGL 4.5 core-profile context without a window (client "
                             "extensions: " + std::string(client ? client : "none") + tried + ")");
    }

    ~Impl()
    {
        if (osmesa) osmesa_api().destroy(osmesa);
        if (egl_context != EGL_NO_CONTEXT) {
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, egl_context);
        }
        if (display != EGL_NO_DISPLAY) eglTerminate(display);
    }
};

GlContext::GlContext(GlPlatform platform, GlProfile profile, int egl_device) : impl_(std::make_unique<Impl>())
{
    impl_->platform = platform;
    info_.platform = platform;
    if (platform == GlPlatform::osmesa && egl_device >= 0)
        throw InputError("", "--gl-device chooses an EGL device: it needs --gl egl");
    if (platform == GlPlatform::osmesa)
        impl_->create_osmesa(info_.detail, profile);
    else if (profile == GlProfile::compatibility)
        throw InputError("",
                         "EGL: uvr asks for a compatibility-profile context (the paper's ARB programs, --backend "
                         "arb) only through OSMesa");
    else
        impl_->create_egl(info_.detail, info_.hardware, egl_device);

    const std::string where = gl_platform_name(platform);
#define UVR_GL_LOAD(type, name)                                                                                     \
    gl_.name = reinterpret_cast<type>(impl_->proc("gl" #name));                                                     \
    if (!gl_.name) throw InputError("", where + ": the OpenGL entry point gl" #name " is missing");
    UVR_GL_FUNCTIONS(UVR_GL_LOAD)
#undef UVR_GL_LOAD

    auto str = [&](GLenum e) {
        const GLubyte* s = gl_.GetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    info_.vendor = str(GL_VENDOR);
    info_.renderer = str(GL_RENDERER);
    info_.version = str(GL_VERSION);
    info_.glsl_version = str(GL_SHADING_LANGUAGE_VERSION);
    int major = 0, minor = 0;
    if (!parse_version(info_.version, major, minor) || major * 10 + minor < 45)
        throw InputError("", where + ": OpenGL 4.5 is needed, the context has '" + info_.version + "' (" +
                                 info_.renderer + ")");
    if (renderer_is_software(info_.renderer)) info_.hardware = false;
    GLint n = 0;
    gl_.GetIntegerv(GL_NUM_EXTENSIONS, &n);
    if (const char* hide = std::getenv("UVR_GL_HIDE_EXTENSIONS")) {
        std::istringstream in(hide);
        for (std::string name; std::getline(in, name, ',');)
            if (!name.empty()) info_.hidden.push_back(name);
    }
    for (GLint i = 0; i < n; ++i) {
        const GLubyte* e = gl_.GetStringi(GL_EXTENSIONS, GLuint(i));
        const std::string name = e ? reinterpret_cast<const char*>(e) : "";
        if (!name.empty() && !info_.hides(name)) info_.extensions.push_back(name);
    }
    gl_.GetIntegerv(GL_MAX_DRAW_BUFFERS, &info_.max_draw_buffers);
    gl_.GetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &info_.max_color_attachments);
    check_error("creating the context");
}

bool egl_device_is_software(const std::string& device_extensions)
{
    return has_word(device_extensions.c_str(), "EGL_MESA_device_software");
}

bool renderer_is_software(const std::string& renderer)
{
    return renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
}

GlContext::~GlContext() = default;

void GlContext::make_current() { impl_->make_current(); }

void* GlContext::proc_address(const char* name) const { return impl_->proc(name); }

void GlContext::check_error(const std::string& what) const
{
    const GLenum e = gl_.GetError();
    if (e != GL_NO_ERROR) throw InputError("", what + ": GL error " + hex(e));
}

// ---- Shaders ----

std::string shader_dir()
{
    const char* env = std::getenv("UVR_SHADER_DIR");
    return env && *env ? std::string(env) : std::string(UVR_SHADER_DIR);
}

std::string read_shader_file(const std::string& name)
{
    const std::string path = shader_dir() + "/" + name;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "cannot open the shader (shaders are read from $UVR_SHADER_DIR or " +
                                        std::string(UVR_SHADER_DIR) + ")");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

namespace {

std::string shader_log(const GlFunctions& gl, GLuint shader)
{
    GLint len = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(std::size_t(len > 0 ? len : 1), '\0');
    gl.GetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    return log.c_str();
}

// Compiles one stage from its strings; `names` (one per string) make the error message.
GLuint compile_stage(const GlFunctions& gl, GLenum type, const std::vector<std::string>& strings,
                     const std::vector<std::string>& names)
{
    const GLuint sh = gl.CreateShader(type);
    std::vector<const char*> ptrs;
    for (const auto& s : strings) ptrs.push_back(s.c_str());
    gl.ShaderSource(sh, GLsizei(ptrs.size()), ptrs.data(), nullptr);
    gl.CompileShader(sh);
    GLint ok = 0;
    gl.GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string log = shader_log(gl, sh);
        gl.DeleteShader(sh);
        std::string map, file = names.back();
        for (std::size_t i = 0; i < names.size(); ++i) map += (i ? ", " : "") + std::to_string(i) + " = " + names[i];
        // Mesa's log starts "N:LINE(COL): error": name the file of source string N.
        unsigned n = 0;
        if (std::sscanf(log.c_str(), "%u:", &n) == 1 && n < names.size()) file = names[n];
        throw InputError(file, "the shader does not compile (source strings: " + map + "):\n" + log);
    }
    return sh;
}

GLuint link(const GlFunctions& gl, GLuint vs, GLuint fs, const std::string& name)
{
    const GLuint prog = gl.CreateProgram();
    gl.AttachShader(prog, vs);
    gl.AttachShader(prog, fs);
    gl.LinkProgram(prog);
    gl.DeleteShader(vs);
    gl.DeleteShader(fs);
    GLint ok = 0;
    gl.GetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        gl.GetProgramiv(prog, GL_INFO_LOG_LENGTH, &len);
        std::string log(std::size_t(len > 0 ? len : 1), '\0');
        gl.GetProgramInfoLog(prog, GLsizei(log.size()), nullptr, log.data());
        gl.DeleteProgram(prog);
        throw InputError(name, "the shader program does not link:\n" + std::string(log.c_str()));
    }
    return prog;
}

void assemble(const GlShaderSource& src, std::vector<std::string>& strings, std::vector<std::string>& names)
{
    std::string prelude = "#version 450 core\n";
    for (const auto& e : src.extensions) prelude += "#extension " + e + " : require\n";
    for (const auto& [name, value] : src.defines) prelude += "#define " + name + " " + value + "\n";
    strings.push_back(prelude);
    names.push_back("prelude");
    for (const auto& f : src.files) {
        strings.push_back("#line 1 " + std::to_string(strings.size()) + "\n" + read_shader_file(f));
        names.push_back(shader_dir() + "/" + f);
    }
}

}  // namespace

std::string assembled_source(const GlShaderSource& src)
{
    std::vector<std::string> strings, names;
    assemble(src, strings, names);
    std::string text;
    for (const std::string& s : strings) text += s;
    return text;
}

GlProgram::GlProgram(const GlContext& ctx, const GlShaderSource& vertex, const GlShaderSource& fragment) : ctx_(ctx)
{
    const GlFunctions& gl = ctx.gl();
    std::vector<std::string> vs_strings, vs_names, fs_strings, fs_names;
    assemble(vertex, vs_strings, vs_names);
    assemble(fragment, fs_strings, fs_names);
    const GLuint vs = compile_stage(gl, GL_VERTEX_SHADER, vs_strings, vs_names);
    GLuint fs = 0;
    try {
        fs = compile_stage(gl, GL_FRAGMENT_SHADER, fs_strings, fs_names);
    } catch (...) {
        gl.DeleteShader(vs);
        throw;
    }
    id_ = link(gl, vs, fs, fs_names.back());
}

GlProgram::~GlProgram()
{
    if (id_) ctx_.gl().DeleteProgram(id_);
}

GLint GlProgram::uniform(const char* name, bool required) const
{
    const GLint loc = ctx_.gl().GetUniformLocation(id_, name);
    if (loc < 0 && required) throw InputError("", std::string("the shader program has no uniform '") + name + "'");
    return loc;
}

GLuint compile_program_from_strings(const GlContext& ctx, const std::string& name, const std::string& vertex_text,
                                    const std::string& fragment_text)
{
    const GlFunctions& gl = ctx.gl();
    const GLuint vs = compile_stage(gl, GL_VERTEX_SHADER, {vertex_text}, {name});
    GLuint fs = 0;
    try {
        fs = compile_stage(gl, GL_FRAGMENT_SHADER, {fragment_text}, {name});
    } catch (...) {
        gl.DeleteShader(vs);
        throw;
    }
    return link(gl, vs, fs, name);
}

void check_framebuffer(const GlContext& ctx, const std::string& what)
{
    const GLenum s = ctx.gl().CheckFramebufferStatus(GL_DRAW_FRAMEBUFFER);
    if (s == GL_FRAMEBUFFER_COMPLETE) return;
    const char* name = "unknown status";
    switch (s) {
    case GL_FRAMEBUFFER_UNDEFINED: name = "GL_FRAMEBUFFER_UNDEFINED"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: name = "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: name = "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER: name = "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER: name = "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER"; break;
    case GL_FRAMEBUFFER_UNSUPPORTED: name = "GL_FRAMEBUFFER_UNSUPPORTED"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: name = "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS: name = "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS"; break;
    default: break;
    }
    throw InputError("", what + ": framebuffer incomplete (" + std::string(name) + ", " + hex(s) + ")");
}

}  // namespace uvr::gpu
