#include "commands.h"
#include "common.h"
#include "engine/zones.h"

namespace odec {

const CommandSpec& fix_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("fix", 3, "hold blocks still: no translation, no rotation");
        c.range();
        c.describe("Without a range every block is fixed. A fixed block still pushes on the blocks it "
                   "touches; 'free' releases it. In deformable blocks the gridpoints the range selects by "
                   "their position are fixed (all three velocity components held at zero); rigid blocks "
                   "are selected by their centroid; the blocks of a solid that is not convex (a clump, "
                   "'poly') are fixed together when the range selects any of them.");
        c.example("fix range z -5 0");
        c.example("fix range z -0.01 0.01");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            BlockSet& s = m.blocks;
            const std::vector<int> gps = select_gridpoints(m, a.range);
            std::vector<int> blocks = gps.empty() ? blocks_to_change(ctx, a) : select_blocks(m, a.range);
            take_whole_clumps(ctx, blocks, "fixing");
            int n = 0;
            for (int b : blocks) {
                if (s.flags[b] & kDeformable) continue;
                n += !(s.flags[b] & kFixed);
                s.flags[b] |= kFixed;
                s.vel[b].setZero();
                s.ang_vel[b].setZero();
            }
            GridpointSet& g = m.gridpoints;
            for (int i : gps) {
                g.vel_bc[i] = 7;
                g.vel_bc_value[i].setZero();
                g.vel_bc_table[i] = 0;
                g.vel[i].setZero();
            }
            if (!gps.empty()) m.geometry_changed = true;
            if (!ctx.interp.quiet) {
                ctx.out << n << " blocks fixed";
                if (g.size() > 0) ctx.out << ", " << gps.size() << " gridpoints fixed";
                ctx.out << "\n";
            }
        });
        return c;
    }();
    return spec;
}

const CommandSpec& free_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("free", 3, "release blocks held by 'fix'");
        c.range();
        c.example("free range id 3");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            BlockSet& s = m.blocks;
            const std::vector<int> gps = select_gridpoints(m, a.range);
            std::vector<int> blocks = gps.empty() ? blocks_to_change(ctx, a) : select_blocks(m, a.range);
            take_whole_clumps(ctx, blocks, "freeing");
            int n = 0;
            for (int b : blocks) {
                if (s.flags[b] & kFixed) {
                    s.flags[b] &= static_cast<std::uint8_t>(~kFixed);
                    s.half_kick[b] = 1;
                    ++n;
                }
            }
            GridpointSet& g = m.gridpoints;
            for (int i : gps) {
                g.vel_bc[i] = 0;
                g.vel_bc_table[i] = 0;
                g.half_kick[i] = 1;
            }
            if (!gps.empty()) m.geometry_changed = true;
            if (!ctx.interp.quiet) {
                ctx.out << n << " blocks freed";
                if (g.size() > 0) ctx.out << ", " << gps.size() << " gridpoints freed";
                ctx.out << "\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
