// From FISH lines to the tree of nodes (ast.h): expressions by precedence, statements by their
// first word, blocks by their closing words.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "fish/ast.h"

namespace odec::fish {

void Expr::assign(Frame&, Value) const {
    fish_fail(loc, "cannot assign to " + describe(),
              {"a variable, an array element or a writable intrinsic (such as c_extra(c)) can be assigned"});
}

namespace {

// ---------------------------------------------------------------------------------------------
// Expression nodes

struct Const final : Expr {
    Value v;
    Value eval(Frame&) const override { return v; }
    std::string describe() const override { return "a constant"; }
};

// `$KCFN`: a classic memory offset, read by imem()/fmem(). odec keeps no such memory, so the
// offset stops the function with what to write instead.
struct MemoryOffset final : Expr {
    std::string name;
    Value eval(Frame&) const override {
        static const std::map<std::string, std::string> instead = {
            {"$kcfn", "c_nforce(c)"}, {"$kcfs", "c_sforce(c)"}, {"$kcnx", "c_nx(c)"}, {"$kcny", "c_ny(c)"},
            {"$kcnz", "c_nz(c)"},     {"$kxc", "c_x(c)"},       {"$kyc", "c_y(c)"},   {"$kzc", "c_z(c)"},
            {"$kcl", "c_area(c) (a 3D contact has an area, not a length)"},
            {"$kb1", "c_b1(c)"},      {"$kb2", "c_b2(c)"},      {"$kbx", "b_x(b)"},   {"$kby", "b_y(b)"},
            {"$kbz", "b_z(b)"},       {"$kbvol", "b_vol(b)"},   {"$kbmass", "b_mass(b)"},
            {"$kp", "b_gp(b)/gp_next(g) for the gridpoints of a deformable block (3D blocks have no corner "
                    "list)"},
            {"$kr", "b_gp(b)/gp_next(g) for the gridpoints of a deformable block (3D blocks have no corner "
                    "list)"},
            {"$kdx", "c_x(c) (odec has no flow domains; a contact's centroid is the nearest thing)"},
            {"$kd1", "c_b1(c) (odec has no flow domains)"},
            {"$kd2", "c_b2(c) (odec has no flow domains)"},
            {"$kc1a", "cx_next(c)/cx_pos(x) for the sub-contacts of a contact (odec has no corners)"},
            {"$kc2a", "cx_next(c)/cx_pos(x) for the sub-contacts of a contact (odec has no corners)"},
        };
        std::string l = name;
        for (char& c : l) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        std::vector<std::string> notes;
        auto it = instead.find(l);
        if (it != instead.end()) {
            notes.push_back("for " + name + " write " + it->second);
        } else if (l == "$kcap") {
            notes.push_back("for " + name + " (a contact's hydraulic aperture) write fl_aperture(c_x(c), c_y(c), c_z(c)): "
                            "the aperture of the flow node nearest the contact's centroid, m");
        } else if (l == "$kcq") {
            notes.push_back("odec keeps no flow rate per contact: fl_flow is what the fixed-pressure boundaries feed "
                            "into the joints, m^3/s ('hist flowrate' records it), fl_pp(x,y,z) a node's pressure");
        } else {
            notes.push_back("read the quantity through its intrinsic: 'help fish' lists them");
        }
        fish_fail(loc, "'" + name + "' is a memory offset of the classic codes: odec has no memory offsets", notes);
    }
    std::string describe() const override { return "a memory offset"; }
};

struct LocalRef final : Expr {
    int slot = 0;
    std::string name;
    Value eval(Frame& f) const override { return f.locals[slot]; }
    void assign(Frame& f, Value v) const override { f.locals[slot] = std::move(v); }
    std::string describe() const override { return "'" + name + "'"; }
};

// An argument or local of the function whose command block runs a statement typed there
// (`@f(n)`, `@x = n + 1`): the statement is compiled and run while that function's frame lives.
struct OuterLocalRef final : Expr {
    Frame* frame = nullptr;
    int slot = 0;
    std::string name;
    Value eval(Frame&) const override { return frame->locals[slot]; }
    void assign(Frame&, Value v) const override { frame->locals[slot] = std::move(v); }
    std::string describe() const override { return "'" + name + "'"; }
};

// A global name without arguments: a variable's value, a function's result (called unless it
// is the function running now, which reads its own value), or a whole array.
struct GlobalRef final : Expr {
    Symbol* sym = nullptr;
    Value eval(Frame& f) const override {
        if (sym->fn && sym->fn.get() != f.fn) {
            std::vector<Value> none;
            return call_function(f.rt, *sym, none, loc);
        }
        if (sym->array) {
            Value r;
            r.type = Type::Array;
            r.a = sym->array;
            return r;
        }
        return sym->value;
    }
    void assign(Frame&, Value v) const override {
        if (sym->array) fish_fail(loc, "'" + sym->name + "' is an array: assign to one of its elements, as " + sym->name + "(1)");
        sym->value = std::move(v);
        sym->assigned = true;
    }
    std::string describe() const override { return "'" + sym->name + "'"; }
};

// name(args): an array element or a call of a user function, decided when it runs (a name
// may become an array or a function after this function was compiled).
struct GlobalCall final : Expr {
    Symbol* sym = nullptr;
    std::vector<ExprP> args;

