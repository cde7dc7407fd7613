// The EGL surfaceless context: the second way to get an off-screen GL context.
//
// Mesa's EGL_PLATFORM_SURFACELESS_MESA needs no display server; a small pbuffer gives
// the context a default framebuffer (VTK renders into framebuffer objects of its own, as
// with OSMesa). glvnd dispatches GL calls to whichever context is current, so on a machine
// with a GPU driver this path draws with the GPU. EGL functions are looked up at run time
// (dlopen of libEGL.so.1) so that odec links and runs where EGL is absent.
#include "render/gl_context.h"

#ifndef ODEC_HAVE_EGL

namespace odec::render {

std::unique_ptr<GlContext> create_egl_context(std::string& error) {
    error = "odec was built without EGL (install libegl-dev and rebuild)";
    return nullptr;
}

} // namespace odec::render

#else

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <dlfcn.h>

namespace odec::render {

namespace {

struct EglApi {
    void* lib = nullptr;
    PFNEGLGETPROCADDRESSPROC get_proc = nullptr;
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = nullptr;
    PFNEGLINITIALIZEPROC initialize = nullptr;
    PFNEGLTERMINATEPROC terminate = nullptr;
    PFNEGLCHOOSECONFIGPROC choose_config = nullptr;
    PFNEGLCREATEPBUFFERSURFACEPROC create_pbuffer = nullptr;
    PFNEGLBINDAPIPROC bind_api = nullptr;
    PFNEGLCREATECONTEXTPROC create_context = nullptr;
    PFNEGLMAKECURRENTPROC make_current = nullptr;
    PFNEGLGETCURRENTCONTEXTPROC get_current_context = nullptr;
    PFNEGLDESTROYCONTEXTPROC destroy_context = nullptr;
    PFNEGLDESTROYSURFACEPROC destroy_surface = nullptr;

    bool load(std::string& error) {
        if (lib) return true;
        lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
        if (!lib) {
            error = "EGL is not installed (libEGL.so.1 not found)";
            return false;
        }
        get_proc = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(lib, "eglGetProcAddress"));
        if (!get_proc) {
            error = "libEGL.so.1 has no eglGetProcAddress";
            return false;
        }
        auto get = [&](const char* name) { return reinterpret_cast<void*>(get_proc(name)); };
        get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(get("eglGetPlatformDisplayEXT"));
        initialize = reinterpret_cast<PFNEGLINITIALIZEPROC>(get("eglInitialize"));
        terminate = reinterpret_cast<PFNEGLTERMINATEPROC>(get("eglTerminate"));
        choose_config = reinterpret_cast<PFNEGLCHOOSECONFIGPROC>(get("eglChooseConfig"));
        create_pbuffer = reinterpret_cast<PFNEGLCREATEPBUFFERSURFACEPROC>(get("eglCreatePbufferSurface"));
        bind_api = reinterpret_cast<PFNEGLBINDAPIPROC>(get("eglBindAPI"));
        create_context = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(get("eglCreateContext"));
        make_current = reinterpret_cast<PFNEGLMAKECURRENTPROC>(get("eglMakeCurrent"));
        get_current_context = reinterpret_cast<PFNEGLGETCURRENTCONTEXTPROC>(get("eglGetCurrentContext"));
        destroy_context = reinterpret_cast<PFNEGLDESTROYCONTEXTPROC>(get("eglDestroyContext"));
        destroy_surface = reinterpret_cast<PFNEGLDESTROYSURFACEPROC>(get("eglDestroySurface"));
        if (!get_platform_display || !initialize || !terminate || !choose_config || !create_pbuffer ||
            !bind_api || !create_context || !make_current || !get_current_context || !destroy_context ||
            !destroy_surface) {
            error = "EGL lacks EGL_EXT_platform_base or a core entry point";
            return false;
        }
        return true;
    }
};

EglApi& egl() {
    static EglApi api;
    return api;
}

class EglGlContext final : public GlContext {
public:
    EglGlContext(EGLDisplay display, EGLSurface surface, EGLContext context)
        : display_(display), surface_(surface), context_(context) {}
    ~EglGlContext() override {
        EglApi& api = egl();
        api.make_current(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        api.destroy_context(display_, context_);
        api.destroy_surface(display_, surface_);
        api.terminate(display_);
        set_proc_address_source(nullptr);
    }
    bool make_current() override {
        set_proc_address_source(this);
        return egl().make_current(display_, surface_, surface_, context_) == EGL_TRUE;
    }
    bool is_current() const override { return egl().get_current_context() == context_; }
    void* proc_address(const char* name) const override {
        return reinterpret_cast<void*>(egl().get_proc(name));
    }
    GlContextKind kind() const override { return GlContextKind::Egl; }
    const char* name() const override { return "EGL"; }

private:
    EGLDisplay display_;
    EGLSurface surface_;
    EGLContext context_;
};

} // namespace

std::unique_ptr<GlContext> create_egl_context(std::string& error) {
    EglApi& api = egl();
    if (!api.load(error)) return nullptr;
    EGLDisplay display = api.get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) {
        error = "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless)";
        return nullptr;
    }
    EGLint major = 0, minor = 0;
    if (api.initialize(display, &major, &minor) != EGL_TRUE) {
        error = "EGL could not initialise the surfaceless display";
        return nullptr;
    }
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                     EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
                                     EGL_ALPHA_SIZE, 8, EGL_DEPTH_SIZE, 24,
                                     EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint n_configs = 0;
    if (api.choose_config(display, config_attribs, &config, 1, &n_configs) != EGL_TRUE || n_configs < 1) {
        api.terminate(display);
        error = "EGL offers no RGBA pbuffer configuration for desktop OpenGL";
        return nullptr;
    }
    const EGLint pbuffer_attribs[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
    EGLSurface surface = api.create_pbuffer(display, config, pbuffer_attribs);
    if (surface == EGL_NO_SURFACE) {
        api.terminate(display);
        error = "EGL could not create a pbuffer";
        return nullptr;
    }
    if (api.bind_api(EGL_OPENGL_API) != EGL_TRUE) {
        api.destroy_surface(display, surface);
        api.terminate(display);
        error = "EGL cannot bind the desktop OpenGL API";
        return nullptr;
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 2,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    EGLContext ctx = api.create_context(display, config, EGL_NO_CONTEXT, context_attribs);
    if (ctx == EGL_NO_CONTEXT) {
        api.destroy_surface(display, surface);
        api.terminate(display);
        error = "EGL could not create an OpenGL 3.2 core context";
        return nullptr;
    }
    auto context = std::make_unique<EglGlContext>(display, surface, ctx);
    if (!context->make_current()) {
        error = "EGL could not make its context current";
        return nullptr;
    }
    return context;
}

} // namespace odec::render

#endif // ODEC_HAVE_EGL
