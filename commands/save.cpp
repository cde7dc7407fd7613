#include "commands.h"
#include "common.h"

namespace odec {

// Placeholder: being written.
const CommandSpec& save_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("save", 4, "(being written)");
        c.handle([](CommandContext&, const Args& a) { fail(a.loc, "'save' is not available yet"); });
        return c;
    }();
    return spec;
}

} // namespace odec