    Value* element(Frame& f) const {
        Array& a = *sym->array;
        if (args.size() != a.dims.size()) {
            fish_fail(loc, "array '" + sym->name + "' has " + std::to_string(a.dims.size()) + " dimension" +
                               (a.dims.size() == 1 ? "" : "s") + ", given " + std::to_string(args.size()) + " index" +
                               (args.size() == 1 ? "" : "es"));
        }
        size_t flat = 0;
        for (size_t k = 0; k < args.size(); ++k) {
            const Value i = args[k]->eval(f);
            if (i.type != Type::Int && !(i.type == Type::Float && i.f == std::floor(i.f) && std::isfinite(i.f))) {
                fish_fail(args[k]->loc, "an array index must be a whole number (got " + to_text(i) + ")");
            }
            const long long ix = i.type == Type::Int ? i.i : static_cast<long long>(i.f);
            if (ix < 1 || ix > a.dims[k]) {
                fish_fail(args[k]->loc, "index " + std::to_string(ix) + " is outside array '" + sym->name + "' (1 to " +
                                            std::to_string(a.dims[k]) + ")");
            }
            flat = flat * static_cast<size_t>(a.dims[k]) + static_cast<size_t>(ix - 1);
        }
        return &a.items[flat];
    }
    Value eval(Frame& f) const override {
        if (sym->array) return *element(f);
        if (sym->fn) {
            std::vector<Value> vals;
            vals.reserve(args.size());
            for (const auto& e : args) vals.push_back(e->eval(f));
            return call_function(f.rt, *sym, vals, loc);
        }
        fish_fail(loc, "'" + sym->name + "' is neither a function nor an array",
                  {"define it with 'def " + sym->name + "' or 'array " + sym->name + "(n)' before this runs"});
    }
    void assign(Frame& f, Value v) const override {
        if (!sym->array) fish_fail(loc, "'" + sym->name + "' is not an array", {"declare it first: array " + sym->name + "(n)"});
        *element(f) = std::move(v);
    }
    std::string describe() const override { return "'" + sym->name + "(...)'"; }
};

struct IntrinsicCall final : Expr {
    const Intrinsic* in = nullptr;
    std::vector<ExprP> args;
    Value eval(Frame& f) const override {
        Value vals[8];
        const int n = static_cast<int>(args.size());
        for (int k = 0; k < n; ++k) vals[k] = args[k]->eval(f);
        return in->get(f.rt, vals, n, loc);
    }
    void assign(Frame& f, Value v) const override {
        if (!in->set) fish_fail(loc, std::string("'") + in->name + "' can be read, not assigned");
        Value vals[8];
        const int n = static_cast<int>(args.size());
        for (int k = 0; k < n; ++k) vals[k] = args[k]->eval(f);
        in->set(f.rt, vals, n, v, loc);
    }
    std::string describe() const override { return std::string("'") + in->name + "'"; }
};

struct VectorLit final : Expr {
    ExprP x, y, z;
    Value eval(Frame& f) const override {
        const Value a = x->eval(f), b = y->eval(f), c = z->eval(f);
        if (!a.is_number() || !b.is_number() || !c.is_number()) fish_fail(loc, "a vector (x,y,z) takes three numbers");
        return Value::vector({a.number(), b.number(), c.number()});
    }
};

struct Unary final : Expr {
    char op = '-';
    ExprP e;
    Value eval(Frame& f) const override {
        const Value v = e->eval(f);
        if (op == '!') return Value::boolean(!truth(v, loc));
        switch (v.type) {
        case Type::Int:
            if (v.i == INT64_MIN) return Value::real(-static_cast<double>(v.i));
            return Value::integer(-v.i);
        case Type::Float: return Value::real(-v.f);
        case Type::Vector: return Value::vector(-v.v);
        default: fish_fail(loc, std::string("cannot negate ") + type_name(v));
        }
    }
};

struct Binary final : Expr {
    std::string op;
    char code = 0; // the operator as one character, for the fast path of two floats or integers
    ExprP a, b;
    Value eval(Frame& f) const override {
        Value x = a->eval(f);
        const Value y = b->eval(f);
        // Most arithmetic is on floats: done here, without the general dispatch.
        if (x.type == Type::Float && (y.type == Type::Float || y.type == Type::Int)) {
            const double q = y.type == Type::Float ? y.f : static_cast<double>(y.i);
            switch (code) {
            case '+': x.f += q; return x;
            case '-': x.f -= q; return x;
            case '*': x.f *= q; return x;
            case '/':
                if (q == 0) break;
                x.f /= q;
                return x;
            default: break;
            }
        } else if (x.type == Type::Int && y.type == Type::Float) {
            const double p = static_cast<double>(x.i);
            switch (code) {
            case '+': return Value::real(p + y.f);
            case '-': return Value::real(p - y.f);
            case '*': return Value::real(p * y.f);
            default: break;
            }
        }
        Value r = binary(op, x, y, loc);
        if (r.type == Type::String && r.s.size() > f.rt.max_string) {
            fish_fail(loc, "a string of more than " + std::to_string(f.rt.max_string) + " characters");
        }
        return r;
    }
};

// `a & b`, `a | b`: the right side runs only when it decides.
struct Logic final : Expr {
    bool is_and = true;
    ExprP a, b;
    Value eval(Frame& f) const override {
        const bool x = truth(a->eval(f), a->loc);
        if (is_and ? !x : x) return Value::boolean(x);
        return Value::boolean(truth(b->eval(f), b->loc));
    }
};

// ---------------------------------------------------------------------------------------------
// Statement nodes

struct Assign final : Stmt {
    ExprP target, value;
    Flow exec(Frame& f) const override {
        target->assign(f, value->eval(f));
        return Flow::Next;
    }
};

struct Evaluate final : Stmt {
    ExprP e;
    Flow exec(Frame& f) const override {
        e->eval(f);
        return Flow::Next;
    }
};

struct If final : Stmt {
    ExprP cond;
    Block then_b, else_b;
    Flow exec(Frame& f) const override {
        return run_block(truth(cond->eval(f), cond->loc) ? then_b : else_b, f);
    }
};

// Each loop iteration: Ctrl-C, and the session's bound on FISH work.
void tick(Frame& f, const SourceLoc& loc) { f.rt.tick(loc); }

struct LoopWhile final : Stmt {
    ExprP cond;
    Block body;
    Flow exec(Frame& f) const override {
        while (truth(cond->eval(f), cond->loc)) {
            tick(f, loc);
            const Flow fl = run_block(body, f);
            if (fl == Flow::ExitLoop) break;
            if (fl == Flow::ExitFunction || fl == Flow::ExitSection) return fl;
        }
        return Flow::Next;
    }
};

struct LoopRange final : Stmt {
    ExprP var, from, to;
    Block body;
    Flow exec(Frame& f) const override {
        const Value a = from->eval(f), b = to->eval(f);
        if (!a.is_number() || !b.is_number()) fish_fail(from->loc, "a loop runs between two numbers");
        if (a.type == Type::Int && b.type == Type::Int) {
            for (long long i = a.i; i <= b.i; ++i) {
                tick(f, loc);
                var->assign(f, Value::integer(i));
                const Flow fl = run_block(body, f);
                if (fl == Flow::ExitLoop) break;
                if (fl == Flow::ExitFunction || fl == Flow::ExitSection) return fl;
                if (i == b.i) break; // ++i would overflow at the largest integer
            }
        } else {
            const double lo = a.number(), hi = b.number();
            if (!std::isfinite(lo) || !std::isfinite(hi)) fish_fail(from->loc, "a loop's bounds must be finite");
            // Beyond 2^53 adding 1 changes nothing: the loop would never end.
            if (std::fabs(lo) > 9e15 || std::fabs(hi) > 9e15) fish_fail(from->loc, "a loop's bounds must lie within +/-9e15");
            for (double x = lo; x <= hi; x += 1) {
                tick(f, loc);
                var->assign(f, Value::real(x));
                const Flow fl = run_block(body, f);
                if (fl == Flow::ExitLoop) break;
                if (fl == Flow::ExitFunction || fl == Flow::ExitSection) return fl;
            }
        }
        return Flow::Next;
    }
};

struct Section final : Stmt {
    Block body;
    Flow exec(Frame& f) const override {
        const Flow fl = run_block(body, f);
        return fl == Flow::ExitSection ? Flow::Next : fl;
    }
};

struct Jump final : Stmt {
    Flow flow = Flow::ExitFunction;
    Flow exec(Frame&) const override { return flow; }
};

struct CaseOf final : Stmt {
    ExprP selector;
    std::vector<std::pair<std::vector<long long>, Block>> cases;
    Block otherwise; // lines before the first `case`
    Flow exec(Frame& f) const override {
        const Value v = selector->eval(f);
        if (v.type != Type::Int) fish_fail(selector->loc, std::string("caseof needs a whole number, not ") + type_name(v));
        for (const auto& c : cases) {
            if (std::find(c.first.begin(), c.first.end(), v.i) != c.first.end()) return run_block(c.second, f);
        }
        return run_block(otherwise, f);
    }
};

struct Command final : Stmt {
    std::shared_ptr<const SourceFile> file;
    int first = 0, last = 0; // lines of the commands
    Flow exec(Frame& f) const override {
        if (first > last) return Flow::Next;
        f.rt.model_changed();
        // `@name` in the commands takes this function's arguments and locals first.
        struct Scope {
            Runtime& rt;
            Scope(Runtime& r, Frame& fr) : rt(r) { rt.command_frames.push_back(&fr); }
            ~Scope() { rt.command_frames.pop_back(); }
        } scope(f.rt, f);
        const bool ok = f.rt.host.run_commands(file, first, last);
        f.rt.model_changed();
        if (!ok) fish_fail(loc, "a command of this 'command' block failed (its error is above)");
        return Flow::Next;
    }
};

// Size an array from its dimension expressions (evaluated when the function is defined).
std::shared_ptr<Array> make_array(Frame& f, const Symbol& sym, const std::vector<ExprP>& dims) {
    auto a = std::make_shared<Array>();
    size_t total = 1;
    for (const auto& d : dims) {
        const Value v = d->eval(f);
        if (v.type != Type::Int && !(v.type == Type::Float && v.f == std::floor(v.f) && std::isfinite(v.f))) {
            fish_fail(d->loc, "an array size must be a whole number (got " + to_text(v) + ")");
        }
        const double x = v.type == Type::Int ? static_cast<double>(v.i) : v.f;
        const size_t cap = f.rt.max_array_items;
        if (x < 1 || x > static_cast<double>(cap)) {
            fish_fail(d->loc, "array '" + sym.name + "' would have " + to_text(v) + " elements along a dimension",
                      {"expected 1 to " + std::to_string(cap) + "; an array is sized when its function is defined, "
                       "from the values variables have then"});
        }
        const size_t n = static_cast<size_t>(x);
        total *= n;
        if (total > cap) fish_fail(d->loc, "array '" + sym.name + "' would have more than " + std::to_string(cap) + " elements");
        a->dims.push_back(static_cast<int>(n));
    }
    // All arrays together: each element takes about 100 bytes.
    const size_t others = f.rt.array_items() - (sym.array ? sym.array->items.size() : 0);
    if (others + total > f.rt.max_array_items) {
        fish_fail(dims.front()->loc, "array '" + sym.name + "' would bring the elements of all arrays beyond " +
                                         std::to_string(f.rt.max_array_items),
                  {"lose_array(a) frees an array that is no longer needed"});
    }
    a->items.assign(total, Value::integer(0));
    return a;
}

// ---------------------------------------------------------------------------------------------
// The compiler

bool is_word(const Token& t, const char* w) { return t.kind == Tok::Name && t.lower == w; }
bool is_op(const Token& t, const char* o) { return t.kind == Tok::Op && t.text == o; }

class Compiler {
public:
    Compiler(Runtime& rt, Function& fn, const std::vector<Line>& lines) : rt_(rt), fn_(fn), lines_(lines) {}
    // A statement typed in a command block: its names are first the running function's locals.
    Frame* outer = nullptr;

