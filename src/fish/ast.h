// The compiled form of FISH: a tree of nodes, built once by `def`, evaluated directly. Names are
// resolved when the function is compiled (locals to a slot, globals to their Symbol, intrinsics
// to their declaration), so a call does no lookup by name.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "fish/intrinsics.h"
#include "fish/runtime.h"
#include "fish/value.h"

namespace odec::fish {

struct Frame {
    Runtime& rt;
    const Function* fn;
    Value* locals;
};

struct Expr {
    SourceLoc loc;
    virtual ~Expr() = default;
    virtual Value eval(Frame& f) const = 0;
    // `target = value`; the default says the target cannot be assigned.
    virtual void assign(Frame& f, Value v) const;
    virtual std::string describe() const { return "this expression"; }
};
using ExprP = std::unique_ptr<Expr>;

enum class Flow { Next, ExitFunction, ExitSection, ExitLoop, ContinueLoop };

struct Stmt {
    SourceLoc loc;
    virtual ~Stmt() = default;
    virtual Flow exec(Frame& f) const = 0;
};
using StmtP = std::unique_ptr<Stmt>;
using Block = std::vector<StmtP>;

struct Function {
    std::string name;
    Symbol* self = nullptr;
    int n_params = 0;
    int n_locals = 0;               // parameters first
    std::vector<std::string> local_names;
    Block body;
    bool whilestepping = false;
    SourceLoc loc;                  // the `def` line
    // `array` statements are declarations, sized when the function is defined (as in the
    // classic dialect): these arrays are given to their names once the definition succeeds.
    std::vector<std::pair<Symbol*, std::shared_ptr<Array>>> arrays;
};

// Run a block; the flow that left it.
Flow run_block(const Block& b, Frame& f);
// Call a user function with argument values.
Value call_function(Runtime& rt, Symbol& s, std::vector<Value>& args, const SourceLoc& at);

// Operators, shared with constant folding and the tests.
Value binary(const std::string& op, const Value& a, const Value& b, const SourceLoc& loc);
bool truth(const Value& v, const SourceLoc& loc);
bool equal(const Value& a, const Value& b);

} // namespace odec::fish
