#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& show_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("show", 4, "show hidden blocks again (all, or those of a range)");
        c.range("which hidden blocks to show (all when no range is given)");
        c.describe("The opposite of 'hide'. Without a range every block is shown, as 'seek' does.");
        c.example("show range id 3");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (!a.has_range) {
                for (auto& f : m.blocks.flags) f &= static_cast<std::uint8_t>(~kHidden);
                return;
            }
            for (int b : select_blocks(m, a.range)) m.blocks.flags[b] &= static_cast<std::uint8_t>(~kHidden);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