    void add_local(const std::string& lower_name, const SourceLoc& loc) {
        if (locals_.count(lower_name)) return;
        if (find_intrinsic(lower_name)) fish_fail(loc, "'" + lower_name + "' is a FISH intrinsic, it cannot be a local variable");
        locals_[lower_name] = fn_.n_locals++;
        fn_.local_names.push_back(lower_name);
    }

    // Every `local` of the body is local from the function's first line (as in 3DEC). A name
    // the body assigns as a plain variable (`name = ...`) is the script's, even where a
    // read-only intrinsic has the same name.
    void collect_locals() {
        for (const Line& l : lines_) {
            const auto& t = l.tokens;
            if (t.size() > 2 && t[0].kind == Tok::Name && is_op(t[1], "=")) {
                const Intrinsic* in = find_intrinsic(t[0].lower);
                if (in && !in->set && in->min_args > 0) rt_.symbol(t[0].text).shadows_intrinsic = true;
            }
            if (t.empty() || !is_word(t[0], "local")) continue;
            size_t i = 1;
            while (i < t.size() && t[i].kind == Tok::Name) {
                add_local(t[i].lower, t[i].loc);
                ++i;
                if (i < t.size() && is_op(t[i], "=")) break;
                if (i < t.size() && is_op(t[i], ",")) ++i;
            }
        }
    }

