#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& config_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("config", 4, "choose the kinds of analysis (3DEC's configuration)");
        c.keyword("dynamic", 3, "make dynamic analysis available, and switch it on").many();
        c.describe("Without 'config dyn' an analysis is static: 'solve' and 'step' use density scaling, "
                   "every gridpoint and block taking the mass that lets the whole model converge at one "
                   "timestep, and model time is not real time. 'config dyn' (as in 3DEC, before the "
                   "model is built) makes dynamic analysis available and switches it on: real masses "
                   "and real time, for waves, shaking and collapse. 'set dyn off' then computes a static "
                   "equilibrium (gravity before an earthquake), 'set dyn on' goes back. 'new' forgets it.");
        c.example("config dyn");
        c.handle([](CommandContext& ctx, const Args& a) {
            if (!a.has("dynamic")) fail(a.loc, "'config' needs what to configure", {"config dyn"}, "config");
            Model& m = ctx.model;
            m.settings.dyn_configured = true;
            m.settings.dynamic = true;
            m.geometry_changed = true; // the masses are chosen again
            if (!ctx.interp.quiet) ctx.out << "dynamic analysis: real masses and real time ('set dyn off' for static)\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
