#include "commands.h"
#include "common.h"

namespace odec {

// Placeholder: being written.
const CommandSpec& plot_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("plot", 4, "(being written)");
        c.handle([](CommandContext&, const Args& a) { fail(a.loc, "'plot' is not available yet"); });
        return c;
    }();
    return spec;
}

} // namespace odec