    void compile() {
        collect_locals();
        size_t pos = 0;
        std::string ended;
        fn_.body = block(pos, {}, ended);
    }

private:
    Runtime& rt_;
    Function& fn_;
    const std::vector<Line>& lines_;
    std::map<std::string, int> locals_;
    const std::vector<Token>* t_ = nullptr;
    size_t i_ = 0;
    bool used_local_ = false; // a local was referred to since this was last cleared
    bool in_memory_call_ = false; // compiling the arguments of imem()/fmem()

    // -- expressions -------------------------------------------------------------------------
    const Token& peek() const { return (*t_)[i_]; }
    const Token& take() { return (*t_)[i_ < t_->size() - 1 ? i_++ : i_]; }
    bool at_end() const { return peek().kind == Tok::End; }
    void expect_op(const char* op, const char* what) {
        if (!is_op(peek(), op)) {
            fish_fail(peek().loc, std::string("expected ") + what + (at_end() ? " before the end of the line" : ", found '" + peek().text + "'"));
        }
        take();
    }

    template <class N>
    std::unique_ptr<N> node(const SourceLoc& loc) {
        auto n = std::make_unique<N>();
        n->loc = loc;
        return n;
    }

    // Nesting (parentheses, signs, blocks) is bounded: each level takes C++ stack, when compiled
    // and when run.
    static constexpr int kMaxNesting = 100;
    int depth_ = 0;
    struct Deeper {
        Compiler& c;
        Deeper(Compiler& cc, const SourceLoc& at) : c(cc) {
            if (++c.depth_ > kMaxNesting) {
                --c.depth_;
                fish_fail(at, "this nests more than " + std::to_string(kMaxNesting) + " levels deep",
                          {"split it into smaller expressions or functions"});
            }
        }
        ~Deeper() { --c.depth_; }
    };

    ExprP expr() {
        Deeper d(*this, peek().loc);
        return or_expr();
    }

    ExprP or_expr() {
        ExprP a = and_expr();
        while (is_op(peek(), "|") || is_word(peek(), "or")) {
            const SourceLoc loc = take().loc;
            auto n = node<Logic>(loc);
            n->is_and = false;
            n->a = std::move(a);
            n->b = and_expr();
            a = std::move(n);
        }
        return a;
    }

    ExprP and_expr() {
        ExprP a = not_expr();
        while (is_op(peek(), "&") || is_word(peek(), "and")) {
            const SourceLoc loc = take().loc;
            auto n = node<Logic>(loc);
            n->a = std::move(a);
            n->b = not_expr();
            a = std::move(n);
        }
        return a;
    }

    ExprP not_expr() {
        Deeper d(*this, peek().loc);
        if (is_word(peek(), "not") || is_op(peek(), "!")) {
            const SourceLoc loc = take().loc;
            auto n = node<Unary>(loc);
            n->op = '!';
            n->e = not_expr();
            return n;
        }
        return comparison();
    }

