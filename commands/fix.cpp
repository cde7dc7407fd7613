#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& fix_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("fix", 3, "hold blocks still: no translation, no rotation");
        c.range();
        c.describe("Without a range every block is fixed. A fixed block still pushes on the blocks it "
                   "touches; 'free' releases it.");
        c.example("fix range z -5 0");
        c.handle([](CommandContext& ctx, const Args& a) {
            BlockSet& s = ctx.model.blocks;
            int n = 0;
            for (int b : blocks_to_change(ctx, a)) {
                n += !(s.flags[b] & kFixed);
                s.flags[b] |= kFixed;
                s.vel[b].setZero();
                s.ang_vel[b].setZero();
            }
            if (!ctx.interp.quiet) ctx.out << n << " blocks fixed\n";
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
            BlockSet& s = ctx.model.blocks;
            int n = 0;
            for (int b : blocks_to_change(ctx, a)) {
                if (s.flags[b] & kFixed) {
                    s.flags[b] &= static_cast<std::uint8_t>(~kFixed);
                    s.half_kick[b] = 1;
                    ++n;
                }
            }
            if (!ctx.interp.quiet) ctx.out << n << " blocks freed\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
