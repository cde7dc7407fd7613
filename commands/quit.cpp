#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& quit_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("quit", 4, "leave odec");
        c.alias("exit");
        c.example("quit");
        c.handle([](CommandContext& ctx, const Args&) { ctx.interp.quit_requested = true; });
        return c;
    }();
    return spec;
}

} // namespace odec
