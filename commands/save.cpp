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
                   "under a temporary name beside it (name.tmp-PID-N) and renamed into place once complete, so "
                   "a save that fails leaves an existing file as it was; temporary files that a save killed "
                   "part way left in the same directory are removed, with a note. The model is checked as "
                   "'restore' checks a file, and a model that 'restore' would refuse is not saved (nothing "
                   "is written): one whose velocities or forces are no longer finite numbers after a run-away, "
                   "for example. An existing file is not replaced when it is read-only (no write permission "
                   "bit) or is not a regular file (a directory, a named pipe, a device).");
        c.example("save gravity");
        c.example("save 'runs/settled.sav'");
        c.handle([](CommandContext& ctx, const Args& a) {
            const Value& file = a.positional[0];
            if (file.text.empty()) fail(file.loc, "'save' needs a file name", {}, "save");
            const std::string path = save_file_name(file.text);
            check_file_allowed(ctx, file.loc, path, "save");
            const size_t slash = path.find_last_of('/');
            const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
            const std::string note = stale_temporaries_note(remove_stale_save_temporaries(dir));
            if (!note.empty()) ctx.interp.err << "note: " << note << "\n";
            std::string error;
            if (!save_model(ctx.model, path, error)) fail(file.loc, error, {}, "save");
            if (!ctx.interp.quiet) ctx.out << "saved the model at step " << ctx.model.step << " to '" << path << "'\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
