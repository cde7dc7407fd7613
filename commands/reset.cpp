#include "commands.h"
#include "engine/cable.h"
#include "engine/liner.h"
#include "common.h"
#include "engine/zones.h"

namespace odec {

const CommandSpec& reset_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("reset", 3, "set accumulated quantities back to zero");
        c.keyword("displacement", 3, "block, gridpoint, cable and liner node displacements, block rotations");
        c.keyword("jdisp", 2, "joint shear displacements (the stresses are kept)");
        c.keyword("time", 2, "model time");
        c.keyword("history", 3, "the samples of every history (the histories themselves stay)");
        c.keyword("velocity", 3, "block and gridpoint velocities, block spins");
        c.keyword("energy", 3, "the energy account ('set energy on'): it starts afresh from the model as it is");
        c.example("reset disp jdisp time hist");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (a.uses.empty()) fail(a.loc, "'reset' needs what to reset: displacement, jdisp, time, history, velocity or energy", {}, "reset");
            if (a.has("energy") && !m.energy.on) {
                fail(a.find("energy")->loc, "the energy account is off", {"'set energy on' starts it"}, "reset");
            }
            BlockSet& s = m.blocks;
            if (a.has("displacement")) {
                for (int b = 0; b < s.size(); ++b) {
                    s.disp[b].setZero();
                    s.ref_orientation[b] = s.orientation[b];
                }
                for (Vec3& d : m.gridpoints.disp) d.setZero();
                reset_cable_displacements(m);
                reset_liner_displacements(m);
            }
            if (a.has("velocity")) {
                for (int b = 0; b < s.size(); ++b) {
                    s.vel[b].setZero();
                    s.ang_vel[b].setZero();
                    s.accel[b].setZero();
                    s.ang_accel[b].setZero();
                    s.half_kick[b] = 1;
                }
                GridpointSet& g = m.gridpoints;
                for (int i = 0; i < g.size(); ++i) {
                    g.vel[i].setZero();
                    g.half_kick[i] = 1;
                }
            }
            if (a.has("jdisp")) {
                for (auto& u : m.contacts.sub_us) u.setZero();
            }
            if (a.has("time")) m.time = 0;
            if (a.has("history")) m.histories.clear_values();
            // Last, so that the account starts from the velocities as reset.
            if (a.has("energy")) start_energy_account(m);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
