#include "commands.h"
#include "common.h"
#include "io/save.h"

namespace odec {

const CommandSpec& save_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("save", 4, "write the whole model state to a file, for 'restore'");
        c.positional.string("file");
        c.describe("Writes everything the model holds: blocks, contacts with their joint history, materials, "
                   "joint sets, groups, histories, tables, gravity, damping and settings, step and time. "
                   "'restore' brings it back exactly: cycling on from the restored model gives the same "
                   "numbers, to the last bit, as never having saved. The extension '.sav' is added when the "
                   "name has none; a relative name is taken from the working directory. The file is written "
                   "under a temporary name beside it and renamed into place once complete, so a save that "
                   "fails leaves an existing file as it was.");
        c.example("save gravity");
        c.example("save 'runs/settled.sav'");
        c.handle([](CommandContext& ctx, const Args& a) {
            const Value& file = a.positional[0];
            if (file.text.empty()) fail(file.loc, "'save' needs a file name", {}, "save");
            const std::string path = save_file_name(file.text);
            check_file_allowed(ctx, file.loc, path, "save");
            std::string error;
            if (!save_model(ctx.model, path, error)) fail(file.loc, error, {}, "save");
            if (!ctx.interp.quiet) ctx.out << "saved the model at step " << ctx.model.step << " to '" << path << "'\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
