#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& return_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("return", 3, "stop reading the current data file and go back to its caller");
        c.example("return");
        c.handle([](CommandContext& ctx, const Args&) { ctx.interp.return_requested = true; });
        return c;
    }();
    return spec;
}

} // namespace odec
