#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& config_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("config", 4, "choose the kinds of analysis (3DEC's configuration)");
        c.keyword("dynamic", 3, "make dynamic analysis available, and switch it on").many();
        c.keyword("flow", 4, "make fluid flow in the joints available, and switch it on ('help fluid')").many();
        c.keyword("fluid", 3, "same as 'flow' (3DEC's spelling: 'configure fluid')").many();
        c.describe("Without 'config dyn' an analysis is static: 'solve' and 'step' use density scaling, "
                   "every gridpoint and block taking the mass that lets the whole model converge at one "
                   "timestep, and model time is not real time. 'config dyn' (as in 3DEC, before the "
                   "model is built) makes dynamic analysis available and switches it on: real masses "
                   "and real time, for waves, shaking and collapse. 'set dyn off' then computes a static "
                   "equilibrium (gravity before an earthquake), 'set dyn on' goes back. 'new' forgets it. "
                   "'config flow' makes fluid flow along the joints available and switches it on: the fluid "
                   "('fluid'), the joints' hydraulic apertures ('prop jmat=n azero ares amax'), fixed pressures "
                   "('bound pp') and initial ones ('insitu pp') follow; 'set flow off' cycles without it, 'set "
                   "flow on' goes back, 'set flow steady|transient' chooses how the pressures advance. 3DEC's 'config "
                   "fluid' is the same as 'config flow'.");
        c.example("config dyn");
        c.example("config flow");
        c.handle([](CommandContext& ctx, const Args& a) {
            if (!a.has("dynamic") && !a.has("flow") && !a.has("fluid")) {
                fail(a.loc, "'config' needs what to configure", {"config dyn", "config flow"}, "config");
            }
            Model& m = ctx.model;
            if (a.has("dynamic")) {
                m.settings.dyn_configured = true;
                m.settings.dynamic = true;
                m.geometry_changed = true; // the masses are chosen again
                if (!ctx.interp.quiet) ctx.out << "dynamic analysis: real masses and real time ('set dyn off' for static)\n";
            }
            if (a.has("flow") || a.has("fluid")) {
                m.flow.configured = true;
                m.flow.on = true;
                m.geometry_changed = true; // held blocks have contacts only with flow on
                if (!ctx.interp.quiet) {
                    ctx.out << "fluid flow in the joints: on (" << (m.flow.mode == FlowMode::Steady ? "steady" : "transient")
                            << "; 'set flow off' to cycle without it)\n";
                }
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
