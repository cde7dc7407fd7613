#include "commands.h"
#include "common.h"
#include "engine/blocks.h"

namespace odec {

const CommandSpec& delete_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("delete", 3, "remove blocks for good");
        c.range();
        c.describe("The blocks in the range go, with their contacts; their ids are not reused. To take "
                   "blocks out for a while (an excavation stage to refill later) use 'excavate'. "
                   "A clump (the blocks of a solid that is not convex, 'poly') goes whole when the range "
                   "selects any of its blocks: a rigid body does not lose a part.");
        c.example("delete range x 1.5 2.3 z 1.5 2.1");
        c.handle([](CommandContext& ctx, const Args& a) {
            if (!a.has_range) fail(a.loc, "'delete' needs a range (to delete everything, use 'new')", {}, "delete");
            std::vector<int> sel = select_blocks(ctx.model, a.range, true);
            take_whole_clumps(ctx, sel, "deleting");
            remove_blocks(ctx.model, sel);
            if (!ctx.interp.quiet) ctx.out << "deleted " << sel.size() << " blocks\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
