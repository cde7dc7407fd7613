#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& ini_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("initial", 3, "give blocks an initial velocity");
        c.keyword("xvel", 2, "velocity x component, m/s").real("v");
        c.keyword("yvel", 2, "velocity y component, m/s").real("v");
        c.keyword("zvel", 2, "velocity z component, m/s").real("v");
        c.range();
        c.describe("The velocity is that of the blocks at the present time; components not given are "
                   "kept. Fixed blocks stay still.");
        c.example("ini zvel -1 range group 'falling'");
        c.handle([](CommandContext& ctx, const Args& a) {
            if (!a.has("xvel") && !a.has("yvel") && !a.has("zvel")) {
                fail(a.loc, "'initial' needs one of: xvel, yvel, zvel", {}, "initial");
            }
            BlockSet& s = ctx.model.blocks;
            for (int b : blocks_to_change(ctx, a)) {
                if (s.flags[b] & kFixed) continue;
                if (a.has("xvel")) s.vel[b].x() = a.real("xvel");
                if (a.has("yvel")) s.vel[b].y() = a.real("yvel");
                if (a.has("zvel")) s.vel[b].z() = a.real("zvel");
                s.half_kick[b] = 1;
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
