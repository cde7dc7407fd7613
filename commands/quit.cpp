#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& quit_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("quit", 4, "leave odec");
        c.alias("exit");
        c.example("quit");
        c.refuse_while_cycling("it would leave odec in the middle of a step; to end the stepping from FISH, "
                               "stop it with the FISH statement 'error'");
        c.handle([](CommandContext& ctx, const Args&) { ctx.interp.quit_requested = true; });
        return c;
    }();
    return spec;
}

} // namespace odec
