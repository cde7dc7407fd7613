#include "commands.h"
#include "common.h"

namespace odec {

const CommandSpec& call_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("call", 3, "run the commands of a data file");
        c.positional.string("file");
        c.describe("A relative path is taken from the directory of the file that calls it (from the "
                   "working directory at the prompt). Calls nest, at most 64 files deep; a file may not call "
                   "itself, directly or through others. Only a regular file of at most 64 MiB is run (not a "
                   "directory, device or pipe). The first error stops every file being run.");
        c.example("call 'geometry.dat'");
        c.handle([](CommandContext& ctx, const Args& a) {
            const std::string path = relative_to_script(a.loc, a.positional[0].text);
            check_file_allowed(ctx, a.positional[0].loc, path, "call");
            if (!ctx.interp.run_file(path, &a.positional[0].loc)) throw ScriptFailed{};
        });
        return c;
    }();
    return spec;
}

} // namespace odec
