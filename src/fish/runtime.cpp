#include "fish/runtime.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "engine/model.h"
#include "fish/ast.h"

namespace odec::fish {

void compile_function(Runtime& rt, const Line& header, const std::vector<Line>& body, std::shared_ptr<Function>& out);
void compile_statement(Runtime& rt, const Line& line, std::shared_ptr<Function>& out);

void fish_fail(const SourceLoc& loc, std::string what, std::vector<std::string> notes) {
    throw FishError{Diagnostic{loc, std::move(what), std::move(notes), "fish"}};
}

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string where(const SourceLoc& l) {
    return (l.file ? l.file->name : std::string("<input>")) + ":" + std::to_string(l.line);
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Values

const char* type_name(const Value& v) {
    switch (v.type) {
    case Type::Int: return "an integer";
    case Type::Float: return "a float";
    case Type::Bool: return "a boolean";
    case Type::String: return "a string";
    case Type::Vector: return "a vector";
    case Type::Pointer: return "a pointer";
    case Type::Array: return "an array";
    }
    return "a value";
}

namespace {
std::string number_text(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    std::string s(buf, r.ptr);
    // A float reads as a float: 2.0 is "2.0", not "2".
    if (s.find_first_of(".en") == std::string::npos) s += ".0";
    return s;
}
} // namespace

std::string to_text(const Value& v) {
    switch (v.type) {
    case Type::Int: return std::to_string(v.i);
    case Type::Float: return number_text(v.f);
    case Type::Bool: return v.i ? "true" : "false";
    case Type::String: return v.s;
    case Type::Vector:
        return "(" + number_text(v.v.x()) + "," + number_text(v.v.y()) + "," + number_text(v.v.z()) + ")";
    case Type::Pointer: return std::to_string(v.i + 1);
    case Type::Array: return "array(" + std::to_string(v.a ? v.a->items.size() : 0) + ")";
    }
    return "";
}

bool truth(const Value& v, const SourceLoc& loc) {
    switch (v.type) {
    case Type::Int:
    case Type::Bool: return v.i != 0;
    case Type::Float: return v.f != 0;
    case Type::Pointer: return true;
    default: fish_fail(loc, std::string("a condition must be a number or a boolean, not ") + type_name(v));
    }
}

bool equal(const Value& a, const Value& b) {
    if (a.is_number() && b.is_number()) {
        if (a.type == Type::Int && b.type == Type::Int) return a.i == b.i;
        return a.number() == b.number();
    }
    if (a.type == Type::Pointer && b.type == Type::Pointer) return a.kind == b.kind && a.i == b.i;
    if (a.type == Type::Pointer || b.type == Type::Pointer) return false; // a pointer is never null
    if (a.type == Type::Bool || b.type == Type::Bool) {
        if ((a.type == Type::Bool || a.is_number()) && (b.type == Type::Bool || b.is_number())) {
            return (a.number() != 0) == (b.number() != 0);
        }
        return false;
    }
    if (a.type == Type::String && b.type == Type::String) return a.s == b.s;
    if (a.type == Type::Vector && b.type == Type::Vector) return a.v == b.v;
    return false;
}

namespace {

[[noreturn]] void bad_operands(const std::string& op, const Value& a, const Value& b, const SourceLoc& loc) {
    std::vector<std::string> notes;
    if ((a.type == Type::String) != (b.type == Type::String) && op == "+") {
        notes.push_back("turn the number into text first: string(x)");
    }
    fish_fail(loc, "cannot use '" + op + "' on " + type_name(a) + " and " + type_name(b), notes);
}

} // namespace

Value binary(const std::string& op, const Value& a, const Value& b, const SourceLoc& loc) {
    const char c = op[0];
    if (op.size() == 1 && (c == '=' || c == '#')) return Value::boolean(equal(a, b) == (c == '='));
    if (a.is_number() && b.is_number()) {
        const bool ints = a.type == Type::Int && b.type == Type::Int;
        if (op == "<") return Value::boolean(ints ? a.i < b.i : a.number() < b.number());
        if (op == ">") return Value::boolean(ints ? a.i > b.i : a.number() > b.number());
        if (op == "<=") return Value::boolean(ints ? a.i <= b.i : a.number() <= b.number());
        if (op == ">=") return Value::boolean(ints ? a.i >= b.i : a.number() >= b.number());
        long long r = 0;
        switch (c) {
        case '+':
            if (ints) return __builtin_add_overflow(a.i, b.i, &r) ? Value::real(a.number() + b.number()) : Value::integer(r);
            return Value::real(a.number() + b.number());
        case '-':
            if (ints) return __builtin_sub_overflow(a.i, b.i, &r) ? Value::real(a.number() - b.number()) : Value::integer(r);
            return Value::real(a.number() - b.number());
        case '*':
            if (ints) return __builtin_mul_overflow(a.i, b.i, &r) ? Value::real(a.number() * b.number()) : Value::integer(r);
            return Value::real(a.number() * b.number());
        case '/':
            if (ints) {
                if (b.i == 0) fish_fail(loc, "division by zero (integer)");
                if (a.i == INT64_MIN && b.i == -1) return Value::real(-a.number());
                return Value::integer(a.i / b.i);
            }
            if (b.number() == 0) fish_fail(loc, "division by zero");
            return Value::real(a.number() / b.number());
        case '^': {
            if (ints && b.i >= 0) {
                long long acc = 1, base = a.i, e = b.i;
                bool over = false;
                while (e > 0 && !over) {
                    if (e & 1) over = __builtin_mul_overflow(acc, base, &acc);
                    e >>= 1;
                    if (e > 0 && !over) over = __builtin_mul_overflow(base, base, &base);
                }
                if (!over) return Value::integer(acc);
            }
            return Value::real(std::pow(a.number(), b.number()));
        }
        default: break;
        }
        bad_operands(op, a, b, loc);
    }
    if (a.type == Type::String && b.type == Type::String) {
        if (op == "+") {
            if (a.s.size() + b.s.size() > Runtime::kMaxString) {
                fish_fail(loc, "a string of more than " + std::to_string(Runtime::kMaxString) + " characters");
            }
            return Value::string(a.s + b.s);
        }
        if (op == "<") return Value::boolean(a.s < b.s);
        if (op == ">") return Value::boolean(a.s > b.s);
        if (op == "<=") return Value::boolean(a.s <= b.s);
        if (op == ">=") return Value::boolean(a.s >= b.s);
        bad_operands(op, a, b, loc);
    }
    if (a.type == Type::Vector && b.type == Type::Vector) {
        if (op == "+") return Value::vector(a.v + b.v);
        if (op == "-") return Value::vector(a.v - b.v);
        bad_operands(op, a, b, loc);
    }
    if (a.type == Type::Vector && b.is_number()) {
        if (op == "*") return Value::vector(a.v * b.number());
        if (op == "/") {
            if (b.number() == 0) fish_fail(loc, "division by zero");
            return Value::vector(a.v / b.number());
        }
    }
    if (a.is_number() && b.type == Type::Vector && op == "*") return Value::vector(a.number() * b.v);
    bad_operands(op, a, b, loc);
}

// ---------------------------------------------------------------------------------------------
// Running

Flow run_block(const Block& b, Frame& f) {
    for (const auto& s : b) {
        const Flow fl = s->exec(f);
        if (fl != Flow::Next) return fl;
    }
    return Flow::Next;
}

namespace {

struct CallGuard {
    Runtime& rt;
    CallGuard(Runtime& r, const Function* fn, const SourceLoc& at) : rt(r) {
        if (static_cast<int>(rt.calls.size()) >= Runtime::kMaxDepth) {
            fish_fail(at, "FISH calls nest more than " + std::to_string(Runtime::kMaxDepth) + " deep",
                      {"a function calls itself, directly or through others, without end"});
        }
        rt.calls.push_back({fn, at});
    }
    ~CallGuard() { rt.calls.pop_back(); }
};

Value run_function(Runtime& rt, const Function& fn, std::vector<Value>& args, const SourceLoc& at) {
    if (rt.host.interrupted()) fish_fail(at, "interrupted");
    CallGuard guard(rt, &fn, at);
    Value small[16];
    std::vector<Value> big;
    Value* locals = small;
    if (fn.n_locals > 16) {
        big.resize(static_cast<size_t>(fn.n_locals));
        locals = big.data();
    }
    for (int k = 0; k < fn.n_params; ++k) locals[k] = std::move(args[static_cast<size_t>(k)]);
    Frame frame{rt, &fn, locals};
    const Flow fl = run_block(fn.body, frame);
    if (fl == Flow::ExitSection) fish_fail(at, "'exit section' outside a section in '" + fn.name + "'");
    if (fl == Flow::ExitLoop || fl == Flow::ContinueLoop) fish_fail(at, "'exit loop' or 'continue' outside a loop in '" + fn.name + "'");
    return fn.self ? fn.self->value : Value::null();
}

} // namespace

Value call_function(Runtime& rt, Symbol& s, std::vector<Value>& args, const SourceLoc& at) {
    // Keep the function alive while it runs, even if it redefines itself.
    const std::shared_ptr<Function> fn = s.fn;
    if (static_cast<int>(args.size()) != fn->n_params) {
        fish_fail(at, "'" + s.name + "' takes " + std::to_string(fn->n_params) + " argument" + (fn->n_params == 1 ? "" : "s") +
                          ", given " + std::to_string(args.size()),
                  {"it is defined at " + where(fn->loc)});
    }
    rt.tick(at);
    try {
        return run_function(rt, *fn, args, at);
    } catch (FishError& e) {
        if (e.diag.notes.size() < 12) e.diag.notes.push_back("in '" + fn->name + "', called at " + where(at));
        throw;
    }
}

// ---------------------------------------------------------------------------------------------
// Runtime

Runtime::Runtime(Host& h) : host(h) {}

void Runtime::tick(const SourceLoc& loc) {
    if (host.interrupted()) fish_fail(loc, "interrupted by Ctrl-C");
    if (budget && *budget >= 0) {
        if (*budget == 0) fish_fail(loc, "this session's bound on FISH loop iterations and calls is reached");
        --*budget;
    }
}

void Runtime::spend(long long steps, const SourceLoc& loc) {
    if (!budget || *budget < 0 || steps <= 0) return;
    if (host.interrupted()) fish_fail(loc, "interrupted by Ctrl-C");
    if (*budget < steps) {
        *budget = 0;
        fish_fail(loc, "this session's bound on FISH loop iterations and calls is reached");
    }
    *budget -= steps;
}

size_t Runtime::array_items() const {
    size_t n = 0;
    for (const auto& [k, s] : symbols_) {
        if (s->array) n += s->array->items.size();
    }
    return n;
}

Runtime::~Runtime() {
    if (file) std::fclose(file);
}

Symbol& Runtime::symbol(const std::string& name) {
    const std::string key = lower(name);
    auto it = symbols_.find(key);
    if (it != symbols_.end()) return *it->second;
    auto s = std::make_unique<Symbol>();
    s->name = name;
    Symbol& ref = *s;
    symbols_.emplace(key, std::move(s));
    return ref;
}

const Symbol* Runtime::find(const std::string& lower_name) const {
    auto it = symbols_.find(lower_name);
    return it == symbols_.end() ? nullptr : it->second.get();
}

bool Runtime::is_function(const std::string& lower_name) const {
    const Symbol* s = find(lower_name);
    return s && s->fn;
}

bool Runtime::is_symbol(const std::string& lower_name) const { return find(lower_name) != nullptr; }

std::vector<std::string> Runtime::names() const {
    std::vector<std::string> out;
    for (const auto& [k, s] : symbols_) out.push_back(s->name);
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Symbol*> Runtime::stepping() const {
    std::vector<Symbol*> out;
    for (const std::string& k : order_) {
        auto it = symbols_.find(k);
        if (it != symbols_.end() && it->second->fn && it->second->fn->whilestepping) out.push_back(it->second.get());
    }
    return out;
}

void Runtime::clear() {
    // Compiled functions point at symbols: drop the functions first.
    for (auto& [k, s] : symbols_) s->fn.reset();
    symbols_.clear();
    order_.clear();
    for (auto& e : extras) e.clear();
    random.seed(1);
    if (file) std::fclose(file);
    file = nullptr;
    model_changed();
}

void Runtime::forget_model() {
    for (auto& e : extras) e.clear();
    model_changed();
}

void Runtime::define(const Line& header, const std::vector<Line>& body) {
    try {
        std::shared_ptr<Function> fn;
        compile_function(*this, header, body, fn);
        Symbol& s = *fn->self;
        const std::string key = lower(s.name);
        order_.erase(std::remove(order_.begin(), order_.end(), key), order_.end());
        order_.push_back(key);
        for (auto& [sym, arr] : fn->arrays) sym->array = std::move(arr);
        fn->arrays.clear();
        s.fn = std::move(fn);
    } catch (FishError& e) {
        throw CommandError{e.diag};
    }
}

Value Runtime::call(Symbol& s, const SourceLoc& loc) {
    std::vector<Value> none;
    model_changed();
    return call_function(*this, s, none, loc);
}

void Runtime::run_statement(const Line& line) {
    try {
        std::shared_ptr<Function> fn;
        compile_statement(*this, line, fn);
        model_changed();
        std::vector<Value> none;
        run_function(*this, *fn, none, line.loc);
    } catch (FishError& e) {
        throw CommandError{e.diag};
    }
}

const Value* Runtime::command_local(const std::string& lower_name) const {
    if (command_frames.empty()) return nullptr;
    const Frame& f = *command_frames.back();
    for (size_t k = 0; k < f.fn->local_names.size(); ++k) {
        if (f.fn->local_names[k] == lower_name) return &f.locals[k];
    }
    return nullptr;
}

std::string Runtime::command_function() const {
    return command_frames.empty() ? std::string() : command_frames.back()->fn->name;
}

Value Runtime::value_for_command(const std::string& name, const SourceLoc& loc) {
    Symbol* s = nullptr;
    auto it = symbols_.find(lower(name));
    if (it != symbols_.end()) s = it->second.get();
    try {
        // The arguments and locals of the function whose command block runs, as in its body.
        if (const Value* local = command_local(lower(name))) {
            if (local->type == Type::Array) fish_fail(loc, "'@" + name + "' is an array: a command takes one value");
            return *local;
        }
        if (!s) {
            // Intrinsics without arguments (`@time`) read as well.
            if (const Intrinsic* in = find_intrinsic(lower(name)); in && in->min_args == 0) {
                model_changed();
                return in->get(*this, nullptr, 0, loc);
            }
            std::vector<std::string> notes{"define it first: def " + name + " ... end, or assign it in a function"};
            fish_fail(loc, "'@" + name + "' is no FISH variable or function", notes);
        }
        if (s->fn) return call(*s, loc);
        if (s->array) fish_fail(loc, "'@" + name + "' is an array: a command takes one value");
        return s->value;
    } catch (FishError& e) {
        throw CommandError{e.diag};
    }
}

void Runtime::model_changed() {
    gps_ready_ = zones_ready_ = false;
}

const std::vector<std::vector<int>>& Runtime::block_gridpoints() {
    if (!gps_ready_) {
        const Model& m = host.model();
        block_gps_.assign(static_cast<size_t>(m.blocks.size()), {});
        std::vector<int> last(static_cast<size_t>(m.blocks.size()), -1);
        // The gridpoints of each block's zones, each once, in gridpoint order.
        std::vector<std::vector<int>> raw(static_cast<size_t>(m.blocks.size()));
        for (int z = 0; z < m.zones.size(); ++z) {
            const int b = m.zones.block[static_cast<size_t>(z)];
            if (b < 0 || b >= m.blocks.size()) continue;
            for (int g : m.zones.gp[static_cast<size_t>(z)]) raw[static_cast<size_t>(b)].push_back(g);
        }
        for (size_t b = 0; b < raw.size(); ++b) {
            auto& v = raw[b];
            std::sort(v.begin(), v.end());
            v.erase(std::unique(v.begin(), v.end()), v.end());
            block_gps_[b] = std::move(v);
        }
        gps_ready_ = true;
    }
    return block_gps_;
}

const std::vector<std::vector<int>>& Runtime::block_zones() {
    if (!zones_ready_) {
        const Model& m = host.model();
        block_zones_.assign(static_cast<size_t>(m.blocks.size()), {});
        for (int z = 0; z < m.zones.size(); ++z) {
            const int b = m.zones.block[static_cast<size_t>(z)];
            if (b >= 0 && b < m.blocks.size()) block_zones_[static_cast<size_t>(b)].push_back(z);
        }
        zones_ready_ = true;
    }
    return block_zones_;
}

} // namespace odec::fish
