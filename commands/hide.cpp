#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& hide_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("hide", 3, "hide blocks from 'jset' and from pictures");
        c.range();
        c.describe("Hidden blocks still move and carry load; 'seek' shows them all again.");
        c.example("hide range z -10 0");
        c.handle([](CommandContext& ctx, const Args& a) {
            for (int b : blocks_to_change(ctx, a, true)) ctx.model.blocks.flags[b] |= kHidden;
        });
        return c;
    }();
    return spec;
}

const CommandSpec& seek_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("seek", 3, "show every hidden block again");
        c.example("seek");
        c.handle([](CommandContext& ctx, const Args&) {
            for (auto& f : ctx.model.blocks.flags) f &= static_cast<std::uint8_t>(~kHidden);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