    ExprP comparison() {
        ExprP a = additive();
        for (;;) {
            const Token& t = peek();
            if (t.kind != Tok::Op) break;
            std::string op = t.text;
            if (op == "==") op = "=";
            if (op == "!=" || op == "~=" || op == "<>") op = "#";
            if (op != "=" && op != "#" && op != "<" && op != ">" && op != "<=" && op != ">=") break;
            const SourceLoc loc = take().loc;
            auto n = node<Binary>(loc);
            n->op = op;
            n->code = op.size() == 1 ? op[0] : 0;
            n->a = std::move(a);
            n->b = additive();
            a = std::move(n);
        }
        return a;
    }

    ExprP additive() {
        ExprP a = multiplicative();
        while (is_op(peek(), "+") || is_op(peek(), "-")) {
            const Token& t = take();
            auto n = node<Binary>(t.loc);
            n->op = t.text;
            n->code = t.text.size() == 1 ? t.text[0] : 0;
            n->a = std::move(a);
            n->b = multiplicative();
            a = std::move(n);
        }
        return a;
    }

    ExprP multiplicative() {
        ExprP a = unary();
        while (is_op(peek(), "*") || is_op(peek(), "/")) {
            const Token& t = take();
            auto n = node<Binary>(t.loc);
            n->op = t.text;
            n->code = t.text.size() == 1 ? t.text[0] : 0;
            n->a = std::move(a);
            n->b = unary();
            a = std::move(n);
        }
        return a;
    }

    ExprP unary() {
        Deeper d(*this, peek().loc);
        if (is_op(peek(), "-")) {
            const SourceLoc loc = take().loc;
            auto n = node<Unary>(loc);
            n->e = unary();
            return n;
        }
        if (is_op(peek(), "+")) {
            take();
            return unary();
        }
        return power();
    }

    // `^` binds tighter than a sign and groups to the right: -2^2 = -4, 2^3^2 = 512.
    ExprP power() {
        ExprP a = primary();
        if (is_op(peek(), "^")) {
            const SourceLoc loc = take().loc;
            auto n = node<Binary>(loc);
            n->op = "^";
            n->code = '^';
            n->a = std::move(a);
            n->b = unary();
            return n;
        }
        return a;
    }

    std::vector<ExprP> call_args() {
        std::vector<ExprP> args;
        take(); // (
        if (is_op(peek(), ")")) {
            take();
            return args;
        }
        for (;;) {
            args.push_back(expr());
            if (is_op(peek(), ",")) {
                take();
                continue;
            }
            expect_op(")", "',' or ')' after an argument");
            return args;
        }
    }

    ExprP primary() {
        const Token& t = peek();
        switch (t.kind) {
        case Tok::Int: {
            auto n = node<Const>(t.loc);
            n->v = Value::integer(t.integer);
            take();
            return n;
        }
        case Tok::Float: {
            auto n = node<Const>(t.loc);
            n->v = Value::real(t.number);
            take();
            return n;
        }
        case Tok::String: {
            auto n = node<Const>(t.loc);
            n->v = Value::string(t.text);
            take();
            return n;
        }
        case Tok::Op:
            if (t.text == "(") {
                const SourceLoc loc = take().loc;
                ExprP first = expr();
                if (is_op(peek(), ",")) { // (x, y, z)
                    auto v = node<VectorLit>(loc);
                    v->x = std::move(first);
                    take();
                    v->y = expr();
                    expect_op(",", "',' and the third component of the vector (x,y,z)");
                    v->z = expr();
                    expect_op(")", "')' to close the vector (x,y,z)");
                    return v;
                }
                expect_op(")", "')'");
                return first;
            }
            fish_fail(t.loc, "expected a value, found '" + t.text + "'");
        case Tok::End: fish_fail(t.loc, "expected a value before the end of the line");
        case Tok::Name: break;
        }
        const Token name = take();
        if (name.lower == "true" || name.lower == "false") {
            auto n = node<Const>(name.loc);
            n->v = Value::boolean(name.lower == "true");
            return n;
        }
        if (name.text[0] == '$' && in_memory_call_ && !locals_.count(name.lower)) {
            auto n = node<MemoryOffset>(name.loc);
            n->name = name.text;
            return n;
        }
        const bool has_args = is_op(peek(), "(");
        auto local = locals_.find(name.lower);
        if (local != locals_.end()) {
            used_local_ = true;
            if (has_args) fish_fail(name.loc, "'" + name.text + "' is a local variable, not a function or an array");
            auto n = node<LocalRef>(name.loc);
            n->slot = local->second;
            n->name = name.text;
            return n;
        }
        if (ExprP o = outer_local(name)) {
            if (has_args) fish_fail(name.loc, "'" + name.text + "' is a local variable of '" + outer->fn->name +
                                                  "', not a function or an array");
            return o;
        }
        const Symbol* user = rt_.find(name.lower);
        const Intrinsic* in = user && user->shadows_intrinsic ? nullptr : find_intrinsic(name.lower);
        if (in) {
            auto n = node<IntrinsicCall>(name.loc);
            n->in = in;
            if (has_args) {
                // `fmem(c + $KCFN)`: a `$` name there is a classic memory offset.
                const bool outer = in_memory_call_;
                in_memory_call_ = std::string(in->name) == "imem" || std::string(in->name) == "fmem";
                n->args = call_args();
                in_memory_call_ = outer;
            }
            const int k = static_cast<int>(n->args.size());
            if (k < in->min_args || (in->max_args >= 0 && k > in->max_args) || k > 8) {
                std::string want = in->min_args == in->max_args ? std::to_string(in->min_args)
                                   : in->max_args < 0          ? std::to_string(in->min_args) + " or more"
                                                               : std::to_string(in->min_args) + " to " + std::to_string(in->max_args);
                fish_fail(name.loc, std::string("'") + in->name + "' takes " + want + " argument" + (want == "1" ? "" : "s") +
                                        ", given " + std::to_string(k),
                          {std::string("use: ") + in->name + (in->max_args == 0 ? "" : std::string("(") + in->args + ")")});
            }
            return n;
        }
        Symbol& s = rt_.symbol(name.text);
        if (has_args) {
            auto n = node<GlobalCall>(name.loc);
            n->sym = &s;
            n->args = call_args();
            return n;
        }
        auto n = node<GlobalRef>(name.loc);
        n->sym = &s;
        return n;
    }

