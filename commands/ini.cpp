#include "commands.h"
#include "common.h"
#include "engine/zones.h"

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
            // In deformable blocks, the gridpoints the range selects by their position.
            GridpointSet& g = ctx.model.gridpoints;
            const std::vector<int> gps = select_gridpoints(ctx.model, a.range);
            for (int i : gps) {
                for (int k = 0; k < 3; ++k) {
                    const char* w = k == 0 ? "xvel" : k == 1 ? "yvel" : "zvel";
                    if (a.has(w) && !(g.vel_bc[i] & (1 << k))) g.vel[i][k] = a.real(w);
                }
                g.half_kick[i] = 1;
            }
            const std::vector<int> blocks = gps.empty() ? blocks_to_change(ctx, a) : select_blocks(ctx.model, a.range);
            for (int b : blocks) {
                if (s.flags[b] & (kFixed | kDeformable)) continue;
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
