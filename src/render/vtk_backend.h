// Drawing a Scene to a PNG file, off-screen, with VTK (the only VTK user in odec).
#pragma once

#include <string>

#include "render/gl_context.h"
#include "render/scene.h"

namespace odec::render {

// Where the time of the last picture went (milliseconds), for `set echo` and benchmarks.
struct RenderTimes {
    double context_ms = 0; // creating the GL context and render window (0 when warm)
    double build_ms = 0;   // scene -> VTK pipeline
    double draw_ms = 0;    // rendering the frame
    double write_ms = 0;   // read-back and PNG
    double total_ms = 0;
};

// Draw `scene` into a PNG at `path` (scene.width x scene.height pixels). The file is
// written under a temporary name and renamed, so it is either whole or absent. The GL
// context and render window are made on the first call and kept for later ones.
// Returns false and fills `error` when nothing could be drawn or written.
bool render_png(const Scene& scene, const std::string& path, std::string& error);

// Timing of the last successful render_png.
RenderTimes last_render_times();

// "OSMesa: OpenGL 4.5 (Core Profile) Mesa 22.3.6 (llvmpipe ...)" once a picture was drawn,
// empty before.
std::string renderer_description();

// The context kind used from the next picture on (default: ODEC_GL, else OSMesa). A live
// renderer of another kind is shut down first.
void set_gl_context_kind(GlContextKind kind);

// Release the render window and the GL context (the window is finalized while its context
// is still alive). Safe to call more than once; a later render_png starts afresh.
void shutdown_renderer();

} // namespace odec::render