    // The running function's argument or local `name`, for a statement typed in its command
    // block; null otherwise.
    ExprP outer_local(const Token& name) {
        if (!outer) return nullptr;
        const auto& names = outer->fn->local_names;
        for (size_t k = 0; k < names.size(); ++k) {
            if (names[k] != name.lower) continue;
            auto n = node<OuterLocalRef>(name.loc);
            n->frame = outer;
            n->slot = static_cast<int>(k);
            n->name = name.text;
            return n;
        }
        return nullptr;
    }

    // A variable named by a token (a loop's counter): local, or global.
    ExprP variable(const Token& name) {
        auto local = locals_.find(name.lower);
        if (local != locals_.end()) {
            auto n = node<LocalRef>(name.loc);
            n->slot = local->second;
            n->name = name.text;
            return n;
        }
        if (ExprP o = outer_local(name)) return o;
        const Symbol* user = rt_.find(name.lower);
        if (find_intrinsic(name.lower) && !(user && user->shadows_intrinsic)) {
            fish_fail(name.loc, "'" + name.text + "' is a FISH intrinsic, not a variable");
        }
        auto n = node<GlobalRef>(name.loc);
        n->sym = &rt_.symbol(name.text);
        return n;
    }

    void expect_end(const char* after) {
        if (!at_end()) fish_fail(peek().loc, "unexpected '" + peek().text + "' " + after);
    }

    ExprP whole_expr(const char* after) {
        ExprP e = expr();
        expect_end(after);
        return e;
    }

    // -- statements --------------------------------------------------------------------------
    static bool closes(const Token& t, const std::set<std::string>& words) {
        return t.kind == Tok::Name && words.count(t.lower);
    }

    // Statements up to a line whose first word is in `until` (returned in `ended`, the line
    // not consumed), or to the end of the body.
    Block block(size_t& pos, const std::set<std::string>& until, std::string& ended) {
        Block out;
        ended.clear();
        while (pos < lines_.size()) {
            const Line& l = lines_[pos];
            if (l.tokens.size() <= 1) {
                ++pos;
                continue;
            }
            if (closes(l.tokens[0], until)) {
                ended = l.tokens[0].lower;
                return out;
            }
            StmtP s = statement(pos);
            if (s) out.push_back(std::move(s));
        }
        return out;
    }

    [[noreturn]] void unclosed(const Line& opener, const char* what, const char* closer) {
        fish_fail(opener.loc, std::string("this ") + what + " has no '" + closer + "' before the function's 'end'");
    }

    void finish_line(size_t& pos, const char* after) {
        t_ = &lines_[pos].tokens;
        i_ = 1;
        expect_end(after);
        ++pos;
    }

