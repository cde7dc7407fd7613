#include "commands.h"
#include "common.h"
#include "fish/runtime.h"

namespace odec {

const CommandSpec& new_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("new", 3, "clear the model and start again");
        c.describe("Removes every block, material, history and setting, and every FISH function and "
                   "variable; the prompt and the running script go on. Run from a FISH function (in a "
                   "'command' block, or in a file that a function calls), 'new' clears the model but keeps "
                   "the FISH functions, variables and arrays, the file FISH has open and the sequence of "
                   "urand/grand: the running function needs them, and a parametric study loops over 'new' "
                   "and its cases (3DEC refuses 'new' inside FISH altogether).");
        c.example("new");
        c.refuse_while_cycling("it would clear the model that is cycling");
        c.handle([](CommandContext& ctx, const Args& a) {
            ctx.interp.last_solve.reset();
            ctx.interp.last_fos.reset();
            if (ctx.interp.fish_running()) {
                ctx.model = Model();
                ctx.interp.fish().forget_model();
                if (!ctx.interp.new_in_fish_noted && !ctx.interp.quiet) {
                    ctx.interp.new_in_fish_noted = true;
                    const SourceLoc& l = a.loc;
                    ctx.out << (l.file ? l.file->name : std::string("<input>")) << ":" << l.line << ":" << l.col
                            << ": note: 'new' inside a FISH function clears the model and keeps the FISH functions "
                               "and variables (said once)\n";
                }
                return;
            }
            ctx.model = Model();
            ctx.interp.fish().clear();
        });
        return c;
    }();
    return spec;
}

} // namespace odec
