#include "commands.h"
#include "common.h"
#include "fish/runtime.h"

namespace odec {

const CommandSpec& new_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("new", 3, "clear the model and start again");
        c.describe("Removes every block, material, history and setting, and every FISH function and "
                   "variable; the prompt and the running script go on.");
        c.example("new");
        c.handle([](CommandContext& ctx, const Args&) {
            ctx.model = Model();
            ctx.interp.fish().clear();
        });
        return c;
    }();
    return spec;
}

} // namespace odec