    StmtP statement(size_t& pos) {
        const Line& l = lines_[pos];
        Deeper d(*this, l.loc);
        t_ = &l.tokens;
        i_ = 0;
        const Token& w = l.tokens[0];
        const std::string k = w.kind == Tok::Name ? w.lower : std::string();

        if (k == "if") {
            take();
            auto s = node<If>(w.loc);
            s->cond = expr();
            if (is_word(peek(), "then")) take();
            expect_end("after the condition of 'if'");
            ++pos;
            if_rest(*s, pos, l);
            return s;
        }
        if (k == "loop") {
            take();
            ++pos;
            std::string ended;
            if (is_word(peek(), "while")) {
                take();
                auto s = node<LoopWhile>(w.loc);
                s->cond = whole_expr("after the condition of 'loop while'");
                s->body = block(pos, {"endloop", "end_loop"}, ended);
                if (ended.empty()) unclosed(l, "loop", "endloop");
                finish_line(pos, "after 'endloop'");
                return s;
            }
            if (is_word(peek(), "local")) take();
            if (peek().kind != Tok::Name) {
                fish_fail(peek().loc, "expected 'loop while condition' or 'loop name (from, to)'");
            }
            auto s = node<LoopRange>(w.loc);
            s->var = variable(take());
            if (!is_op(peek(), "(")) fish_fail(peek().loc, "expected '(from, to)' after the loop variable");
            take();
            s->from = expr();
            expect_op(",", "',' between the loop's bounds");
            s->to = expr();
            expect_op(")", "')' after the loop's bounds");
            expect_end("after the loop's bounds");
            s->body = block(pos, {"endloop", "end_loop"}, ended);
            if (ended.empty()) unclosed(l, "loop", "endloop");
            finish_line(pos, "after 'endloop'");
            return s;
        }
        if (k == "section") {
            take();
            expect_end("after 'section'");
            ++pos;
            auto s = node<Section>(w.loc);
            std::string ended;
            s->body = block(pos, {"endsection", "end_section"}, ended);
            if (ended.empty()) unclosed(l, "section", "endsection");
            finish_line(pos, "after 'endsection'");
            return s;
        }
        if (k == "caseof" || k == "case_of") {
            take();
            auto s = node<CaseOf>(w.loc);
            s->selector = whole_expr("after the value of 'caseof'");
            ++pos;
            std::string ended;
            s->otherwise = block(pos, {"case", "endcase", "end_case"}, ended);
            while (ended == "case") {
                t_ = &lines_[pos].tokens;
                i_ = 1;
                std::vector<long long> values;
                for (;;) {
                    bool neg = false;
                    if (is_op(peek(), "-")) {
                        take();
                        neg = true;
                    }
                    if (peek().kind != Tok::Int) fish_fail(peek().loc, "expected a whole number after 'case'");
                    values.push_back(neg ? -take().integer : take().integer);
                    if (is_op(peek(), ",")) {
                        take();
                        continue;
                    }
                    break;
                }
                expect_end("after the case's number");
                ++pos;
                Block b = block(pos, {"case", "endcase", "end_case"}, ended);
                s->cases.emplace_back(std::move(values), std::move(b));
            }
            if (ended.empty()) unclosed(l, "caseof", "endcase");
            finish_line(pos, "after 'endcase'");
            return s;
        }
        if (k == "command") {
            take();
            expect_end("after 'command'");
            auto s = node<Command>(w.loc);
            s->file = l.loc.file;
            s->first = l.loc.line + 1;
            ++pos;
            while (pos < lines_.size()) {
                const auto& t = lines_[pos].tokens;
                if (t.size() > 1 && (is_word(t[0], "endcommand") || is_word(t[0], "end_command"))) break;
                ++pos;
            }
            if (pos >= lines_.size()) unclosed(l, "command block", "endcommand");
            s->last = lines_[pos].loc.line - 1;
            finish_line(pos, "after 'endcommand'");
            return s;
        }
        if (k == "exit" || k == "return") {
            take();
            auto s = node<Jump>(w.loc);
            if (k == "exit" && is_word(peek(), "section")) {
                take();
                s->flow = Flow::ExitSection;
            } else if (k == "exit" && is_word(peek(), "loop")) {
                take();
                s->flow = Flow::ExitLoop;
            }
            expect_end(k == "exit" ? "after 'exit' (expected 'exit', 'exit section' or 'exit loop')" : "after 'return'");
            ++pos;
            return s;
        }
        if (k == "continue") {
            take();
            expect_end("after 'continue'");
            auto s = node<Jump>(w.loc);
            s->flow = Flow::ContinueLoop;
            ++pos;
            return s;
        }
        if (k == "whilestepping") {
            take();
            expect_end("after 'whilestepping'");
            fn_.whilestepping = true;
            ++pos;
            return nullptr;
        }
        if (k == "array") {
            take();
            // array a(n[,m]) [b(n) ...]: one statement per array.
            while (!at_end()) {
                if (peek().kind != Tok::Name) fish_fail(peek().loc, "expected an array name");
                const Token name = take();
                if (locals_.count(name.lower) || find_intrinsic(name.lower)) {
                    fish_fail(name.loc, "'" + name.text + "' cannot be an array: it is a " +
                                            (locals_.count(name.lower) ? "local variable" : "FISH intrinsic"));
                }
                if (!is_op(peek(), "(")) fish_fail(peek().loc, "expected the array's size in parentheses: " + name.text + "(n)");
                Symbol& sym = rt_.symbol(name.text);
                if (sym.fn) fish_fail(name.loc, "'" + name.text + "' is a function, it cannot also be an array");
                used_local_ = false;
                std::vector<ExprP> dims = call_args();
                if (dims.empty() || dims.size() > 3) fish_fail(name.loc, "an array has 1 to 3 dimensions");
                if (used_local_) {
                    fish_fail(name.loc, "the size of array '" + name.text + "' uses a local variable",
                              {"an array is sized when its function is defined: use numbers or global variables"});
                }
                std::vector<Value> none(static_cast<size_t>(fn_.n_locals + 1));
                Frame frame{rt_, &fn_, none.data()};
                fn_.arrays.emplace_back(&sym, make_array(frame, sym, dims));
                if (is_op(peek(), ",")) take();
            }
            ++pos;
            return nullptr;
        }
        if (k == "local" || k == "global") {
            take();
            // local a, b   |   local a = expr
            while (!at_end()) {
                if (peek().kind != Tok::Name) fish_fail(peek().loc, "expected a variable name after '" + k + "'");
                const Token name = take();
                if (k == "global") {
                    if (locals_.count(name.lower)) fish_fail(name.loc, "'" + name.text + "' is already local in this function");
                    rt_.symbol(name.text);
                }
                if (is_op(peek(), "=")) {
                    const SourceLoc loc = take().loc;
                    auto s = node<Assign>(loc);
                    i_ -= 2;
                    s->target = primary();
                    take(); // =
                    s->value = whole_expr("after the value");
                    ++pos;
                    return s;
                }
                if (is_op(peek(), ",")) take();
            }
            ++pos;
            return nullptr;
        }
        if (k == "else" || k == "endif" || k == "end_if" || k == "endloop" || k == "end_loop" || k == "endsection" ||
            k == "end_section" || k == "case" || k == "endcase" || k == "end_case" || k == "endcommand" ||
            k == "end_command" || k == "then") {
            fish_fail(w.loc, "'" + w.text + "' without the statement it closes");
        }
        if (k == "def" || k == "define") {
            fish_fail(w.loc, "'" + w.text + "' inside a function: the previous definition has no 'end'");
        }

        // An assignment (`=` after a variable, an element or an intrinsic) or an expression
        // (usually a call); in an expression `=` compares.
        const size_t start = i_;
        ExprP target = primary();
        if (!is_op(peek(), "=")) {
            i_ = start;
            target = expr();
        }
        if (is_op(peek(), "=")) {
            const SourceLoc loc = take().loc;
            // What cannot be assigned is refused when the function is defined.
            if (auto* in = dynamic_cast<IntrinsicCall*>(target.get()); in && !in->in->set) {
                fish_fail(target->loc, std::string("'") + in->in->name + "' can be read, not assigned");
            }
            if (!dynamic_cast<LocalRef*>(target.get()) && !dynamic_cast<OuterLocalRef*>(target.get()) &&
                !dynamic_cast<GlobalRef*>(target.get()) &&
                !dynamic_cast<GlobalCall*>(target.get()) && !dynamic_cast<IntrinsicCall*>(target.get())) {
                fish_fail(target->loc, "cannot assign to " + target->describe(),
                          {"the left of '=' is a variable, an array element or a writable intrinsic"});
            }
            auto s = node<Assign>(loc);
            s->target = std::move(target);
            s->value = whole_expr("after the value");
            ++pos;
            return s;
        }
        if (!at_end()) fish_fail(peek().loc, "unexpected '" + peek().text + "': expected '=' or the end of the statement");
        auto s = node<Evaluate>(w.loc);
        s->e = std::move(target);
        ++pos;
        return s;
    }

