// The picture backend of builds without VTK (-DODEC_PICTURES=OFF, and the fuzzing and replay
// programs of tests/fuzz/): `plot` builds its whole scene as usual, then draws nothing and
// writes no file. Everything else of vtk_backend.h does nothing.
#include "render/vtk_backend.h"

namespace odec::render {

bool render_png(const Scene&, const std::string&, std::string&) { return true; }

RenderTimes last_render_times() { return {}; }

std::string renderer_description() { return "none (built without pictures)"; }

void set_gl_context_kind(GlContextKind) {}

void shutdown_renderer() {}

} // namespace odec::render
