#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& config_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("config", 4, "choose the kinds of analysis (3DEC's configuration)");
        c.keyword("dynamic", 3, "dynamic analysis: always available in odec").many();
        c.describe("3DEC asks for 'config dyn' before a dynamic analysis. odec always runs the "
                   "mechanical model with its full equations of motion: what makes a run static or "
                   "dynamic is its damping ('damp local' or 'damp auto' for a static solution, "
                   "'damp rayleigh' or 'damp off' for a dynamic one) and its boundaries. 'config' "
                   "is accepted for scripts written for 3DEC and changes nothing.");
        c.example("config dyn");
        c.handle([](CommandContext&, const Args&) {});
        return c;
    }();
    return spec;
}

} // namespace odec
