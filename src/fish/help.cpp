#include "fish/help.h"

#include <cstring>

#include "fish/intrinsics.h"

namespace odec::fish {

namespace {

const char* kStatements =
    "def name [(a, b, ...)] ... end   a function (also 'define'); its value is what it assigns to its own name\n"
    "local x [= value]                a variable of this call only (arguments are local too)\n"
    "x = value, a(i, j) = value       assignment (names are global unless local)\n"
    "if cond [then] ... [else [if ...]] ... endif\n"
    "loop i (from, to) ... endloop    i = from, from+1, ..., to\n"
    "loop while cond ... endloop      (exit loop leaves it)\n"
    "section ... exit section ... endsection\n"
    "caseof n ... case 1 ... case 2, 3 ... endcase\n"
    "array a(n [, m [, k]])           sized when the function is defined, from numbers or globals\n"
    "command ... endcommand           run commands; @name in them takes FISH values (the function's\n"
    "                                 arguments and locals first, then globals)\n"
    "exit, return                     leave the function\n"
    "whilestepping                    (a line of the function) run it at every step\n"
    "operators: ^ (power), * /, + -, = # < > <= >= (# and != are 'not equal'), & (and), | (or), not\n"
    "integer op integer stays an integer (7/2 = 3); a float makes a float\n"
    "set name = value ...             (a command) give FISH variables values from outside a function\n"
    "$KCFN, imem(i), fmem(i)          memory offsets of the classic codes: stop with the intrinsic to use\n";

std::string line_of(const Intrinsic& in) {
    std::string head = std::string(in.name) + (in.max_args == 0 ? std::string() : "(" + std::string(in.args) + ")");
    if (in.set) head += " [assignable]";
    std::string pad = head.size() < 28 ? std::string(28 - head.size(), ' ') : std::string(" ");
    return "  " + head + pad + in.help + "\n";
}

} // namespace

std::string help_overview() {
    std::string s = "FISH, the classic dialect of 3DEC and UDEC. Statements:\n\n";
    s += kStatements;
    s += "\nIntrinsics (help fish <name> for one):\n";
    const char* group = "";
    for (const Intrinsic* in : all_intrinsics()) {
        if (std::strcmp(in->group, group) != 0) {
            group = in->group;
            s += std::string("\n ") + group + ":\n";
        }
        s += line_of(*in);
    }
    return s;
}

std::string help_intrinsic(const std::string& lower_name) {
    const Intrinsic* in = find_intrinsic(lower_name);
    if (!in) return "";
    return line_of(*in);
}

std::string manual_page() {
    std::string s = "# FISH\n\n"
                    "FISH is the scripting language of 3DEC and UDEC; odec runs its classic dialect. A "
                    "function is defined by `def name ... end`, compiled once when defined, and run by "
                    "`@name` (or `@name(1, 2)`) as a command, by its name alone, or from other functions. "
                    "`@name` in any command takes the value of a FISH variable or function; `hist @name` (or "
                    "`hist name`) records it as the model cycles (a function that fails there, or gives no finite "
                    "number, stops the `step` or `solve` with the reason); `list @name` prints it. Errors point at the line and "
                    "column inside the function and give the chain of calls. Units are SI; zone stresses "
                    "are tension positive, contact stresses and forces compression positive, as everywhere "
                    "in odec. Pointers to blocks, contacts, gridpoints and zones hold while the model does "
                    "not change; a pointer into a changed model is refused with a message.\n\n"
                    "## Statements\n\n```\n";
    s += kStatements;
    s += "```\n\n## Example\n\n```\n"
         "def weight_on_base\n"
         "  local c = contact_head\n"
         "  weight_on_base = 0.0\n"
         "  loop while c # 0\n"
         "    if b_region(c_b1(c)) = 1 | b_region(c_b2(c)) = 1\n"
         "      weight_on_base = weight_on_base + c_nforce(c)\n"
         "    endif\n"
         "    c = c_next(c)\n"
         "  endloop\n"
         "end\n"
         "hist @weight_on_base\n"
         "```\n\n## Commands from FISH\n\n"
         "Any command may run in a `command ... endcommand` block, or in a file such a block `call`s, and "
         "does there what it does at the prompt, with two exceptions. `new` in a running function "
         "clears the model but keeps the FISH functions, variables and arrays, the file FISH has open "
         "and the urand/grand sequence, so that a parametric study can loop over cases that each start "
         "with `new` (3DEC refuses `new` and `restore` inside FISH); `restore` keeps FISH as it is, "
         "since save files hold no FISH. While the model cycles (a `whilestepping` function, or a FISH "
         "history sampled during `step` or `solve`), the commands that would replace the model or "
         "cycle it again are refused with a located error: `new`, `restore`, `step`, `solve` and "
         "`quit` (`help` of each says why); a command that changes the blocks there (`jset`, `poly`, "
         "`gen`, `delete`, ...) is taken up by the cycle at once: contacts, masses and timestep follow "
         "before the next stage, and energy a function gives the blocks is allowed for by the "
         "run-away check. A pointer taken before such a change is refused when used.\n\n"
         "`@name` in the commands of a `command ... endcommand` block (and of a file they `call`) "
         "takes the value `name` has in the function's body: its argument or local of that name "
         "first, else the global variable or function. A history records a global as the model "
         "cycles, after the function has returned: `hist @name` with a local is refused.\n\n"
         "## Intrinsics\n";
    const char* group = "";
    for (const Intrinsic* in : all_intrinsics()) {
        if (std::strcmp(in->group, group) != 0) {
            group = in->group;
            s += std::string("\n### ") + group + "\n\n| intrinsic | gives |\n|---|---|\n";
        }
        std::string head = std::string("`") + in->name + (in->max_args == 0 ? std::string() : "(" + std::string(in->args) + ")") + "`";
        std::string help = in->help;
        for (char& ch : help) if (ch == '|') ch = '/';
        s += "| " + head + (in->set ? " (assignable)" : "") + " | " + help + " |\n";
    }
    return s;
}

} // namespace odec::fish
