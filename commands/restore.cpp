#include "commands.h"
#include "common.h"
#include "io/save.h"

namespace odec {

const CommandSpec& restore_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("restore", 4, "replace the model with one written by 'save'");
        c.positional.string("file");
        c.describe("Replaces the whole model (blocks, contacts, materials, histories, tables, settings, step "
                   "and time) with the one in the file; cycling on gives the same numbers, to the last bit, as "
                   "the run that saved it would have (a file of an older save format is brought up to this one as it "
                   "is read: it cycles on as it would have to within the last digits where the format changed "
                   "how a number is held, such as the shear of the sub-contacts, held since format 17 as two "
                   "components in the contact plane, or a contact's normal, held since format 18 to within "
                   "2e-9 rad, or the gap of an open sub-contact, held since format 19 by its blocks' last "
                   "refreshed geometry; a file older than format 19 also lacks the contacts' free motion, so "
                   "at its first steps odec looks at every contact's corners, and may refresh a contact "
                   "sooner than the run that saved it would have). The extension '.sav' is added when the "
                   "name has none; a "
                   "relative name is taken from the working directory. A file that is truncated, damaged (its "
                   "checksum does not match), not a save file at all, or written in a newer save format than "
                   "this odec reads is refused with the reason, and the current model is kept; so is one whose "
                   "numbers are not finite or out of range, or whose arrays disagree, however it was made. "
                   "Only a regular file is read: a directory, a named pipe or a device is refused without "
                   "waiting on it, and a file longer or shorter than its header says is refused before the "
                   "rest of it is read. FISH functions and variables are not part of a save file: they stay "
                   "as they are, so a FISH function may restore a model in a 'command' block and go on.");
        c.example("restore gravity");
        c.refuse_while_cycling("it would replace the model that is cycling");
        c.example("rest 'runs/settled.sav'");
        c.handle([](CommandContext& ctx, const Args& a) {
            const Value& file = a.positional[0];
            if (file.text.empty()) fail(file.loc, "'restore' needs a file name", {}, "restore");
            const std::string path = save_file_name(file.text);
            check_file_allowed(ctx, file.loc, path, "restore");
            std::string error;
            if (!restore_model(path, ctx.model, error)) fail(file.loc, error, {}, "restore");
            ctx.interp.last_solve.reset(); // they spoke of the model replaced
            ctx.interp.last_fos.reset();
            const Model& m = ctx.model;
            if (!ctx.interp.quiet) {
                ctx.out << "restored '" << path << "': " << m.blocks.size() << " blocks, " << m.contacts.size()
                        << " contacts, step " << m.step << ", time " << num(m.time) << " s\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
