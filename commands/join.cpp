#include "commands.h"
#include "common.h"
#include "engine/contact.h"
#include "engine/blocks.h"

namespace odec {

const CommandSpec& join_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("join", 4, "glue blocks together: their contacts neither slip nor open");
        c.range();
        c.describe("Contacts between two blocks of the range are glued. Contacts are found first when "
                   "the model has not been cycled yet.");
        c.example("join range z 0 10");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const std::vector<int> sel = select_blocks(m, a.range);
            // Find the contacts now, even before the model can cycle (no timestep, no mass yet).
            refresh_world_vertices(m);
            detect_contacts(m);
            const int n = join_blocks(m, sel);
            if (!ctx.interp.quiet) ctx.out << "joined " << n << " contacts between " << sel.size() << " blocks\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
