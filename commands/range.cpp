#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& range_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("range", 3, "give a range phrase a name, for 'nrange' in later commands");
        c.keyword("name", 2, "the name").word("name");
        c.range("the filters the name stands for (the word 'range' may be left out)");
        c.describe("Named ranges belong to the session: 'new' keeps them. 'nrange a b' in a range phrase "
                   "means in a and in b; 'union nrange a b' means in a or in b. A name given again is "
                   "redefined.");
        c.example("range name podium region 1");
        c.example("range name columns union nrange col_base col_shaft col_capital");
        c.example("change mat=2 range nrange columns");
        c.handle([](CommandContext& ctx, const Args& a) {
            if (!a.has("name")) fail(a.loc, "'range' needs 'name' and the filters it stands for", {}, "range");
            if (!a.has_range) fail(a.find("name")->loc, "'range name' needs the filters it stands for", {}, "range");
            std::string key = a.text("name");
            for (char& ch : key) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            ctx.interp.named_ranges[key] = a.range;
        });
        return c;
    }();
    return spec;
}

} // namespace odec
