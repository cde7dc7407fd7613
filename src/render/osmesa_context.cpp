// The OSMesa context, and the two shims that let Debian's GLX-built VTK draw into it.
//
// Why it is done this way. Debian 12's VTK 9.1 knows only X windows; asked to render with
// no X server it aborts. Rebuilding VTK is not an option for people who install odec from
// Debian packages, so odec makes a GL context itself and hands it to a
// vtkGenericOpenGLRenderWindow, which believes whatever it is told about its context.
// Three things then stand between VTK and the pixels:
//
//  1. GL entry points. VTK loads every GL function with GLEW, and Debian's GLEW is the GLX
//     build: it asks glXGetProcAddressARB for each name. The executable therefore defines
//     (and exports, see ODEC_EXPORTS in CMakeLists.txt) its own glXGetProcAddressARB and
//     glXGetProcAddress, which answer from the current context's driver (OSMesa or EGL) and
//     return null for names starting with "glX": GLEW would otherwise call a fake
//     glXGetCurrentDisplay and crash.
//  2. glewInit. Once the GL part is loaded GLEW goes on to initialise GLX, which fails with
//     GLEW_ERROR_GLX_VERSION_11_ONLY or GLEW_ERROR_NO_GLX_DISPLAY; VTK would report that
//     failure on every frame. The exported glewInit below calls the real one (found with
//     dlsym(RTLD_NEXT)) and maps those two results to GLEW_OK.
//  3. GL 1.x calls that VTK makes directly (glClear, glViewport, glReadPixels ...) are bound
//     by the dynamic linker, not by GLEW. They must bind to libOSMesa rather than to glvnd's
//     dispatch stubs, which is why the executables link libOSMesa first, with --no-as-needed.
//
// The context asks for a 3.2 core profile (VTK's OpenGL2 backend needs 3.2); Mesa gives
// 4.5 core on llvmpipe. VTK draws into framebuffer objects of its own and the picture is
// read back from those, so the OSMesa buffer itself is only a token binding and stays small.
#include <GL/glew.h>
// glew.h leaves GLAPI undefined, and osmesa.h needs it.
#ifndef GLAPI
#define GLAPI extern
#endif
#include <GL/osmesa.h>

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "render/gl_context.h"

namespace odec::render {

namespace {

const GlContext* g_proc_source = nullptr;

class OSMesaGlContext final : public GlContext {
public:
    OSMesaGlContext(OSMesaContext ctx) : ctx_(ctx), buffer_(kSide * kSide * 4, 0) {}
    ~OSMesaGlContext() override {
        if (g_proc_source == this) set_proc_address_source(nullptr);
        OSMesaDestroyContext(ctx_);
    }
    bool make_current() override {
        set_proc_address_source(this);
        return OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, kSide, kSide) == GL_TRUE;
    }
    bool is_current() const override { return OSMesaGetCurrentContext() == ctx_; }
    void* proc_address(const char* name) const override {
        return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
    }
    GlContextKind kind() const override { return GlContextKind::OSMesa; }
    const char* name() const override { return "OSMesa"; }

private:
    static constexpr int kSide = 16; // token default framebuffer; VTK renders to its own FBOs
    OSMesaContext ctx_;
    std::vector<unsigned char> buffer_;
};

} // namespace

std::unique_ptr<GlContext> create_osmesa_context(std::string& error) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                           OSMESA_DEPTH_BITS, 24,
                           OSMESA_STENCIL_BITS, 8,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3,
                           OSMESA_CONTEXT_MINOR_VERSION, 2,
                           0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx) {
        error = "OSMesa could not create an OpenGL 3.2 core context";
        return nullptr;
    }
    auto context = std::make_unique<OSMesaGlContext>(ctx);
    if (!context->make_current()) {
        error = "OSMesa could not make its context current";
        return nullptr;
    }
    return context;
}

GlContextKind default_gl_context_kind() {
    const char* v = std::getenv("ODEC_GL");
    if (v && (std::strcmp(v, "egl") == 0 || std::strcmp(v, "EGL") == 0)) return GlContextKind::Egl;
    return GlContextKind::OSMesa;
}

std::unique_ptr<GlContext> create_gl_context(GlContextKind kind, std::string& error) {
    if (kind == GlContextKind::Egl) return create_egl_context(error);
    return create_osmesa_context(error);
}

void set_proc_address_source(const GlContext* context) { g_proc_source = context; }

} // namespace odec::render

using odec::render::g_proc_source;

namespace {
void* forward_proc_address(const char* name) {
    if (!name || std::strncmp(name, "glX", 3) == 0) return nullptr;
    if (g_proc_source) return g_proc_source->proc_address(name);
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}
} // namespace

// Exported from the executable (ODEC_EXPORTS), so GLEW inside libGLEW binds to these.
extern "C" __attribute__((visibility("default"))) void* glXGetProcAddressARB(const unsigned char* name) {
    return forward_proc_address(reinterpret_cast<const char*>(name));
}

extern "C" __attribute__((visibility("default"))) void* glXGetProcAddress(const unsigned char* name) {
    return forward_proc_address(reinterpret_cast<const char*>(name));
}

extern "C" __attribute__((visibility("default"))) GLenum GLEWAPIENTRY glewInit(void) {
    using GlewInitFn = GLenum (*)(void);
    static GlewInitFn real = reinterpret_cast<GlewInitFn>(dlsym(RTLD_NEXT, "glewInit"));
    if (!real) return GLEW_ERROR_NO_GL_VERSION;
    const GLenum result = real();
    // The GL part succeeded; only GLX, which odec never uses, is missing.
    if (result == GLEW_ERROR_GLX_VERSION_11_ONLY || result == GLEW_ERROR_NO_GLX_DISPLAY) return GLEW_OK;
    return result;
}
