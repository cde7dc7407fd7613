#include "commands.h"
#include "common.h"
#include "fish/intrinsics.h"
#include "fish/runtime.h"

namespace odec {

const CommandSpec& list_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("list", 3, "print FISH variables: their names and values");
        c.positional.word("name").optional("every FISH variable").repeat();
        c.describe("Each name (written with or without '@') is printed with its value; a function is "
                   "run first and its value printed. In a function's 'command ... endcommand' block, a name "
                   "is first the function's argument or local. Without names, every FISH variable and "
                   "function is listed with its current value (functions are not run).");
        c.example("list @sf_sum2");
        c.handle([](CommandContext& ctx, const Args& a) {
            fish::Runtime& rt = ctx.interp.fish();
            if (a.positional.empty()) {
                for (const std::string& n : rt.names()) {
                    std::string lower = n;
                    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
                    const fish::Symbol* s = rt.find(lower);
                    ctx.out << n << " = ";
                    if (s->array) ctx.out << "array of " << s->array->items.size() << "\n";
                    else ctx.out << fish::to_text(s->value) << (s->fn ? "  (function)" : "") << "\n";
                }
                return;
            }
            // Check every name before printing any.
            std::vector<std::string> names;
            for (const Value& v : a.positional) {
                std::string n = v.text;
                if (!n.empty() && n[0] == '@') n.erase(0, 1);
                std::string lower = n;
                for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
                if (!rt.command_local(lower) && !rt.is_symbol(lower) && !fish::find_intrinsic(lower)) {
                    fail(v.loc, "'" + n + "' is no FISH variable or function", {"'list' alone lists them"}, "list");
                }
                names.push_back(n);
            }
            for (size_t k = 0; k < names.size(); ++k) {
                const fish::Value val = rt.value_for_command(names[k], a.positional[k].loc);
                ctx.out << names[k] << " = " << fish::to_text(val) << "\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
