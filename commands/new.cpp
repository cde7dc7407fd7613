#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& new_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("new", 3, "clear the model and start again");
        c.describe("Removes every block, material, history and setting; the prompt and the running "
                   "script go on.");
        c.example("new");
        c.handle([](CommandContext& ctx, const Args&) { ctx.model = Model(); });
        return c;
    }();
    return spec;
}

} // namespace odec
