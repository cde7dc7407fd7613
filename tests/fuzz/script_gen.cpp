// The script generator of the interpreter's fuzzing target (see script_gen.h).
//
// Every choice takes a byte (two for a choice among more than 256); when the bytes run out
// each choice takes its first option, which is always the ordinary one, so that a short
// input is a short, valid script. Commands come from the declarations: a command, its
// keywords (those a person would write together most of the time, any of them otherwise),
// and values of the declared type, mostly of a sensible size inside the declared limits,
// sometimes on a limit or just past it. A few keywords whose values only make sense
// together (a brick's corners, a prism's ends, a tunnel's axis) are written as a whole.
#include "script_gen.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "fish/intrinsics.h"
#include "lang/decl.h"

namespace odec::fuzz {

namespace {

class Choices {
public:
    Choices(const std::uint8_t* data, std::size_t size) : d_(data), n_(size) {}

    unsigned byte() { return at_ < n_ ? d_[at_++] : 0u; }
    bool exhausted() const { return at_ >= n_; }

    // An index below n; 0 once the bytes have run out. No byte is taken when there is no choice.
    std::size_t below(std::size_t n) {
        if (n <= 1) return 0;
        if (n <= 256) return byte() % n;
        const unsigned hi = byte();
        return ((hi << 8) | byte()) % n;
    }
    // True about percent times in a hundred; false once the bytes have run out.
    bool maybe(int percent) { return byte() >= 256u - static_cast<unsigned>(percent * 256 / 100); }
    // An index by weight; 0 once the bytes have run out.
    std::size_t weighted(std::initializer_list<int> weights) {
        int total = 0;
        for (int w : weights) total += w;
        std::size_t r = below(static_cast<std::size_t>(total));
        std::size_t k = 0;
        for (int w : weights) {
            if (r < static_cast<std::size_t>(w)) return k;
            r -= static_cast<std::size_t>(w);
            ++k;
        }
        return 0;
    }
    template <class T>
    const T& pick(std::initializer_list<T> options) {
        return *(options.begin() + below(options.size()));
    }
    template <class T>
    const T& pick(const std::vector<T>& options) {
        return options[below(options.size())];
    }

private:
    const std::uint8_t* d_;
    std::size_t n_;
    std::size_t at_ = 0;
};

// A number as a person writes it: integers without a point, others with six digits.
std::string num(double x) {
    char buf[64];
    if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15) {
        std::snprintf(buf, sizeof buf, "%.0f", x);
    } else {
        std::snprintf(buf, sizeof buf, "%.6g", x);
    }
    return buf;
}

// Every digit: for a value one ulp past a limit.
std::string exact(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

bool one_of(const std::string& s, std::initializer_list<const char*> names) {
    for (const char* n : names) {
        if (s == n) return true;
    }
    return false;
}

// What a value means, for its size: the declarations give its type and limits, its name and
// keyword tell a stiffness from a coordinate.
enum class Kind {
    Coord, Length, Count, Index, Steps, Dip, Dd, Stiffness, Density, Strength, Angle, Fraction, Dt, Time,
    Velocity, Force, Stress, Plain
};

Kind kind_of(const std::string& cmd, const std::string& kw, const ValueSpec& v) {
    const bool lo_finite = std::isfinite(v.lo), hi_finite = std::isfinite(v.hi);
    if (v.type == ValueType::Int) {
        if ((cmd == "step" && kw.empty()) || kw == "cycles") return Kind::Steps;
        if (one_of(kw, {"number", "ntheta", "nrad", "nseg"})) return Kind::Count;
        if (kw == "size" || kw == "seed") return Kind::Plain;
        return Kind::Index;
    }
    if (one_of(kw, {"dip"}) || v.name == "dip") return Kind::Dip;
    if (one_of(kw, {"dd"}) || v.name == "dd") return Kind::Dd;
    if (one_of(kw, {"density", "dens"})) return Kind::Density;
    if (one_of(kw, {"bulk", "k", "shear", "g", "ymod", "young", "jkn", "jks"})) return Kind::Stiffness;
    if (one_of(kw, {"cohesion", "tension", "jcohesion", "jtension", "jzdilation", "zdilation"})) return Kind::Strength;
    if (one_of(kw, {"friction", "dilation", "jfriction", "jdilation", "jres_friction"})) return Kind::Angle;
    if (one_of(kw, {"prat", "poisson", "persistence", "dtfrac", "local"}) || (cmd == "solve" && kw == "ratio") ||
        (cmd == "damping" && kw.empty()))
        return Kind::Fraction;
    if (one_of(kw, {"spacing", "radius", "outer", "box", "edge", "ratio", "magnify"}) || v.name == "r") return Kind::Length;
    if (kw == "dt" || kw == "ctol") return Kind::Dt;
    if (kw == "time") return Kind::Time;
    if (one_of(kw, {"xvelocity", "yvelocity", "zvelocity", "xvel", "yvel", "zvel"})) return Kind::Velocity;
    if (one_of(kw, {"xload", "yload", "zload"})) return Kind::Force;
    if (one_of(kw, {"stress", "xgrad", "ygrad", "zgrad"})) return Kind::Stress;
    if (!lo_finite && !hi_finite) return Kind::Coord;
    return Kind::Plain;
}

std::vector<double> palette(Kind k) {
    switch (k) {
    case Kind::Coord: return {0.5, 0, 1, 0.25, 0.75, -0.5, 1.5, 0.1, 0.9, 2, -1, 0.3};
    case Kind::Length: return {0.5, 0.25, 1, 0.3, 0.7, 2, 0.1};
    case Kind::Count: return {1, 2, 3, 1, 4};
    case Kind::Index: return {1, 2, 1, 3, 0, 5};
    case Kind::Steps: return {10, 1, 5, 20, 2, 50, 3};
    case Kind::Dip: return {45, 0, 90, 30, 60, 80, 10};
    case Kind::Dd: return {90, 0, 180, 270, 45, -90, 135, 360};
    case Kind::Stiffness: return {1e9, 1e10, 1e8, 5e9, 2e9};
    case Kind::Density: return {2000, 2600, 1000, 2500};
    case Kind::Strength: return {0, 1e5, 1e6, 3e5};
    case Kind::Angle: return {30, 0, 20, 40, 45, 10};
    case Kind::Fraction: return {0.25, 0.1, 0.5, 1e-3, 0.9, 0.8};
    case Kind::Dt: return {1e-4, 1e-5, 1e-3};
    case Kind::Time: return {1e-3, 0.01, 1e-4, 0.1};
    case Kind::Velocity: return {0, 0.01, -0.01, 0.1, -1};
    case Kind::Force: return {1000, -1000, 0, 1e5};
    case Kind::Stress: return {-1e6, 0, -1e5, 1e5, -2e6};
    case Kind::Plain: return {1, 0.5, 2, 10, 100};
    }
    return {1};
}

bool within(const ValueSpec& v, double x) {
    if (std::isfinite(v.lo) && (v.lo_kind == Limit::Open ? !(x > v.lo) : !(x >= v.lo))) return false;
    if (std::isfinite(v.hi) && (v.hi_kind == Limit::Open ? !(x < v.hi) : !(x <= v.hi))) return false;
    return true;
}

// Names the generator gives things, so that later commands can find them.
const std::vector<std::string> kGroups = {"g1", "tunnel", "rock", "g2"};
const std::vector<std::string> kVars = {"v1", "v2", "v3"};

struct Function {
    std::string name;
    int args = 0;
};

// Where generated text goes: the script or a called file, with its indentation.
struct Sink {
    std::string* text;
    int indent = 0;
};

class Generator {
public:
    Generator(Choices& c, const CommandTable& table) : c_(c), table_(table) {
        for (const fish::Intrinsic* in : fish::all_intrinsics()) {
            const std::string g = in->group, a = in->args;
            if (in->min_args == 1 && (a == "b" || a == "c" || a == "s" || a == "g" || a == "z")) {
                const char kind = a[0];
                readers_[kind].push_back(in->name);
                if (in->set) writers_[kind].push_back(in->name);
            } else if (in->min_args == 0 && (g == "model" || g == "math")) {
                scalars_.push_back(in->name);
            } else if (g == "math" || g == "vector" || g == "string") {
                functions_.push_back(in);
            }
        }
    }

    GeneratedScript run() {
        GeneratedScript out;
        Sink s{&out.text, 0};
        if (!c_.maybe(20)) prelude(s);
        const std::size_t items = 1 + c_.below(12);
        for (std::size_t i = 0; i < items && out.text.size() < kMaxText && !c_.exhausted(); ++i) body_item(s);
        if (!c_.maybe(30)) line(s, "step " + num(c_.pick({10.0, 20.0, 5.0, 1.0, 40.0})));
        out.files = files_;
        return out;
    }

private:
    static constexpr std::size_t kMaxText = 24 * 1024;

    Choices& c_;
    const CommandTable& table_;
    std::map<char, std::vector<std::string>> readers_, writers_; // by pointer kind
    std::vector<std::string> scalars_;
    std::vector<const fish::Intrinsic*> functions_;
    std::vector<std::pair<std::string, std::string>> files_;
    std::set<std::string> saved_;
    std::vector<std::string> named_ranges_;
    std::vector<Function> functions_defined_;
    int n_functions_ = 0;
    int n_arrays_ = 0;

    // Inside a FISH function: its arguments, loop counters and pointers, innermost last.
    struct Scope {
        bool in_fish = false;
        std::vector<std::string> names;            // numbers: arguments, loop counters
        std::vector<std::pair<char, std::string>> pointers; // 'b', 'c', 's', 'g', 'z'
        int depth = 0;
        int loops = 0; // loops around the statement being written: 'exit loop' needs one
        int runs = 1;  // about how many times the statement runs: loops multiply it
    } scope_;

    // Nested loops multiply: a command block should not run more than about this many times,
    // or one input takes seconds ('gen' forks the mesher each time).
    static constexpr int kMaxRuns = 40;

    void line(Sink& s, const std::string& text) {
        s.text->append(static_cast<std::size_t>(s.indent) * 2, ' ');
        *s.text += text;
        *s.text += '\n';
    }

    // --- values ----------------------------------------------------------------------------

    std::string fish_number_name() {
        // Inside a command block: a FISH global ('@v1') or a loop counter; outside, a global.
        std::vector<std::string> names = kVars;
        if (scope_.in_fish) {
            for (const std::string& n : scope_.names) {
                if (n == "k" || n == "i" || n == "j") names.push_back(n); // loop counters are globals
            }
        }
        return "@" + c_.pick(names);
    }

    // A number outside the ordinary: on a limit, one ulp or one past it, huge, tiny, zero.
    std::string wild_number(const ValueSpec& v) {
        const bool lo = std::isfinite(v.lo), hi = std::isfinite(v.hi);
        switch (c_.below(12)) {
        case 0: return lo ? num(v.lo) : "-1e300";
        case 1: return hi ? num(v.hi) : "1e300";
        case 2: return lo ? exact(std::nextafter(v.lo, -kInf)) : "-1";
        case 3: return hi ? exact(std::nextafter(v.hi, kInf)) : "1e-300";
        case 4: return lo ? num(v.lo - 1) : "-1e9";
        case 5: return hi ? num(v.hi + 1) : "1e9";
        case 6: return c_.pick({"0", "-0", "0.0"});
        case 7: return c_.pick({"1e309", "-1e309", "4.9e-324", "1e-320"});
        case 8: return v.type == ValueType::Int ? c_.pick({"2147483648", "1.5", "-2147483649", "1e10"}) : "1e18";
        case 9: return fish_number_name();
        case 10: return c_.pick({"auto", "x", "'1'", "("});
        default: return lo && hi ? exact(v.lo + (v.hi - v.lo) * c_.byte() / 255.0) : "-1";
        }
    }

    std::string sane_number(const std::string& cmd, const std::string& kw, const ValueSpec& v) {
        const Kind k = kind_of(cmd, kw, v);
        const bool lo = std::isfinite(v.lo), hi = std::isfinite(v.hi);
        // A bounded value that no palette fits (or, sometimes, any bounded value): anywhere inside.
        if (lo && hi && (k == Kind::Plain || c_.maybe(15))) {
            double x = v.lo + (v.hi - v.lo) * c_.byte() / 255.0;
            if (v.type == ValueType::Int) {
                x = std::round(x);
                if (v.hi - v.lo > 100) x = v.lo + c_.pick(palette(Kind::Index)) + 1;
            }
            if (!within(v, x)) x = v.lo + (v.hi - v.lo) / 2;
            return v.type == ValueType::Int ? num(std::round(x)) : num(x);
        }
        const std::vector<double> p = palette(k);
        double x = p[c_.below(p.size())];
        if (!within(v, x)) {
            if (lo && within(v, v.lo + std::fabs(x))) {
                x = v.lo + std::fabs(x);
            } else if (lo && within(v, v.lo + 1)) {
                x = v.lo + 1;
            } else if (hi && within(v, v.hi - std::fabs(x))) {
                x = v.hi - std::fabs(x);
            } else if (lo && hi) {
                x = v.lo + (v.hi - v.lo) / 2;
            }
        }
        if (v.type == ValueType::Int) x = std::round(x);
        return num(x);
    }

    std::string coord() { return num(c_.pick(palette(Kind::Coord))); }

    std::string vec(const std::string& x, const std::string& y, const std::string& z) {
        switch (c_.weighted({6, 3, 1})) {
        case 0: return x + "," + y + "," + z;
        case 1: return "(" + x + "," + y + "," + z + ")";
        default: return x + " " + y + " " + z;
        }
    }

    std::string quoted(const std::string& s) {
        switch (c_.weighted({8, 1, 1})) {
        case 0: return "'" + s + "'";
        case 1: return "\"" + s + "\"";
        default: return s;
        }
    }

    // A file for `call`: made (once) from generated commands, written by the harness.
    std::string call_file(const std::string& name) {
        for (const auto& f : files_) {
            if (f.first == name) return name;
        }
        files_.emplace_back(name, std::string()); // taken now, so that the file may call itself
        const std::size_t slot = files_.size() - 1;
        std::string text;
        Sink s{&text, 0};
        const Scope outer = scope_;
        scope_ = Scope{};
        const std::size_t n = 1 + c_.below(4);
        for (std::size_t i = 0; i < n; ++i) {
            switch (c_.weighted({10, 2, 2, 1, 1})) {
            case 0: line(s, model_command(false)); break;
            case 1: fish_function(s, false); break;
            case 2: line(s, "call " + quoted(name == "part.dat" ? call_file("part2.dat") : c_.pick({std::string("part.dat"), name}))); break;
            case 3: line(s, "return"); break;
            default: line(s, "step " + num(c_.pick({5.0, 1.0, 10.0}))); break;
            }
        }
        scope_ = outer;
        files_[slot].second = text;
        return name;
    }

    std::string string_value(const std::string& cmd, const std::string& kw, bool wild) {
        if (wild && c_.maybe(50)) {
            return quoted(c_.pick({std::string("../up"), std::string("/tmp/odec-abs"), std::string("."), std::string(""),
                                   std::string("nosuch"), std::string("part.dat"), std::string("a/b/c")}));
        }
        if (cmd == "save") {
            const std::string n = c_.pick({std::string("m1"), std::string("m2"), std::string("m1.sav")});
            saved_.insert(n);
            return quoted(n);
        }
        if (cmd == "restore") {
            if (!saved_.empty() && !c_.maybe(10)) {
                std::vector<std::string> names(saved_.begin(), saved_.end());
                return quoted(c_.pick(names));
            }
            return quoted("m1");
        }
        if (cmd == "call") return quoted(call_file(c_.maybe(20) ? "part2.dat" : "part.dat"));
        if (cmd == "table" && kw == "read") {
            if (c_.maybe(70)) {
                bool have = false;
                for (const auto& f : files_) have = have || f.first == "tab.txt";
                if (!have) files_.emplace_back("tab.txt", "0 0\n0.01 1\n0.02 0.5\n");
                return quoted("tab.txt");
            }
            return quoted("part.dat");
        }
        if (cmd == "title") return quoted(c_.pick({std::string("a model"), std::string("x"), std::string("")}));
        return quoted(c_.pick({std::string("out1"), std::string("h.txt"), std::string("p.png"), std::string("log1")}));
    }

    std::string word_value(const std::string& cmd, const std::string& kw) {
        if (cmd == "help") {
            const CommandSpec* c = table_.commands[c_.below(table_.commands.size())];
            return c->name;
        }
        if (cmd == "list" || (cmd == "history" && kw == "fish")) {
            std::vector<std::string> names = kVars;
            for (const Function& f : functions_defined_) names.push_back(f.name);
            return c_.pick(names);
        }
        if (cmd == "range" && kw == "name") {
            const std::string n = c_.pick({std::string("r1"), std::string("r2")});
            if (std::find(named_ranges_.begin(), named_ranges_.end(), n) == named_ranges_.end()) named_ranges_.push_back(n);
            return n;
        }
        if (kw == "nrange") return named_ranges_.empty() ? "r1" : c_.pick(named_ranges_);
        const std::string g = c_.pick(kGroups);
        return c_.maybe(30) ? "'" + g + "'" : g;
    }

    std::string choice_value(const ValueSpec& v) {
        const std::string& w = v.choices[c_.below(v.choices.size())];
        if (c_.maybe(10) && w.size() > 1) return w.substr(0, 1 + c_.below(w.size() - 1));
        if (c_.maybe(3)) {
            std::string u = w;
            for (char& ch : u) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
            return u;
        }
        return w;
    }

    // One value of a keyword; `wild` is the chance in a hundred of an unusual number.
    std::string value(const std::string& cmd, const std::string& kw, const ValueSpec& v, int wild) {
        std::string out;
        if (v.labelled) out = v.name + " ";
        switch (v.type) {
        case ValueType::Int:
        case ValueType::Real:
            if (!v.choices.empty() && c_.maybe(10)) return out + v.choices[c_.below(v.choices.size())];
            if (c_.maybe(wild)) return out + wild_number(v);
            if (scope_.in_fish && c_.maybe(4)) return out + fish_number_name();
            return out + sane_number(cmd, kw, v);
        case ValueType::Vec3: {
            if (c_.maybe(wild)) {
                ValueSpec any;
                return out + vec(coord(), wild_number(any), coord());
            }
            if (kw == "g" || (cmd == "gravity") || kw == "gravity") {
                return out + vec("0", "0", c_.pick({std::string("-10"), std::string("-9.81"), std::string("0")}));
            }
            return out + vec(coord(), coord(), coord());
        }
        case ValueType::String: return out + string_value(cmd, kw, c_.maybe(wild));
        case ValueType::Word: return out + word_value(cmd, kw);
        case ValueType::Choice: return out + choice_value(v);
        }
        return out;
    }

    // The values of a keyword (or of a command's positional values), as its declaration says.
    std::string values(const std::string& cmd, const KeywordSpec& k, int wild) {
        std::string out;
        for (const ValueSpec& v : k.values) {
            if (v.optional && c_.maybe(40)) continue;
            out += " " + value(cmd, k.name, v, wild);
        }
        if (k.repeat_last && !k.values.empty()) {
            const std::size_t more = c_.below(3);
            for (std::size_t i = 0; i < more; ++i) out += " " + value(cmd, k.name, k.values.back(), wild);
        }
        return out;
    }

    // A keyword as a person types it: whole, cut to its shortest form, or in capitals.
    std::string spelled(const std::string& name, int min) {
        switch (c_.weighted({40, 6, 2, 1})) {
        case 0: return name;
        case 1: return name.substr(0, static_cast<std::size_t>(std::max(1, std::min<int>(min, static_cast<int>(name.size())))));
        case 2: {
            std::string u = name;
            for (char& ch : u) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
            return u;
        }
        default: return name.substr(0, 1 + c_.below(name.size())); // maybe too short, maybe ambiguous
        }
    }

    // The range phrase: one to three filters, the word 'range' itself sometimes left out.
    std::string range_phrase(int wild) {
        const auto& filters = range_filters();
        std::string out = c_.maybe(10) ? "" : "range";
        auto add = [&out](const std::string& w) { out += (out.empty() ? "" : " ") + w; };
        const std::size_t n = 1 + c_.weighted({6, 3, 1});
        for (std::size_t i = 0; i < n; ++i) {
            if (c_.maybe(10)) add("not");
            const KeywordSpec* f = nullptr;
            // Mostly the filters that select by position, region, group and id.
            static const char* const common[] = {"z", "x", "y", "region", "group", "id", "sphere", "plane"};
            if (c_.maybe(75)) {
                const std::string want = common[c_.below(sizeof common / sizeof common[0])];
                for (const KeywordSpec& k : filters) {
                    if (k.name == want) f = &k;
                }
            }
            if (!f) f = &filters[c_.below(filters.size())];
            if (f->name == "not" || f->name == "union") {
                add(f->name);
                continue;
            }
            add(spelled(f->name, f->min));
            if (f->name == "x" || f->name == "y" || f->name == "z" || f->name == "xr" || f->name == "yr" ||
                f->name == "zr") {
                // An interval that holds something more often than not: lo below hi.
                const double lo = c_.pick({0.0, -0.5, 0.5, 0.25, -1.0, 0.9});
                const double hi = lo + c_.pick({1.0, 0.5, 0.1, 2.0, 0.001});
                out += c_.maybe(wild) ? " " + num(hi) + " " + wild_number(f->values[0]) : " " + num(lo) + " " + num(hi);
                continue;
            }
            if (f->name == "nrange" || f->name == "group") {
                out += " " + word_value("range", f->name);
                continue;
            }
            out += values("range", *f, wild);
        }
        return out;
    }

    // --- commands from the declarations ------------------------------------------------------

    const CommandSpec* spec(const std::string& name) const { return table_.find(name); }

    std::string verb(const CommandSpec& c) {
        switch (c_.weighted({30, 3, 2})) {
        case 0: return c.name;
        case 1: return c.aliases.empty() ? c.name : c_.pick(c.aliases);
        default: return c.name.substr(0, static_cast<std::size_t>(std::max(1, c.min)));
        }
    }

    // `kw values` (or `kw=value` for a keyword of one value, as `prop mat=1` is written).
    std::string keyword(const CommandSpec& c, const KeywordSpec& k, int wild) {
        if (k.is_range) return range_phrase(wild);
        std::string w = spelled(k.name, k.min);
        if (!k.rest_of.empty()) {
            // Words that belong to another command (`set plot ...` -> `plot set ...`) or to the handler.
            const CommandSpec* other = k.rest_of == "*" ? &c : spec(k.rest_of);
            if (other && !other->keywords.empty()) {
                const KeywordSpec& o = other->keywords[c_.below(other->keywords.size())];
                if (!o.is_range && o.rest_of.empty()) w += " " + o.name + values(other->name, o, wild);
            }
            return w;
        }
        const std::string vals = values(c.name, k, wild);
        if (k.values.size() == 1 && !k.repeat_last && !k.values[0].labelled && !vals.empty() && c_.maybe(15)) {
            return w + "=" + vals.substr(1);
        }
        return w + vals;
    }

    // A command of the declarations with the keywords named (those the declarations lack
    // are left out); each value by its declaration.
    std::string command(const std::string& name, const std::vector<std::string>& keywords, int wild = 5) {
        const CommandSpec* c = spec(name);
        if (!c) return "; no command '" + name + "'";
        std::string out = verb(*c) + values(c->name, c->positional, wild);
        for (const std::string& k : keywords) {
            const KeywordSpec* ks = c->find_keyword(k);
            if (ks) out += " " + keyword(*c, *ks, wild);
        }
        return out;
    }

    // Any command, any keywords: what the declarations allow, and a little more.
    std::string wild_command() {
        const CommandSpec& c = *table_.commands[c_.below(table_.commands.size())];
        if (c.name == "quit" && !c_.maybe(5)) return "print info";
        std::string out = verb(c) + values(c.name, c.positional, 25);
        const std::size_t n = c.keywords.empty() ? 0 : c_.below(5);
        std::set<int> groups;
        std::set<const KeywordSpec*> used;
        for (std::size_t i = 0; i < n; ++i) {
            const KeywordSpec& k = c.keywords[c_.below(c.keywords.size())];
            // Keep to one of each choice group, and each keyword once, mostly.
            if (k.choice != 0 && groups.count(k.choice) && !c_.maybe(10)) continue;
            if (used.count(&k) && !k.repeatable && !c_.maybe(10)) continue;
            groups.insert(k.choice);
            used.insert(&k);
            out += " " + keyword(c, k, 25);
        }
        // A required choice left out: add one, mostly.
        for (int g : c.required_choices) {
            if (groups.count(g) || c_.maybe(10)) continue;
            std::vector<const KeywordSpec*> in_group;
            for (const KeywordSpec& k : c.keywords) {
                if (k.choice == g) in_group.push_back(&k);
            }
            if (!in_group.empty()) out += " " + keyword(c, *c_.pick(in_group), 25);
        }
        return out;
    }

    std::string brick() {
        const double x1 = c_.pick({0.0, 0.0, -0.5, 1.0, 0.25});
        const double y1 = c_.pick({0.0, 0.0, -0.5, 1.0, 0.25});
        const double z1 = c_.pick({1.0, 0.0, 0.5, -0.5, 2.0});
        const double dx = c_.pick({1.0, 0.5, 0.25, 2.0});
        const double dy = c_.pick({1.0, 0.5, 0.25, 2.0});
        const double dz = c_.pick({0.5, 1.0, 0.25, 0.1});
        return "brick " + num(x1) + " " + num(x1 + dx) + " " + num(y1) + " " + num(y1 + dy) + " " + num(z1) + " " +
               num(z1 + dz);
    }

    std::string tetra() {
        const double x = c_.pick({0.0, 1.0, 0.5}), y = c_.pick({0.0, 1.0, 0.5}), z = c_.pick({1.0, 0.0, 2.0});
        const double s = c_.pick({0.5, 1.0, 0.25});
        std::vector<std::string> p = {vec(num(x), num(y), num(z)), vec(num(x + s), num(y), num(z)),
                                      vec(num(x), num(y + s), num(z)), vec(num(x), num(y), num(z + s))};
        if (c_.maybe(20)) std::swap(p[1], p[2]);
        if (c_.maybe(5)) p[3] = p[0]; // flat
        return "tetra " + p[0] + " " + p[1] + " " + p[2] + " " + p[3];
    }

    std::string prism() {
        const double y0 = c_.pick({0.0, 1.0, -0.5}), y1 = y0 + c_.pick({1.0, 0.5});
        const double x = c_.pick({0.0, 0.5}), z = c_.pick({1.0, 0.0}), s = c_.pick({1.0, 0.5});
        auto end = [&](double y) {
            std::string out = vec(num(x), num(y), num(z)) + " " + vec(num(x + s), num(y), num(z)) + " ";
            if (c_.maybe(50)) out += vec(num(x + s), num(y), num(z + s)) + " ";
            return out + vec(num(x), num(y), num(z + s));
        };
        return "prism a " + end(y0) + " b " + end(y1);
    }

    // A tunnel's axis: across the model along y or x, or by length along a direction.
    std::string axis() {
        if (c_.maybe(25)) {
            return "dip " + num(c_.pick({0.0, 30.0, 90.0})) + " dd " + num(c_.pick({0.0, 90.0})) + " origin " +
                   vec("0.5", "0.5", "0.5") + " length -1 1";
        }
        const std::string m = num(c_.pick({0.5, 0.0, 0.25}));
        return c_.maybe(30) ? "a " + vec("-1", m, m) + " b " + vec("2", m, m) : "a " + vec(m, "-1", m) + " b " + vec(m, "2", m);
    }

    std::string ring_pattern(bool box) {
        std::string out = " radius " + num(c_.pick({0.2, 0.3, 0.1, 0.4}));
        if (box) out += " box " + num(c_.pick({1.0, 0.8, 1.5}));
        else if (c_.maybe(60)) out += " outer " + num(c_.pick({0.6, 0.45, 0.9}));
        out += " ntheta " + num(c_.pick({4.0, 8.0, 3.0, 6.0}));
        out += " nrad " + num(c_.pick({1.0, 2.0}));
        if (c_.maybe(40)) out += " nseg " + num(c_.pick({2.0, 1.0, 3.0}));
        if (c_.maybe(20)) out += " ratio " + num(c_.pick({1.5, 1.2, 0.8}));
        return out;
    }

    std::string poly() {
        std::string out = verb(*spec("poly")) + " ";
        switch (c_.weighted({10, 2, 3, 3, 1})) {
        case 0: out += brick(); break;
        case 1: out += tetra(); break;
        case 2: out += prism(); break;
        case 3: return out + "tunnel " + axis() + ring_pattern(true);
        default: return wild_command();
        }
        if (c_.maybe(30)) out += " region " + num(c_.pick({2.0, 1.0, 3.0}));
        if (c_.maybe(15)) out += " group " + c_.pick(kGroups);
        if (c_.maybe(10)) out += " mat " + num(c_.pick({1.0, 2.0}));
        return out;
    }

    std::string jset() {
        std::vector<std::string> k = {"dip", "dd"};
        if (!c_.maybe(15)) k.push_back("origin");
        if (c_.maybe(40)) {
            k.push_back("spacing");
            k.push_back("number");
        }
        if (c_.maybe(15)) k.push_back("join");
        if (c_.maybe(15)) k.push_back("jmat");
        if (c_.maybe(10)) {
            k.push_back("persistence");
            k.push_back("seed");
        }
        if (c_.maybe(25)) k.push_back("range");
        return command("jset", k);
    }

    std::string tunnel() {
        std::string out = verb(*spec("tunnel")) + " " + axis() + ring_pattern(false);
        if (c_.maybe(15)) out += " group " + c_.pick(kGroups);
        if (c_.maybe(20)) out += " " + range_phrase(5);
        return out;
    }

    std::string generate() {
        if (c_.maybe(15)) {
            return command("generate", {"model", "density", "bulk", "shear", "friction", "cohesion", "tension"});
        }
        // Coarse zones, so that a run stays quick: a 1 m block makes tens of zones.
        std::string out = verb(*spec("generate")) + " edge " + num(c_.pick({0.5, 0.7, 1.0, 0.4}));
        if (c_.maybe(25)) out += " " + range_phrase(5);
        return out;
    }

    std::string prop() {
        if (c_.maybe(50)) {
            std::vector<std::string> k = {"material"};
            for (const char* p : {"density", "ymod", "prat", "cohesion", "friction", "tension", "bulk", "shear"}) {
                if (c_.maybe(35)) k.push_back(p);
            }
            return command("property", k);
        }
        std::vector<std::string> k = {"jmat"};
        for (const char* p : {"jkn", "jks", "jfriction", "jcohesion", "jtension", "jdilation", "jres_friction"}) {
            if (c_.maybe(35)) k.push_back(p);
        }
        return command("property", k);
    }

    // One command that builds, changes or looks at the model: what FISH command blocks and
    // called files hold, and most of the script's own commands.
    std::string model_command(bool allow_wild = true) {
        // Weights: 'gen' forks the mesher, which costs more than most whole scripts.
        switch (c_.weighted({12, 10, 4, 2, 5, 5, 2, 5, 5, 5, 5, 4, 3, 3, 3, 3, 2, 2, 2, 2, 2, 2, 2, 2, 1, 1, 6})) {
        case 0: return jset();
        case 1: return poly(); // in a walk over the blocks, until the session's block bound
        case 2: return tunnel();
        // Each 'gen' forks the mesher: within the session's zone bound a loop of them can
        // still take seconds, so only where the block runs a few times.
        case 3: return scope_.runs > 4 ? jset() : generate();
        case 4: return command("delete", {"range"});
        case 5: return command("excavate", {"range"});
        case 6: return command("fill", c_.maybe(50) ? std::vector<std::string>{"range"} : std::vector<std::string>{});
        case 7: return "new";
        case 8: return saved_.empty() && !c_.maybe(10) ? command("save", {}) : command("restore", {});
        case 9: return command("save", {});
        case 10: return command("call", {});
        case 11: return prop();
        case 12: return command("change", {c_.pick({std::string("jmat"), std::string("material"), std::string("cons"),
                                                     std::string("jcons")}), "range"});
        case 13: return command(c_.maybe(70) ? "fix" : "free", c_.maybe(80) ? std::vector<std::string>{"range"} : std::vector<std::string>{});
        case 14: return "step " + num(c_.pick({5.0, 1.0, 10.0, 2.0}));
        case 15: return command("print", {c_.pick({std::string("info"), std::string("max"), std::string("block"),
                                                   std::string("contact"), std::string("zone"), std::string("gp")})});
        case 16: return command("history", {c_.pick({std::string("unbalanced"), std::string("zdisplacement"),
                                                     std::string("xvelocity"), std::string("fish"), std::string("ncyc"),
                                                     std::string("nstress"), std::string("szz")})});
        case 17: return command("boundary", {c_.pick({std::string("zvelocity"), std::string("xload"), std::string("stress"),
                                                      std::string("zgrad")}), "range"});
        case 18: return command("initial", {c_.pick({std::string("xvel"), std::string("zvel")}), "range"});
        case 19: return command("group", {"range"});
        case 20: return command(c_.pick({std::string("hide"), std::string("show"), std::string("join")}), {"range"});
        case 21: return command("seek", {});
        case 22: return command("set", {c_.pick({std::string("dt"), std::string("jmat"), std::string("large"),
                                                 std::string("small"), std::string("dtfrac"), std::string("ctol"),
                                                 std::string("gravity"), std::string("jcons")})});
        case 23: return command("damping", {c_.pick({std::string("local"), std::string("auto"), std::string("off"),
                                                     std::string("mass")})});
        case 24: return command("solve", c_.maybe(50) ? std::vector<std::string>{"ratio", "cycles"} : std::vector<std::string>{"cycles"});
        case 25: return command("insitu", {c_.pick({std::string("stress"), std::string("zgrad")})});
        default: return allow_wild ? wild_command() : command("print", {"info"});
        }
    }

    // --- FISH ----------------------------------------------------------------------------------

    std::string fish_scalar_expr(int depth) {
        const int pointers = static_cast<int>(scope_.pointers.size());
        switch (depth <= 0 ? c_.below(4) : c_.weighted({4, 2, 3, 2, 2, 4, 2, 1, 1})) {
        case 0: return num(c_.pick({1.0, 0.0, 2.0, 3.0, 10.0, 0.5, -1.0, 1e-3, 2000.0}));
        case 1: return c_.pick(kVars);
        case 2:
            if (!scope_.names.empty()) return c_.pick(scope_.names);
            return c_.pick(kVars);
        case 3:
            if (pointers > 0) {
                const auto& p = scope_.pointers[c_.below(scope_.pointers.size())];
                const auto& r = readers_[p.first];
                if (!r.empty()) return c_.pick(r) + "(" + p.second + ")";
            }
            return scalars_.empty() ? "nblock" : c_.pick(scalars_);
        case 4: return scalars_.empty() ? "nblock" : c_.pick(scalars_);
        case 5:
            return fish_scalar_expr(depth - 1) + " " + c_.pick({"+", "-", "*", "/", "^", "+"}) + " " +
                   fish_scalar_expr(depth - 1);
        case 6: {
            if (functions_.empty()) return "1";
            const fish::Intrinsic* f = c_.pick(functions_);
            std::string out = std::string(f->name) + "(";
            const int n = f->max_args > f->min_args && c_.maybe(30) ? f->max_args : f->min_args;
            // The vector intrinsics take vectors (all but 'vector' itself, which makes one).
            const bool vectors = std::string(f->group) == "vector" && std::string(f->name) != "vector";
            for (int i = 0; i < n; ++i) out += (i ? ", " : "") + (vectors ? fish_vector_expr() : fish_scalar_expr(depth - 1));
            return out + ")";
        }
        case 7: return "(" + fish_scalar_expr(depth - 1) + ")";
        default: {
            // A function defined before, by name (called) or with its arguments.
            if (functions_defined_.empty()) return "-" + fish_scalar_expr(depth - 1);
            const Function& f = c_.pick(functions_defined_);
            if (f.args == 0) return f.name;
            std::string out = f.name + "(";
            for (int i = 0; i < f.args; ++i) out += (i ? ", " : "") + fish_scalar_expr(0);
            return out + ")";
        }
        }
    }

    std::string fish_vector_expr() {
        for (const auto& p : scope_.pointers) {
            if (c_.maybe(50)) {
                switch (p.first) {
                case 'b': return "b_pos(" + p.second + ")";
                case 'c': return "c_n(" + p.second + ")";
                case 'g': return "gp_pos(" + p.second + ")";
                case 'z': return "z_pos(" + p.second + ")";
                default: break;
                }
            }
        }
        switch (c_.below(3)) {
        case 0: return "vector(" + fish_scalar_expr(0) + ", " + fish_scalar_expr(0) + ", " + fish_scalar_expr(0) + ")";
        case 1: return "gravity";
        default: return "vector(1, 0, 0)";
        }
    }

    std::string fish_condition() {
        std::string out = fish_scalar_expr(1) + " " + c_.pick({"<", ">", "=", "#", "<=", ">="}) + " " + fish_scalar_expr(1);
        if (c_.maybe(15)) out += " " + std::string(c_.pick({"&", "|"})) + " " + fish_scalar_expr(0) + " > 0";
        return out;
    }

    void command_block(Sink& s) {
        line(s, "command");
        ++s.indent;
        const std::size_t n = 1 + c_.weighted({6, 3, 1});
        for (std::size_t i = 0; i < n && (i == 0 || !c_.exhausted()); ++i) line(s, model_command());
        --s.indent;
        line(s, "endcommand");
    }

    // A walk over the blocks (contacts, gridpoints, zones, a contact's sub-contacts).
    void walk(Sink& s, int depth) {
        struct W { char kind; const char* head; const char* next; };
        static const W walks[] = {{'b', "block_head", "b_next"}, {'c', "contact_head", "c_next"},
                                  {'g', "gp_head", "gp_next"}, {'z', "zone_head", "z_next"}};
        const W* w = &walks[c_.weighted({6, 4, 1, 1})];
        std::string head = w->head;
        char kind = w->kind;
        const char* next = w->next;
        // The sub-contacts of a contact being walked.
        for (const auto& p : scope_.pointers) {
            if (p.first == 'c' && c_.maybe(40)) {
                head = "c_cx(" + p.second + ")";
                kind = 's';
                next = "cx_next";
                break;
            }
        }
        const std::string name = std::string(1, kind) + "p" + std::to_string(scope_.depth);
        line(s, "local " + name + " = " + head);
        line(s, "loop while " + name + " # 0");
        ++s.indent;
        scope_.pointers.emplace_back(kind, name);
        ++scope_.loops;
        const int runs = scope_.runs;
        scope_.runs = std::min(kMaxRuns, runs * 10); // tens of blocks, contacts or zones
        const auto& wr = writers_[kind];
        if (!wr.empty() && c_.maybe(40)) line(s, c_.pick(wr) + "(" + name + ") = " + fish_scalar_expr(1));
        fish_block(s, depth - 1, 1 + c_.below(2));
        scope_.runs = runs;
        --scope_.loops;
        scope_.pointers.pop_back();
        line(s, name + " = " + next + "(" + name + ")");
        --s.indent;
        line(s, "endloop");
    }

    void fish_statement(Sink& s, int depth) {
        const bool deeper = depth > 0;
        switch (c_.weighted({8, deeper ? 6 : 0, deeper ? 6 : 0, deeper ? 2 : 0, deeper ? 4 : 0, 10, deeper ? 2 : 0,
                             deeper ? 1 : 0, 2, 2, 1, 1, 1})) {
        case 0: line(s, c_.pick(kVars) + " = " + fish_scalar_expr(2)); break;
        case 1: {
            line(s, "if " + fish_condition() + (c_.maybe(80) ? " then" : ""));
            ++s.indent;
            fish_block(s, depth - 1, 1 + c_.below(2));
            --s.indent;
            if (c_.maybe(30)) {
                line(s, "else");
                ++s.indent;
                fish_block(s, depth - 1, 1);
                --s.indent;
            }
            line(s, "endif");
            break;
        }
        case 2: {
            const std::string k = c_.pick({std::string("k"), std::string("i"), std::string("j")});
            const int n = std::min(static_cast<int>(c_.pick({3.0, 2.0, 1.0, 5.0, 20.0, 10.0, 0.0})),
                                   std::max(1, kMaxRuns / scope_.runs));
            // A global as the bound (as scripts write it) only where it cannot multiply much.
            const std::string to = scope_.runs == 1 && c_.maybe(10) ? c_.pick(kVars) : num(n);
            line(s, "loop " + k + " (1, " + to + ")");
            ++s.indent;
            scope_.names.push_back(k);
            ++scope_.loops;
            const int runs = scope_.runs;
            scope_.runs = std::min(kMaxRuns, runs * std::max(n, 1));
            fish_block(s, depth - 1, 1 + c_.below(3));
            scope_.runs = runs;
            --scope_.loops;
            scope_.names.pop_back();
            --s.indent;
            line(s, "endloop");
            break;
        }
        case 3: {
            const std::string w = "w" + std::to_string(scope_.depth);
            line(s, w + " = 0");
            line(s, "loop while " + w + " < " + num(c_.pick({3.0, 2.0, 10.0})));
            ++s.indent;
            line(s, w + " = " + w + " + 1");
            ++scope_.loops;
            const int runs = scope_.runs;
            scope_.runs = std::min(kMaxRuns, runs * 3);
            fish_block(s, depth - 1, 1 + c_.below(2));
            scope_.runs = runs;
            --scope_.loops;
            if (c_.maybe(20)) {
                line(s, "if " + w + " = 2 then");
                line(s, "  exit loop");
                line(s, "endif");
            }
            --s.indent;
            line(s, "endloop");
            break;
        }
        case 4: walk(s, depth); break;
        case 5: command_block(s); break;
        case 6: {
            line(s, "caseof int(" + fish_scalar_expr(1) + ")");
            ++s.indent;
            fish_block(s, 0, 1);
            --s.indent;
            const std::size_t n = 1 + c_.below(3);
            for (std::size_t i = 0; i < n; ++i) {
                line(s, "case " + num(static_cast<double>(i)));
                ++s.indent;
                fish_block(s, depth - 1, 1);
                --s.indent;
            }
            line(s, "endcase");
            break;
        }
        case 7: {
            line(s, "section");
            ++s.indent;
            fish_block(s, depth - 1, 1);
            line(s, "if " + fish_condition() + " then");
            line(s, "  exit section");
            line(s, "endif");
            fish_block(s, depth - 1, 1);
            --s.indent;
            line(s, "endsection");
            break;
        }
        case 8: {
            const std::string a = "arr" + std::to_string(++n_arrays_ % 3);
            const int n = static_cast<int>(c_.pick({3.0, 1.0, 10.0}));
            line(s, "array " + a + "(" + num(n) + ")");
            line(s, a + "(" + num(1 + static_cast<double>(c_.below(static_cast<std::size_t>(n) + 1))) + ") = " +
                        fish_scalar_expr(1));
            if (c_.maybe(30)) line(s, c_.pick(kVars) + " = " + a + "(1)");
            break;
        }
        case 9: line(s, "v9 = out('v = ' + string(" + fish_scalar_expr(1) + "))"); break;
        case 10: line(s, scope_.loops > 0 && c_.maybe(50) ? "exit loop" : c_.pick({"exit", "return"})); break;
        case 11: line(s, "error = 'stopped by the script'"); break;
        default:
            line(s, "v9 = open('io.txt', 1, 1)");
            line(s, "array lines(2)");
            line(s, "lines(1) = 'poly brick 0 1 0 1 2 3'");
            line(s, "v9 = write(lines, " + num(c_.pick({1.0, 2.0, 3.0})) + ")");
            line(s, "v9 = close");
            break;
        }
    }

    void fish_block(Sink& s, int depth, std::size_t n) {
        ++scope_.depth;
        for (std::size_t i = 0; i < n && (i == 0 || !c_.exhausted()); ++i) fish_statement(s, depth);
        --scope_.depth;
    }

    // `def f ... end`, then (mostly) a call of it. A `whilestepping` function runs at every
    // step from then on; its command block usually runs at a few steps only.
    void fish_function(Sink& s, bool stepping) {
        const std::string name = (stepping ? "ws" : "f") + std::to_string(++n_functions_);
        const int args = !stepping && c_.maybe(20) ? 2 : 0;
        line(s, "def " + name + (args ? "(a, b)" : ""));
        ++s.indent;
        const Scope outer = scope_;
        scope_.in_fish = true;
        if (args) {
            scope_.names.push_back("a");
            scope_.names.push_back("b");
        }
        if (stepping) {
            line(s, "whilestepping");
            switch (c_.weighted({5, 3, 2, 2})) {
            case 0:
                line(s, "if step = " + num(c_.pick({3.0, 1.0, 5.0, 2.0, 10.0})) + " then");
                ++s.indent;
                command_block(s);
                --s.indent;
                line(s, "endif");
                break;
            case 1: command_block(s); break;
            case 2:
                line(s, "if step > " + num(c_.pick({3.0, 1.0, 5.0})) + " then");
                ++s.indent;
                fish_block(s, 2, 1 + c_.below(2));
                --s.indent;
                line(s, "endif");
                break;
            default: fish_block(s, 2, 1 + c_.below(3)); break;
            }
        } else {
            fish_block(s, 3, 1 + c_.below(4));
        }
        if (c_.maybe(30)) line(s, name + " = " + fish_scalar_expr(1));
        scope_ = outer;
        --s.indent;
        line(s, "end");
        functions_defined_.push_back(Function{name, args});
        if (stepping) return;
        switch (c_.weighted({7, 1, 1, 1})) {
        case 0: line(s, "@" + name + (args ? "(" + num(c_.pick({1.0, 0.5, 3.0})) + ", 2)" : "")); break;
        case 1: line(s, args ? "@v1 = " + name + "(1, 2)" : name); break; // UDEC calls a function by its name alone
        case 2: line(s, "hist @" + name); break;
        default: break;
        }
    }

    void fish_top_statement(Sink& s) {
        switch (c_.weighted({4, 2, 2, 1, 1})) {
        case 0: line(s, "@" + c_.pick(kVars) + " = " + fish_scalar_expr(2)); break;
        case 1: line(s, "set " + c_.pick(kVars) + " = " + num(c_.pick({1.0, 0.5, 2.0})) + " v2 = " + coord()); break;
        case 2: line(s, "hist " + std::string(c_.maybe(50) ? "@" : "") + c_.pick(kVars)); break;
        case 3: line(s, "list " + std::string(c_.maybe(50) ? "@" + c_.pick(kVars) : "")); break;
        default: line(s, "@" + c_.pick(kVars) + " = " + c_.pick(scalars_.empty() ? kVars : scalars_)); break;
        }
    }

    // --- the script ----------------------------------------------------------------------------

    // A small model most scripts start from: blocks on a joint, properties, gravity.
    void prelude(Sink& s) {
        const std::size_t shape = c_.weighted({7, 6, 4, 2, 1});
        bool base = false;
        switch (shape) {
        case 0:
            line(s, "poly brick 0 1 0 1 0 1");
            if (!c_.maybe(30)) line(s, "set dt 1e-4"); // a lone block has no contact to set it
            break;
        case 1:
            line(s, "poly brick 0 1 0 1 0 0.5");
            line(s, "poly brick 0 1 0 1 0.5 1");
            break;
        case 2:
            line(s, "poly brick -0.5 1.5 -0.5 1.5 -0.5 0 region 1");
            line(s, "poly brick 0 1 0 1 0 1 region 2");
            base = true;
            break;
        case 3: line(s, "poly tunnel a (0.5,0,0.5) b (0.5,1,0.5) radius 0.2 box 0.5 ntheta 4 nrad 1"); break;
        default: line(s, "poly " + prism()); break;
        }
        if (c_.maybe(35)) {
            std::string j = "jset dip " + num(c_.pick({45.0, 0.0, 90.0, 30.0, 60.0})) + " dd " +
                            num(c_.pick({90.0, 0.0, 180.0, 45.0})) + " origin " + vec("0.5", "0.5", "0.5");
            if (c_.maybe(30)) j += " spacing " + num(c_.pick({0.5, 0.3})) + " number " + num(c_.pick({2.0, 3.0}));
            if (c_.maybe(15)) j += " join";
            line(s, j);
        }
        const bool zoned = c_.maybe(12);
        std::string mat = "prop mat=1 dens=" + num(c_.pick({2000.0, 2600.0}));
        if (zoned || c_.maybe(20)) mat += " ymod=1e9 prat=0.25";
        if (c_.maybe(15)) mat += " coh=1e5 fric=30 ten=1e4";
        line(s, mat);
        std::string jmat = "prop jmat=1 jkn=1e9 jks=1e9 jfric=" + num(c_.pick({30.0, 20.0, 40.0}));
        if (c_.maybe(20)) jmat += " jcoh=1e4 jten=1e3";
        line(s, jmat);
        if (!c_.maybe(5)) line(s, "grav 0 0 -10");
        if (zoned) {
            if (c_.maybe(30)) line(s, "change cons=2");
            line(s, "gen edge " + num(c_.pick({0.5, 0.7, 1.0})));
        }
        if (base) line(s, "fix range region 1");
        else if (c_.maybe(20)) line(s, "fix range z 0 0.3");
        if (c_.maybe(20)) line(s, c_.pick({std::string("hist unbal"), std::string("hist zdis 0.5,0.5,1"),
                                           std::string("hist ncyc 5")}));
        if (c_.maybe(15)) {
            line(s, "save 'm0'");
            saved_.insert("m0");
        }
    }

    void body_item(Sink& s) {
        switch (c_.weighted({22, 8, 14, 8, 10, 4, 3, 6, 2, 1})) {
        case 0: line(s, model_command()); break;
        case 1: line(s, wild_command()); break;
        case 2: fish_function(s, false); break;
        case 3: fish_function(s, true); break;
        case 4: line(s, "step " + num(c_.pick({10.0, 5.0, 20.0, 1.0, 2.0}))); break;
        case 5: {
            const std::string n = c_.pick({std::string("m1"), std::string("m2")});
            line(s, "save '" + n + "'");
            saved_.insert(n);
            if (c_.maybe(50)) line(s, model_command(false));
            line(s, "restore '" + n + "'");
            break;
        }
        case 6: line(s, command("call", {})); break;
        case 7: fish_top_statement(s); break;
        case 8: line(s, command("range", {"name", "range"})); break;
        default: line(s, "new"); break;
        }
    }
};

} // namespace

GeneratedScript generate_script(const std::uint8_t* choices, std::size_t size, const CommandTable& table) {
    Choices c(choices, size);
    Generator g(c, table);
    return g.run();
}

std::string printable(const GeneratedScript& g) {
    std::string out;
    for (const auto& f : g.files) {
        out += "; file '" + f.first + "', written before the script runs:\n";
        std::size_t at = 0;
        while (at < f.second.size()) {
            std::size_t nl = f.second.find('\n', at);
            if (nl == std::string::npos) nl = f.second.size();
            out += ";   " + f.second.substr(at, nl - at) + "\n";
            at = nl + 1;
        }
    }
    return out + g.text;
}

} // namespace odec::fuzz
