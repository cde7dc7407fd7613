#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& bound_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("boundary", 3, "prescribe block velocities or apply forces");
        c.alias("apply");
        c.keyword("xvelocity", 2, "hold the x velocity at v, m/s").real("v");
        c.keyword("yvelocity", 2, "hold the y velocity at v, m/s").real("v");
        c.keyword("zvelocity", 2, "hold the z velocity at v, m/s").real("v");
        c.keyword("xload", 2, "apply a force fx, N, to each block").real("fx");
        c.keyword("yload", 2, "apply a force fy, N, to each block").real("fy");
        c.keyword("zload", 2, "apply a force fz, N, to each block").real("fz");
        c.keyword("history", 4, "scale the velocities by table n of time: v(t) = v table(t)").integer("table", 1).labelled();
        c.keyword("free", 3, "release prescribed velocities and remove applied forces");
        c.range();
        c.describe("A prescribed velocity component is held whatever the forces; the others stay free. "
                   "Loads add to gravity and contact forces. Without a range every block is taken.");
        c.example("bound xvel 0.01 range z 9 10");
        c.example("apply xvel 2.8 hist table 1 range z -1 0");
        c.example("bound zload -1e6 range id 5");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            BlockSet& s = m.blocks;
            const char* vel[3] = {"xvelocity", "yvelocity", "zvelocity"};
            const char* load[3] = {"xload", "yload", "zload"};
            bool any_vel = false, any = a.has("free");
            for (int i = 0; i < 3; ++i) {
                any_vel = any_vel || a.has(vel[i]);
                any = any || a.has(vel[i]) || a.has(load[i]);
            }
            if (!any) fail(a.loc, "'boundary' needs a velocity (xvel ...), a load (xload ...) or 'free'", {}, "boundary");
            if (a.has("history") && !any_vel) {
                fail(a.find("history")->loc, "'hist table n' goes with a velocity", {}, "boundary");
            }
            const int table = a.has("history") ? a.integer("history") : 0;
            if (table > 0 && !m.tables.find(table)) {
                fail(a.find("history")->values[0].loc, "there is no table " + std::to_string(table),
                     {"define it first: table " + std::to_string(table) + " x1 y1 x2 y2 ..."}, "boundary");
            }
            for (int b : blocks_to_change(ctx, a)) {
                if (a.has("free")) {
                    s.vel_bc[b] = 0;
                    s.vel_bc_table[b] = 0;
                    s.applied_force[b].setZero();
                }
                for (int i = 0; i < 3; ++i) {
                    if (a.has(vel[i])) {
                        s.vel_bc[b] |= static_cast<std::uint8_t>(1 << i);
                        s.vel_bc_value[b][i] = a.real(vel[i]);
                        s.vel_bc_table[b] = table;
                    }
                    if (a.has(load[i])) s.applied_force[b][i] = a.real(load[i]);
                }
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