    void if_rest(If& s, size_t& pos, const Line& opener) {
        std::string ended;
        s.then_b = block(pos, {"else", "endif", "end_if"}, ended);
        if (ended.empty()) unclosed(opener, "if", "endif");
        if (ended == "else") {
            const Line& el = lines_[pos];
            t_ = &el.tokens;
            i_ = 1;
            if (is_word(peek(), "if")) { // else if: a nested if sharing this endif
                take();
                auto inner = node<If>(el.loc);
                inner->cond = expr();
                if (is_word(peek(), "then")) take();
                expect_end("after the condition of 'else if'");
                ++pos;
                if_rest(*inner, pos, el);
                s.else_b.push_back(std::move(inner));
                return;
            }
            expect_end("after 'else'");
            ++pos;
            s.else_b = block(pos, {"endif", "end_if"}, ended);
            if (ended.empty()) unclosed(opener, "if", "endif");
        }
        finish_line(pos, "after 'endif'");
    }
};

} // namespace

// Compile into a new Function; the symbol keeps its old definition until this succeeds.
void compile_function(Runtime& rt, const Line& header, const std::vector<Line>& body, std::shared_ptr<Function>& out) {
    const auto& t = header.tokens;
    // def name [ (a, b, ...) ]
    size_t i = 1;
    if (t.size() < 2 || t[i].kind != Tok::Name) {
        fish_fail(t.size() > 1 ? t[1].loc : header.loc, "expected the function's name after '" + t[0].text + "'");
    }
    const Token& name = t[i++];
    if (find_intrinsic(name.lower)) {
        fish_fail(name.loc, "'" + name.text + "' is a FISH intrinsic: choose another name for the function",
                  {"see 'help fish " + name.lower + "'"});
    }
    auto fn = std::make_shared<Function>();
    fn->name = name.text;
    fn->loc = name.loc;
    Compiler c(rt, *fn, body);
    if (i < t.size() && t[i].kind == Tok::Op && t[i].text == "(") {
        ++i;
        while (i < t.size() && !(t[i].kind == Tok::Op && t[i].text == ")")) {
            if (t[i].kind != Tok::Name) fish_fail(t[i].loc, "expected an argument name");
            c.add_local(t[i].lower, t[i].loc);
            ++i;
            if (i < t.size() && t[i].kind == Tok::Op && t[i].text == ",") ++i;
        }
        if (i >= t.size() || t[i].kind != Tok::Op) fish_fail(header.loc, "expected ')' after the arguments");
        ++i;
    }
    fn->n_params = fn->n_locals;
    if (t[i].kind != Tok::End) fish_fail(t[i].loc, "unexpected '" + t[i].text + "' after the function's name");
    Symbol& s = rt.symbol(name.text);
    if (s.array) fish_fail(name.loc, "'" + name.text + "' is an array, it cannot also be a function");
    fn->self = &s;
    c.compile();
    out = std::move(fn);
}

// One top-level statement: compiled as the body of a nameless function and run.
void compile_statement(Runtime& rt, const Line& line, std::shared_ptr<Function>& out) {
    auto fn = std::make_shared<Function>();
    fn->name = "";
    fn->loc = line.loc;
    std::vector<Line> body{line};
    Compiler c(rt, *fn, body);
    if (!rt.command_frames.empty()) c.outer = rt.command_frames.back();
    c.compile();
    out = std::move(fn);
}

} // namespace odec::fish
