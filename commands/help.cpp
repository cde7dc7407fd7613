#include "commands.h"
#include "common.h"
#include "fish/help.h"
#include "lang/help.h"

namespace odec {

const CommandSpec& help_command_spec() {
    static const CommandSpec spec = [] {
        CommandSpec c("help", 1, "show the commands, or the keywords of one command");
        c.positional.word("command").optional("the list of commands").word("keyword").optional("all keywords");
        c.example("help prop");
        c.example("help prop dens");
        c.handle([](CommandContext& ctx, const Args& a) {
            const CommandTable& table = ctx.interp.table;
            if (a.positional.empty()) {
                ctx.out << help_overview(table);
                return;
            }
            const Value& what = a.positional[0];
            std::string w = what.text;
            for (char& ch : w) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            if (w == "range") {
                ctx.out << help_range();
                return;
            }
            if (w == "fish") {
                if (a.positional.size() == 1) {
                    ctx.out << fish::help_overview();
                    return;
                }
                std::string k = a.positional[1].text;
                for (char& ch : k) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
                const std::string h = fish::help_intrinsic(k);
                if (h.empty()) fail(a.positional[1].loc, "'" + a.positional[1].text + "' is no FISH intrinsic", {"'help fish' lists them"});
                ctx.out << h;
                return;
            }
            std::vector<std::string> cand;
            const CommandSpec* c = table.match(w, &cand);
            if (!c && cand.empty()) {
                // `help c_nforce`: a FISH intrinsic named alone.
                const std::string h = fish::help_intrinsic(w);
                if (!h.empty()) {
                    ctx.out << h;
                    return;
                }
            }
            if (!c) {
                std::vector<std::string> all;
                for (const CommandSpec* s : table.commands) all.push_back(s->name);
                const auto near = closest_words(w, all);
                fail(what.loc, "no help for '" + what.text + "': it is not a command",
                     {near.empty() ? "type 'help' for the list of commands" : "did you mean '" + near[0] + "'?"});
            }
            if (a.positional.size() == 1) {
                ctx.out << help_command(*c);
                return;
            }
            const Value& kwv = a.positional[1];
            std::string k = kwv.text;
            for (char& ch : k) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            for (const KeywordSpec& ks : c->keywords) {
                if (abbreviates(k, ks.name, ks.min)) {
                    ctx.out << help_keyword(*c, ks);
                    return;
                }
            }
            std::vector<std::string> all;
            for (const KeywordSpec& ks : c->keywords) all.push_back(ks.name);
            fail(kwv.loc, "'" + c->name + "' has no keyword '" + kwv.text + "'",
                 {all.empty() ? "'" + c->name + "' takes no keywords" : "its keywords are: " + [&] {
                     std::string s;
                     for (size_t i = 0; i < all.size(); ++i) s += (i ? ", " : "") + all[i];
                     return s;
                 }()});
        });
        return c;
    }();
    return spec;
}

} // namespace odec
