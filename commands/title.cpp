#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& title_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("title", 3, "set the model title shown on pictures and printouts");
        c.positional.string("text").optional("empty");
        c.example("title 'Block on an incline'");
        c.handle([](CommandContext& ctx, const Args& a) {
            ctx.model.title = a.positional.empty() ? "" : a.positional[0].text;
        });
        return c;
    }();
    return spec;
}

} // namespace odec
