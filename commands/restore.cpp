#include "commands.h"
#include "common.h"

namespace odec {

// Placeholder: being written.
const CommandSpec& restore_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("restore", 4, "(being written)");
        c.handle([](CommandContext&, const Args& a) { fail(a.loc, "'restore' is not available yet"); });
        return c;
    }();
    return spec;
}

} // namespace odec
