#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& grav_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("gravity", 4, "set the gravity vector, m/s^2");
        c.positional.vec("g");
        c.example("grav 0 0 -10");
        c.handle([](CommandContext& ctx, const Args& a) { ctx.model.gravity = a.positional[0].vec; });
        return c;
    }();
    return spec;
}

} // namespace odec
