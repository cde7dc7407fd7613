#include "lang/decl.h"

#include <cmath>
#include <sstream>

namespace odec {

namespace {

std::string fmt_num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

ValueSpec make_value(std::string n, ValueType t) {
    ValueSpec v;
    v.name = std::move(n);
    v.type = t;
    return v;
}

std::string value_synopsis(const ValueSpec& v) {
    std::string s = v.type == ValueType::Choice ? "" : v.name;
    if (v.type == ValueType::Choice) {
        for (size_t k = 0; k < v.choices.size(); ++k) s += (k ? "|" : "") + v.choices[k];
    }
    if (v.type == ValueType::Real) {
        for (const auto& w : v.choices) s += "|" + w;
    }
    if (v.type == ValueType::Vec3) s = (v.labelled || v.name == "x,y,z") ? "x,y,z" : v.name + "(x,y,z)";
    if (v.labelled) s = v.name + " " + (v.type == ValueType::Vec3 ? s : std::string("v"));
    return v.optional ? "[" + s + "]" : s;
}

} // namespace

const char* type_name(ValueType t) {
    switch (t) {
    case ValueType::Int: return "an integer";
    case ValueType::Real: return "a number";
    case ValueType::Vec3: return "a vector x,y,z";
    case ValueType::String: return "a string";
    case ValueType::Word: return "a name";
    case ValueType::Choice: return "a word";
    }
    return "a value";
}

std::string describe_limits(const ValueSpec& v) {
    const bool has_lo = std::isfinite(v.lo), has_hi = std::isfinite(v.hi);
    if (has_lo && has_hi) {
        if (v.lo_kind == Limit::Closed && v.hi_kind == Limit::Closed) return fmt_num(v.lo) + " to " + fmt_num(v.hi);
        return std::string(v.lo_kind == Limit::Open ? "> " : ">= ") + fmt_num(v.lo) +
               (v.hi_kind == Limit::Open ? " and < " : " and <= ") + fmt_num(v.hi);
    }
    if (has_lo) return std::string(v.lo_kind == Limit::Open ? "> " : ">= ") + fmt_num(v.lo);
    if (has_hi) return std::string(v.hi_kind == Limit::Open ? "< " : "<= ") + fmt_num(v.hi);
    return "";
}

KeywordSpec& KeywordSpec::integer(std::string n, double lo, double hi) {
    ValueSpec v = make_value(std::move(n), ValueType::Int);
    v.lo = lo;
    v.hi = hi;
    values.push_back(v);
    return *this;
}

KeywordSpec& KeywordSpec::real(std::string n, double lo, double hi, Limit lo_kind, Limit hi_kind) {
    ValueSpec v = make_value(std::move(n), ValueType::Real);
    v.lo = lo;
    v.hi = hi;
    v.lo_kind = lo_kind;
    v.hi_kind = hi_kind;
    values.push_back(v);
    return *this;
}

KeywordSpec& KeywordSpec::vec(std::string n) {
    values.push_back(make_value(std::move(n), ValueType::Vec3));
    return *this;
}

KeywordSpec& KeywordSpec::string(std::string n) {
    values.push_back(make_value(std::move(n), ValueType::String));
    return *this;
}

KeywordSpec& KeywordSpec::word(std::string n) {
    values.push_back(make_value(std::move(n), ValueType::Word));
    return *this;
}

KeywordSpec& KeywordSpec::one_of(std::string n, std::vector<std::string> words) {
    ValueSpec v = make_value(std::move(n), ValueType::Choice);
    v.choices = std::move(words);
    values.push_back(v);
    return *this;
}

KeywordSpec& KeywordSpec::or_word(std::string word) {
    values.back().choices.push_back(std::move(word));
    return *this;
}

KeywordSpec& KeywordSpec::optional(std::string default_value) {
    values.back().optional = true;
    values.back().default_text = std::move(default_value);
    return *this;
}

KeywordSpec& KeywordSpec::labelled() {
    values.back().labelled = true;
    return *this;
}

KeywordSpec& KeywordSpec::repeat() {
    repeat_last = true;
    return *this;
}

KeywordSpec& KeywordSpec::many() {
    repeatable = true;
    return *this;
}

KeywordSpec& KeywordSpec::in_choice(int group) {
    choice = group;
    return *this;
}

KeywordSpec& KeywordSpec::forward_to(std::string command) {
    rest_of = std::move(command);
    return *this;
}

KeywordSpec& KeywordSpec::rest_as_words() {
    rest_of = "*";
    return *this;
}

KeywordSpec& KeywordSpec::defaults(std::string text) {
    default_text = std::move(text);
    return *this;
}

std::string KeywordSpec::synopsis() const {
    std::string s = name;
    if (is_range) return s + " <filters>";
    if (rest_of == "*") return s + " ...";
    if (!rest_of.empty()) return s + " <" + rest_of + " options>";
    for (const ValueSpec& v : values) s += " " + value_synopsis(v);
    if (repeat_last) s += " ...";
    return s;
}

CommandSpec::CommandSpec(std::string n, int min_abbrev, std::string one_line)
    : name(std::move(n)), min(min_abbrev), summary(std::move(one_line)) {}

static KeywordSpec make_keyword(std::string n, int min_abbrev, std::string help) {
    KeywordSpec k;
    k.name = std::move(n);
    k.min = min_abbrev;
    k.help = std::move(help);
    return k;
}

KeywordSpec& CommandSpec::keyword(std::string n, int min_abbrev, std::string help) {
    keywords.push_back(make_keyword(std::move(n), min_abbrev, std::move(help)));
    return keywords.back();
}

KeywordSpec& CommandSpec::range(std::string help) {
    KeywordSpec& k = keyword("range", 3, std::move(help));
    k.is_range = true;
    return k;
}

CommandSpec& CommandSpec::alias(std::string a) {
    aliases.push_back(std::move(a));
    return *this;
}

CommandSpec& CommandSpec::require_one_of(int group) {
    required_choices.push_back(group);
    return *this;
}

CommandSpec& CommandSpec::describe(std::string text) {
    description = std::move(text);
    return *this;
}

CommandSpec& CommandSpec::example(std::string text) {
    examples.push_back(std::move(text));
    return *this;
}

CommandSpec& CommandSpec::refuse_while_cycling(std::string why) {
    not_while_cycling = std::move(why);
    return *this;
}

CommandSpec& CommandSpec::handle(Handler h) {
    handler = std::move(h);
    return *this;
}

std::string CommandSpec::synopsis() const {
    std::string s = name;
    for (const ValueSpec& v : positional.values) s += " " + value_synopsis(v);
    if (positional.repeat_last) s += " ...";
    // Keywords of one choice group are shown as alternatives.
    std::vector<int> shown_groups;
    for (const KeywordSpec& k : keywords) {
        if (k.choice != 0) {
            bool seen = false;
            for (int g : shown_groups) seen = seen || g == k.choice;
            if (seen) continue;
            shown_groups.push_back(k.choice);
            std::string alt;
            for (const KeywordSpec& o : keywords) {
                if (o.choice == k.choice) alt += (alt.empty() ? "" : " | ") + o.name;
            }
            bool required = false;
            for (int g : required_choices) required = required || g == k.choice;
            s += required ? " {" + alt + "}" : " [" + alt + "]";
        } else {
            s += " [" + k.name + (k.is_range || !k.values.empty() || !k.rest_of.empty() ? " ..." : "") + "]";
        }
    }
    return s;
}

const KeywordSpec* CommandSpec::find_keyword(const std::string& full_name) const {
    for (const KeywordSpec& k : keywords) {
        if (k.name == full_name) return &k;
    }
    return nullptr;
}

const std::vector<KeywordSpec>& range_filters() {
    static const std::vector<KeywordSpec> filters = [] {
        std::vector<KeywordSpec> f;
        auto add = [&](std::string n, int min, std::string help) -> KeywordSpec& {
            f.push_back(make_keyword(std::move(n), min, std::move(help)));
            return f.back();
        };
        add("x", 1, "centroid x between lo and hi").real("lo").real("hi");
        add("y", 1, "centroid y between lo and hi").real("lo").real("hi");
        add("z", 1, "centroid z between lo and hi").real("lo").real("hi");
        add("region", 3, "blocks created with this region number").integer("n", 0);
        add("group", 2, "blocks in the named group").word("name");
        add("id", 2, "the block with this id, or ids lo to hi").integer("lo", 1).integer("hi", 1).optional("lo");
        add("bid", 3, "(3DEC) as 'id': the block with this id, or ids lo to hi").integer("lo", 1).integer("hi", 1).optional("lo");
        add("xr", 2, "(3DEC) as 'x': centroid x between lo and hi").real("lo").real("hi");
        add("yr", 2, "(3DEC) as 'y': centroid y between lo and hi").real("lo").real("hi");
        add("zr", 2, "(3DEC) as 'z': centroid z between lo and hi").real("lo").real("hi");
        add("sphere", 2, "centroid within radius r of c").vec("c").real("r", 0, kInf, Limit::Open);
        add("cylinder", 2, "centroid within radius r of the segment a-b").vec("a").vec("b").real("r", 0, kInf, Limit::Open);
        add("plane", 2, "centroid above or below a plane: plane dip d dd a origin x,y,z above|below")
            .real("dip", 0, 90).labelled()
            .real("dd", -360, 360).labelled()
            .vec("origin").labelled()
            .one_of("side", {"above", "below"});
        add("nrange", 2, "blocks in every one of the ranges named by 'range name'").word("name").repeat();
        add("union", 2, "before 'nrange': blocks in any one of the named ranges instead");
        add("not", 3, "invert the filter that follows");
        return f;
    }();
    return filters;
}

} // namespace odec
