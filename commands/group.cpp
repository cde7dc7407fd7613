#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& group_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("group", 3, "give blocks a group name");
        c.positional.word("name");
        c.range();
        c.describe("A block belongs to one group at a time; 'range group name' selects it later.");
        c.example("group 'lining' range cylinder 0,-10,0 0,10,0 4");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const std::vector<int> sel = select_blocks(m, a.range, true);
            const int g = m.group_index(a.positional[0].text, true);
            for (int b : sel) m.blocks.group[b] = g;
            if (!ctx.interp.quiet) ctx.out << sel.size() << " blocks in group " << a.positional[0].text << "\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
