#include "commands.h"
#include "common.h"
#include "engine/blocks.h"

namespace odec {

const CommandSpec& poly_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("poly", 4, "create a rigid convex polyhedral block");
        c.keyword("brick", 2, "axis-aligned box from x1 to x2, y1 to y2, z1 to z2")
            .real("x1").real("x2").real("y1").real("y2").real("z1").real("z2")
            .in_choice(1);
        c.keyword("region", 3, "region number of the new block, for 'range region'").integer("n", 0).defaults("0");
        c.keyword("group", 2, "group name of the new block").word("name");
        c.keyword("material", 3, "material number of the new block").integer("n", 1, 1000000).defaults("1");
        c.require_one_of(1);
        c.describe("The block is rigid: it moves as a whole, with three translations and three rotations "
                   "about its centroid. Its mass and inertia come from its faces and the density of its "
                   "material ('prop mat=n dens=...').");
        c.example("poly brick 0 10 0 10 -5 0 region 1 group 'base'");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const KeywordUse* b = a.find("brick");
            const char* axes[3] = {"x", "y", "z"};
            for (int i = 0; i < 3; ++i) {
                const Value& lo = b->values[2 * i];
                const Value& hi = b->values[2 * i + 1];
                if (!(hi.number > lo.number)) {
                    fail(hi.loc, std::string("'brick' ") + axes[i] + "2 must be greater than " + axes[i] + "1 (got " +
                                     num(hi.number) + " after " + num(lo.number) + ")",
                         {}, "poly");
                }
            }
            const int region = a.has("region") ? a.integer("region") : 0;
            const int material = a.has("material") ? a.integer("material") : 1;
            const int group = a.has("group") ? m.group_index(a.text("group"), true) : -1;
            const Polyhedron p = make_brick(b->values[0].number, b->values[1].number, b->values[2].number,
                                            b->values[3].number, b->values[4].number, b->values[5].number);
            add_block(m, p, region, group, material);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
