#include "commands.h"
#include "common.h"

namespace odec {

// Placeholder: being written.
const CommandSpec& export_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("export", 4, "(being written)");
        c.handle([](CommandContext&, const Args& a) { fail(a.loc, "'export' is not available yet"); });
        return c;
    }();
    return spec;
}

} // namespace odec
