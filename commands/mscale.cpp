#include "analysis_mode.h"
#include "commands.h"
#include "common.h"
#include "engine/cycle.h"

namespace odec {

const CommandSpec& mscale_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("mscale", 3, "partial density scaling for dynamic analysis: the few masses that hold the "
                                   "timestep down are raised to allow this one");
        c.positional.real("dt", 0, kInf, Limit::Open).or_word("off");
        c.describe("In dynamic mode the timestep is set by the smallest zones and the lightest blocks; a few "
                   "slivers or small blocks can make it many times smaller than the rest need. 'mscale dt' "
                   "gives just those gridpoints, blocks (a block held by stiff grout or a liner's bond "
                   "too) and cable and liner nodes the mass that lets them take the step dt, "
                   "leaving every other mass real; each cycling command that chooses the masses anew says "
                   "how many were scaled and how much mass was added (a few percent of the model's is "
                   "harmless to its dynamics; much more is not). dt must be larger than the timestep the "
                   "model takes with real masses. 'mscale off' goes back to real masses. A timestep forced "
                   "with 'set dt' takes precedence. In static mode every mass is scaled already: 'mscale' "
                   "is kept for when 'set dyn on' returns to dynamic analysis.");
        c.example("mscale 5e-6");
        c.example("mscale off");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const Value& v = a.positional.at(0);
            if (v.text == "off") {
                m.settings.mscale_dt = 0;
                m.geometry_changed = true;
                if (!ctx.interp.quiet) ctx.out << "mscale off: real masses in dynamic mode\n";
                return;
            }
            if (m.blocks.size() == 0) {
                fail(v.loc, "there is nothing to scale: the model has no blocks", {"build the model first"}, "mscale");
            }
            std::string why;
            const double real = real_mass_timestep(m, &why);
            if (real > 0 && !(v.number > real)) {
                fail(v.loc, "the timestep " + num(v.number) + " s is not above the one the model takes with real masses, " +
                                num(real) + " s: there is nothing to scale",
                     {"give a larger timestep, or 'mscale off'"}, "mscale");
            }
            m.settings.mscale_dt = v.number;
            m.geometry_changed = true;
            if (real <= 0) {
                warn(ctx, v.loc, "the model cannot cycle yet (" + why + "): the masses are scaled when it does");
            }
            if (!m.settings.dynamic) {
                warn(ctx, v.loc, "the analysis is static, where every mass is scaled already: 'mscale' applies once "
                                 "'set dyn on' (after 'config dyn') makes it dynamic");
            } else if (!ctx.interp.quiet) {
                ctx.out << "mscale: masses that need a step below " << num(v.number) << " s are raised to allow it"
                        << (real > 0 ? " (real masses: " + num(real) + " s)" : std::string()) << "\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
