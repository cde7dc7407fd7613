// An off-screen OpenGL context that VTK draws into.
//
// odec owns the GL context and lends it to VTK (see vtk_backend.cpp): Debian's VTK is
// built for X only, so its own windows cannot open without a display. Two kinds serve:
// OSMesa (software, always there with libosmesa6) and EGL surfaceless (Mesa's
// EGL_PLATFORM_SURFACELESS_MESA with a pbuffer; the way to a real GPU where one exists).
// No VTK and no GL headers here, so any file may hold a context.
#pragma once

#include <memory>
#include <string>

namespace odec::render {

enum class GlContextKind { OSMesa, Egl };

class GlContext {
public:
    virtual ~GlContext() = default;
    // Bind the context to the calling thread. Returns false when the driver refuses.
    virtual bool make_current() = 0;
    virtual bool is_current() const = 0;
    // Address of a GL entry point as this context's driver gives it, or null.
    virtual void* proc_address(const char* name) const = 0;
    virtual GlContextKind kind() const = 0;
    // "OSMesa" or "EGL", for messages.
    virtual const char* name() const = 0;
};

// Each returns null and fills `error` when the context cannot be made. The context is
// made current before it is returned.
std::unique_ptr<GlContext> create_osmesa_context(std::string& error);
std::unique_ptr<GlContext> create_egl_context(std::string& error);

// The kind chosen by the environment: ODEC_GL=egl asks for EGL, anything else OSMesa.
GlContextKind default_gl_context_kind();
std::unique_ptr<GlContext> create_gl_context(GlContextKind kind, std::string& error);

// The context whose driver answers glXGetProcAddress* (GLEW asks for every entry point
// through it); set by make_current of each context. Null: OSMesa answers.
void set_proc_address_source(const GlContext* context);

} // namespace odec::render
