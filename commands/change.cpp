#include "commands.h"
#include "common.h"
#include "engine/blocks.h"

namespace odec {

const CommandSpec& change_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("change", 4, "give blocks another material");
        c.keyword("material", 3, "block material number").integer("n", 1, 1000000);
        c.range();
        c.describe("Blocks in the range (every block when no range is given) take the material; their "
                   "mass and inertia follow its density.");
        c.example("change mat=2 range z -10 0");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (!a.has("material")) fail(a.loc, "'change' needs 'mat=n'", {}, "change");
            const int n = a.integer("material");
            for (int b : blocks_in_range(ctx, a)) m.blocks.material[b] = n;
            update_masses(m);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
