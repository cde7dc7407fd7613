#include <algorithm>

#include "commands.h"
#include "common.h"
#include "engine/zones.h"

namespace odec {

namespace {

void set_excavated(CommandContext& ctx, const Args& a, bool on) {
    BlockSet& s = ctx.model.blocks;
    int n = 0;
    std::vector<int> blocks = select_blocks(ctx.model, a.range, true);
    take_whole_clumps(ctx, blocks, on ? "excavating" : "filling");
    std::vector<int> filled;
    for (int b : blocks) {
        const bool was = s.flags[b] & kExcavated;
        if (was == on) continue;
        if (on) {
            s.flags[b] |= kExcavated;
        } else {
            s.flags[b] &= static_cast<std::uint8_t>(~kExcavated);
            s.vel[b].setZero();
            s.ang_vel[b].setZero();
            s.half_kick[b] = 1;
            filled.push_back(b);
        }
        ++n;
    }
    // A filled block is new material: its zones start unstressed and elastic, its gridpoints at rest.
    if (!filled.empty()) {
        std::sort(filled.begin(), filled.end());
        ZoneSet& z = ctx.model.zones;
        for (int i = 0; i < z.size(); ++i) {
            if (!std::binary_search(filled.begin(), filled.end(), z.block[i])) continue;
            z.stress[i] = Sym6{0, 0, 0, 0, 0, 0};
            z.state[i] = 0;
        }
        GridpointSet& g = ctx.model.gridpoints;
        for (int i = 0; i < g.size(); ++i) {
            if (!std::binary_search(filled.begin(), filled.end(), g.block[i])) continue;
            g.vel[i].setZero();
            g.half_kick[i] = 1;
        }
    }
    ctx.model.geometry_changed = true;
    if (!ctx.interp.quiet) ctx.out << (on ? "excavated " : "filled ") << n << " blocks\n";
}

} // namespace

const CommandSpec& excavate_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("excavate", 3, "null blocks: they leave the model but are kept for 'fill'");
        c.range();
        c.describe("Excavated blocks carry no load and make no contacts; 'fill' brings them back where "
                   "they were, at rest; a zoned block comes back as new material, its zones unstressed. This is how a cavern is excavated in stages. A clump (the blocks of a solid that "
                   "is not convex, 'poly') is excavated and filled whole when the range selects any of its blocks.");
        c.example("excavate range cylinder 0,-10,0 0,10,0 3");
        c.handle([](CommandContext& ctx, const Args& a) {
            if (!a.has_range) fail(a.loc, "'excavate' needs a range", {}, "excavate");
            set_excavated(ctx, a, true);
        });
        return c;
    }();
    return spec;
}

const CommandSpec& fill_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("fill", 3, "bring excavated blocks back");
        c.range();
        c.example("fill range group 'stage2'");
        c.handle([](CommandContext& ctx, const Args& a) { set_excavated(ctx, a, false); });
        return c;
    }();
    return spec;
}

} // namespace odec
