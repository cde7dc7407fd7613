// The FISH runtime: global symbols (variables, functions, arrays), definitions compiled once to a
// tree of nodes, and their execution with a call stack for error messages.
//
// FISH speaks to the rest of odec through a Host (the command interpreter): the model it reads
// and writes, the commands of `command ... endcommand`, the output of `out()`, Ctrl-C.
#pragma once

#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "fish/lexer.h"
#include "fish/value.h"
#include "lang/source.h"

namespace odec {
struct Model;
}

namespace odec::fish {

struct Function;
struct Frame;
class Runtime;

// What FISH needs from the program around it.
class Host {
public:
    virtual ~Host() = default;
    virtual Model& model() = 0;
    // Run the commands on lines first_line..last_line (1-based) of file: the inside of a
    // `command ... endcommand` block. Their `@name` words take the values FISH has then.
    // False when one failed (the error is reported); the FISH function then stops.
    virtual bool run_commands(const std::shared_ptr<const SourceFile>& file, int first_line, int last_line) = 0;
    virtual std::ostream& out() = 0;
    virtual std::ostream& err() = 0;
    // Ctrl-C was pressed: a running function stops at its next statement.
    virtual bool interrupted() = 0;
    // Files FISH opens must stay in the working directory (fuzzing sessions).
    virtual bool confine_files() = 0;
    // How the last `solve` ended, in a word (equilibrium, mechanism, not converged,
    // interrupted), or "" before any.
    virtual std::string solve_verdict() { return ""; }
    // The factor of safety the last `solve fos` found, or 0 (none yet, or not found).
    virtual double fos_factor() { return 0; }
};

// A global name: a variable, a function (whose value is what it assigns to its own name), or
// an array. Symbols live as long as the runtime, so compiled code points at them directly.
struct Symbol {
    std::string name;                 // as first written
    Value value;                      // 0 until assigned
    std::shared_ptr<Function> fn;     // set by `def name`
    std::shared_ptr<Array> array;     // set by `array name(n)`
    // A script assigns to this name although an intrinsic has it: from then on the name is the
    // script's variable (scripts written for older versions use such names freely).
    bool shadows_intrinsic = false;
    bool assigned = false;            // given a value by a script (not only named)
};

// A FISH error: where, what, and the chain of calls it happened in.
struct FishError {
    Diagnostic diag;
};
[[noreturn]] void fish_fail(const SourceLoc& loc, std::string what, std::vector<std::string> notes = {});

class Runtime {
public:
    explicit Runtime(Host& host);
    ~Runtime();

    // Compile `def name[(args)]` (header) with the lines of its body (up to, not including,
    // `end`). Throws CommandError; a definition that fails leaves the earlier one in place.
    void define(const Line& header, const std::vector<Line>& body);

    // Run one statement typed outside a definition: `@f`, `@f(1,2)`, `@x = 3`, `f` (UDEC).
    // Throws CommandError (with the call chain in its notes).
    void run_statement(const Line& line);

    // The value for a command word `@name`: in the commands of a function's `command ...
    // endcommand` block (and the files they call), the function's argument or local of that
    // name; else the global's (a function is called first). Throws CommandError when name is no
    // FISH symbol.
    Value value_for_command(const std::string& name, const SourceLoc& loc);
    // The argument or local `lower_name` of the function whose command block runs now (the
    // innermost), or null when there is none of that name.
    const Value* command_local(const std::string& lower_name) const;
    // The name of that function ("" when no command block runs).
    std::string command_function() const;
    // The frames of the functions whose command blocks are running, innermost last.
    std::vector<Frame*> command_frames;

    // Whether `name` (lower case) is a defined function / a symbol with a value or a function.
    bool is_function(const std::string& lower_name) const;
    bool is_symbol(const std::string& lower_name) const;
    // Names of functions and variables, for completion and `list`.
    std::vector<std::string> names() const;
    const Symbol* find(const std::string& lower_name) const;
    Symbol& symbol(const std::string& name); // created as a variable of value 0 when new

    // `whilestepping` functions, in the order defined: run at the start of every step.
    std::vector<Symbol*> stepping() const;
    // Call a function with no arguments from outside FISH (histories, whilestepping).
    Value call(Symbol& s, const SourceLoc& loc);

    // Forget every symbol (`new`).
    void clear();
    // Forget what FISH keeps of the model (per-object values, walks): `new` inside a running
    // function, which keeps the functions and variables.
    void forget_model();

    Host& host;
    // Per-object values that scripts store (`c_extra(c) = v`), by object id.
    std::unordered_map<long long, Value> extras[5];
    // The file of open()/write()/read()/close(): one at a time, as in the classic dialect.
    std::FILE* file = nullptr;
    bool file_writing = false;
    std::string file_name; // as open() was given it, for messages
    // Lists of gridpoints and zones of each block, for b_gp/gp_next and b_zone/z_next: built
    // when first asked, forgotten whenever the model may have changed.
    const std::vector<std::vector<int>>& block_gridpoints();
    const std::vector<std::vector<int>>& block_zones();
    void model_changed();
    // urand and grand: the same sequence in every session, from its start and after `new`.
    std::mt19937_64 random{1};
    // Loop iterations and calls FISH may still run (the fuzzing sessions' bound); null or < 0:
    // no limit.
    long long* budget = nullptr;
    // A loop iteration or a call: stops at Ctrl-C and at the end of the budget.
    void tick(const SourceLoc& loc);
    // Work that counts as `steps` loop iterations against the budget (none without one): stops
    // at Ctrl-C and where the budget runs out, as that many ticks would.
    void spend(long long steps, const SourceLoc& loc);
    // Longest string FISH builds, in characters (no string is ever longer than kMaxString).
    static constexpr size_t kMaxString = size_t{1} << 20;
    size_t max_string = kMaxString;
    // Elements of all arrays together.
    size_t max_array_items = 10000000;
    size_t array_items() const;
    // How deep FISH calls may nest (each takes C++ stack).
    static constexpr int kMaxDepth = 100;
    // Where FISH is running now (for messages): innermost call last.
    struct Call {
        const Function* fn;
        SourceLoc at;
    };
    std::vector<Call> calls;

private:
    std::unordered_map<std::string, std::unique_ptr<Symbol>> symbols_;
    std::vector<std::string> order_; // definition order of functions, for whilestepping
    std::vector<std::vector<int>> block_gps_, block_zones_;
    bool gps_ready_ = false, zones_ready_ = false;
};

} // namespace odec::fish
