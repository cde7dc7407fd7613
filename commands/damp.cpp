#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& damp_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("damping", 4, "choose how motion is damped");
        c.positional.real("fraction", 0, 1).optional().real("frequency", 0, kInf, Limit::Open).optional();
        c.keyword("local", 3, "local damping: each force component reduced by a |f| against the motion")
            .real("a", 0, 1, Limit::Closed, Limit::Open).optional("0.8").in_choice(1);
        c.keyword("auto", 2, "adaptive global damping: viscous, 0.7 of critical for the slowest motion the model shows")
            .in_choice(1);
        c.keyword("mass", 2, "mass-proportional Rayleigh damping: 'damp fraction frequency mass'").in_choice(1);
        c.keyword("off", 2, "no damping, for dynamics").in_choice(1);
        c.describe("Local damping with a = 0.8 is the default, for blocks and gridpoints alike: it brings a "
                   "model to equilibrium and does not bias a steady motion (a strength test driven by 'bound "
                   "zvel'), but it is not physical: a block falling freely under it accelerates at (1 - a) g. "
                   "'damp auto' sets a viscous damping each step from the frequency of the motion the model "
                   "shows (its unbalanced forces' change over the step against its velocities): 0.7 of "
                   "critical for the slowest mode, which is what is left to settle; a motion against no "
                   "stiffness (a block sliding freely) draws almost none. With the density scaling of a "
                   "static analysis (see 'config') it reaches the equilibrium of a deformable model in a "
                   "quarter to a sixth of the steps local damping takes (an elastic column: 413 steps "
                   "against 1,820; the Kirsch hole: 347 against 2,204). Being viscous, it drags gridpoints "
                   "driven at a steady velocity (a footing pushed by 'bound zvel' reads some 6 % high), so "
                   "keep local damping for strength tests. Use 'damp off' or 'damp ... mass' for dynamics.");
        c.example("damp local 0.8");
        c.example("damp 0.05 1.5 mass");
        c.handle([](CommandContext& ctx, const Args& a) {
            Damping& d = ctx.model.damping;
            const std::string mode = a.chosen(1);
            if (mode == "mass") {
                if (a.positional.size() < 2) {
                    fail(a.find("mass")->loc, "'damp ... mass' needs the critical damping fraction and the frequency",
                         {"for example: damp 0.05 1.5 mass"}, "damping");
                }
            } else if (!a.positional.empty()) {
                fail(a.positional[0].loc, "a damping fraction and frequency go with 'mass'",
                     {"for example: damp 0.05 1.5 mass"}, "damping");
            }
            if (mode.empty()) {
                fail(a.loc, "'damping' needs one of: local, auto, mass, off", {}, "damping");
            }
            if (mode == "local") {
                d.mode = DampingMode::Local;
                d.local = a.find("local")->values.empty() ? 0.8 : a.real("local");
            } else if (mode == "auto") {
                d.mode = DampingMode::Auto;
                d.auto_coefficient = 0;
                // The estimate starts afresh from the next step (integrate.cpp).
                d.auto_after = 0;
                d.auto_inertia = 0;
                d.auto_dt = 0;
            } else if (mode == "mass") {
                d.mode = DampingMode::Rayleigh;
                d.rayleigh_fraction = a.positional[0].number;
                d.rayleigh_frequency = a.positional[1].number;
            } else {
                d.mode = DampingMode::Off;
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
