#include "lang/parser.h"
#include "lang/not_yet.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace odec {

namespace {

constexpr double kDegree = M_PI / 180.0;

std::string join(const std::vector<std::string>& words, const std::string& sep = ", ") {
    std::string s;
    for (size_t k = 0; k < words.size(); ++k) s += (k ? sep : "") + words[k];
    return s;
}

std::string quoted_list(const std::vector<std::string>& words) {
    std::vector<std::string> q;
    for (const auto& w : words) q.push_back("'" + w + "'");
    if (q.size() <= 1) return join(q);
    return join(std::vector<std::string>(q.begin(), q.end() - 1)) + " or " + q.back();
}


// Matches a word against named things with minimum abbreviations. Returns the index of
// the one match, -1 when none, -2 when ambiguous (candidates filled), -3 when the word
// abbreviates something but is shorter than its minimum (candidates filled with minimums).
template <class Names>
int match_word(const std::string& w, const Names& names, std::vector<std::string>& candidates) {
    candidates.clear();
    int found = -1, n_found = 0;
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i].first == w) return static_cast<int>(i);
    }
    std::vector<std::string> too_short;
    for (size_t i = 0; i < names.size(); ++i) {
        const std::string& name = names[i].first;
        if (w.size() <= name.size() && name.compare(0, w.size(), w) == 0) {
            if (static_cast<int>(w.size()) >= names[i].second) {
                found = static_cast<int>(i);
                ++n_found;
                candidates.push_back(name);
            } else {
                too_short.push_back(name.substr(0, std::max<size_t>(names[i].second, w.size())));
            }
        }
    }
    if (n_found == 1) return found;
    if (n_found > 1) return -2;
    if (!too_short.empty()) {
        candidates = too_short;
        return -3;
    }
    return -1;
}

// Edit distance counting a swap of two neighbouring letters as one edit ("dnes" for "dens").
size_t edit_distance(const std::string& a, const std::string& b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
    for (size_t i = 0; i <= n; ++i) d[i][0] = i;
    for (size_t j = 0; j <= m; ++j) d[0][j] = j;
    for (size_t i = 1; i <= n; ++i) {
        for (size_t j = 1; j <= m; ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[n][m];
}

class Parser {
public:
    Parser(const CommandTable& table, const std::vector<Token>& toks, const NamedRanges* named)
        : table_(table), t_(toks), named_(named) {}

    Args run() {
        Args a;
        const Token& verb = t_[0];
        if (verb.kind != TokenKind::Word) {
            fail(verb.loc, "expected a command but found '" + verb.text + "'", {"type 'help' for the list of commands"});
        }
        std::vector<std::string> cand;
        const CommandSpec* c = table_.match(verb.lower, &cand);
        if (!c) unknown_command(verb, cand);
        a.command = c;
        a.loc = verb.loc;
        cmd_ = c;
        pos_ = 1;
        // Positional values.
        parse_values(c->positional, c->name, verb, a.positional, true);
        // Keywords.
        std::vector<std::pair<std::string, int>> names;
        for (const KeywordSpec& k : c->keywords) names.emplace_back(k.name, k.min);
        while (pos_ < t_.size()) {
            const Token& w = t_[pos_];
            if (w.kind != TokenKind::Word) {
                if (c->keywords.empty()) {
                    fail(w.loc, "extra word '" + w.text + "': '" + c->name + "' takes nothing more", {}, c->name);
                }
                fail(w.loc, "unexpected '" + w.text + "': expected a keyword of '" + c->name + "'",
                     {"expected one of: " + keyword_list()}, c->name);
            }
            int k = match_word(w.lower, names, cand);
            if (k < 0) {
                // Classic scripts often leave out the word `range`: `fix region 1`, `hide reg 2`.
                const KeywordSpec* range_kw = nullptr;
                for (const KeywordSpec& ks : c->keywords) {
                    if (ks.is_range) range_kw = &ks;
                }
                std::vector<std::pair<std::string, int>> filters;
                for (const KeywordSpec& f : range_filters()) filters.emplace_back(f.name, f.min);
                std::vector<std::string> fc;
                if (range_kw && !a.has_range && match_word(w.lower, filters, fc) >= 0) {
                    k = static_cast<int>(range_kw - c->keywords.data());
                    --pos_; // the filter word is read again by the range phrase
                } else {
                    unknown_keyword(w, k, cand, names);
                }
            }
            const KeywordSpec& spec = c->keywords[k];
            ++pos_;
            for (const KeywordUse& u : a.uses) {
                if (u.spec == &spec && !spec.repeatable) {
                    fail(w.loc, "'" + spec.name + "' given twice", {"it was first given at column " + std::to_string(u.loc.col)},
                         c->name);
                }
                if (spec.choice != 0 && u.spec->choice == spec.choice && u.spec != &spec) {
                    fail(w.loc, "'" + spec.name + "' cannot be combined with '" + u.spec->name + "'",
                         {"give one of: " + join(group_names(spec.choice))}, c->name);
                }
            }
            KeywordUse use;
            use.spec = &spec;
            use.loc = w.loc;
            if (!spec.rest_of.empty()) {
                use.rest.assign(t_.begin() + static_cast<long>(pos_), t_.end());
                pos_ = t_.size();
            } else if (spec.is_range) {
                parse_range(w, a.range);
                a.has_range = true;
                a.range_loc = w.loc;
            } else {
                parse_values(spec, spec.name, w, use.values, false);
            }
            a.uses.push_back(std::move(use));
        }
        for (int g : c->required_choices) {
            if (a.chosen(g).empty()) {
                SourceLoc end = t_.back().loc;
                end.col += end.length;
                end.length = 1;
                fail(t_.size() == 1 ? verb.loc : end, "'" + c->name + "' needs one of: " + join(group_names(g)), {}, c->name);
            }
        }
        return a;
    }

private:
    const CommandTable& table_;
    const std::vector<Token>& t_;
    const NamedRanges* named_;
    const CommandSpec* cmd_ = nullptr;
    size_t pos_ = 0;

    std::vector<std::string> group_names(int g) const {
        std::vector<std::string> out;
        for (const KeywordSpec& k : cmd_->keywords) {
            if (k.choice == g) out.push_back(k.name);
        }
        return out;
    }

    std::string keyword_list() const {
        std::vector<std::string> out;
        for (const KeywordSpec& k : cmd_->keywords) out.push_back(k.name);
        return join(out);
    }

    [[noreturn]] void unknown_command(const Token& verb, const std::vector<std::string>& cand) {
        std::vector<std::string> all;
        for (const CommandSpec* c : table_.commands) {
            all.push_back(c->name);
            for (const auto& al : c->aliases) all.push_back(al);
        }
        std::vector<std::pair<std::string, int>> names;
        for (const CommandSpec* c : table_.commands) {
            names.emplace_back(c->name, c->min);
            for (const auto& al : c->aliases) names.emplace_back(al, c->min);
        }
        std::vector<std::string> c2;
        const int r = match_word(verb.lower, names, c2);
        if (r == -2) {
            fail(verb.loc, "ambiguous abbreviation '" + verb.text + "': could be " + quoted_list(cand.empty() ? c2 : cand),
                 {"type more letters of the command"});
        }
        if (r == -3) {
            fail(verb.loc, "abbreviation '" + verb.text + "' is too short: write at least " + quoted_list(c2),
                 {"type more letters of the command"});
        }
        const std::string missing = not_yet_available(verb.lower);
        if (!missing.empty()) fail(verb.loc, missing, {"type 'help' for the commands odec has"});
        std::vector<std::string> notes;
        const auto near = closest_words(verb.lower, all);
        if (!near.empty()) notes.push_back("did you mean " + quoted_list(near) + "?");
        notes.push_back("type 'help' for the list of commands");
        fail(verb.loc, "unknown command '" + verb.text + "'", notes);
    }

    [[noreturn]] void unknown_keyword(const Token& w, int r, const std::vector<std::string>& cand,
                                      const std::vector<std::pair<std::string, int>>& names) {
        if (r == -2) {
            fail(w.loc, "ambiguous abbreviation '" + w.text + "' for '" + cmd_->name + "': could be " + quoted_list(cand),
                 {"type more letters of the keyword"}, cmd_->name);
        }
        if (r == -3) {
            fail(w.loc, "abbreviation '" + w.text + "' is too short: write at least " + quoted_list(cand), {}, cmd_->name);
        }
        std::vector<std::string> all;
        for (const auto& n : names) all.push_back(n.first);
        std::vector<std::string> notes;
        if (all.empty()) {
            fail(w.loc, "extra word '" + w.text + "': '" + cmd_->name + "' takes nothing more", {}, cmd_->name);
        }
        const auto near = closest_words(w.lower, all);
        if (!near.empty()) notes.push_back("did you mean " + quoted_list(near) + "?");
        notes.push_back("expected one of: " + join(all));
        fail(w.loc, "unknown keyword '" + w.text + "' for '" + cmd_->name + "'", notes, cmd_->name);
    }

    SourceLoc end_loc(const Token& after) const {
        SourceLoc l = pos_ > 0 ? t_[pos_ - 1].loc : after.loc;
        l.col += l.length;
        l.length = 1;
        return l;
    }

    bool next_is_number() const { return pos_ < t_.size() && t_[pos_].kind == TokenKind::Number; }
    bool next_starts_vector() const {
        return pos_ < t_.size() && (t_[pos_].kind == TokenKind::Number || t_[pos_].kind == TokenKind::LParen);
    }

    // Whether the next token can start a value of type v (used for optional and repeated values).
    bool can_start(const ValueSpec& v) const {
        if (pos_ >= t_.size()) return false;
        const Token& t = t_[pos_];
        if (v.labelled) return t.kind == TokenKind::Word && abbreviates(t.lower, v.name, 2);
        switch (v.type) {
        case ValueType::Int:
        case ValueType::Real:
            if (t.kind == TokenKind::Word) {
                for (const auto& c : v.choices) {
                    if (t.lower == c) return true;
                }
            }
            return t.kind == TokenKind::Number;
        case ValueType::Vec3: return next_starts_vector();
        case ValueType::String:
        case ValueType::Word: return t.kind == TokenKind::String || (t.kind == TokenKind::Word && !is_keyword(t.lower));
        case ValueType::Choice: {
            if (t.kind != TokenKind::Word) return false;
            for (const auto& c : v.choices) {
                if (abbreviates(t.lower, c, 1)) return true;
            }
            return false;
        }
        }
        return false;
    }

    bool is_keyword(const std::string& w) const {
        for (const KeywordSpec& k : cmd_->keywords) {
            if (abbreviates(w, k.name, k.min)) return true;
        }
        return false;
    }

    std::string owner_phrase(const std::string& owner, const KeywordSpec& spec, const ValueSpec& v) const {
        if (spec.values.size() == 1 && !spec.repeat_last) return "'" + owner + "'";
        return "'" + owner + "' " + v.name;
    }

    [[noreturn]] void missing(const std::string& owner, const KeywordSpec& spec, const ValueSpec& v, const Token& kw) {
        fail(end_loc(kw), "missing value for " + owner_phrase(owner, spec, v) + ": expected " + type_name(v.type),
             {"'" + owner + "' takes: " + (spec.name.empty() ? cmd_->synopsis() : spec.synopsis())}, cmd_->name);
    }

    double number(const std::string& owner, const KeywordSpec& spec, const ValueSpec& v, const Token& kw) {
        if (pos_ >= t_.size()) missing(owner, spec, v, kw);
        const Token& t = t_[pos_];
        if (t.kind != TokenKind::Number) {
            std::string what = type_name(v.type);
            for (const auto& c : v.choices) what += " or '" + c + "'";
            fail(t.loc, "'" + t.text + "' is not a number: '" + owner + "' expects " + v.name + " (" + what + ")",
                 {"'" + owner + "' takes: " + (spec.name.empty() ? cmd_->synopsis() : spec.synopsis())}, cmd_->name);
        }
        ++pos_;
        return t.number;
    }

    void check_limits(const std::string& owner, const KeywordSpec& spec, const ValueSpec& v, const Token& t, double x) {
        // Beyond kMaxMagnitude what odec derives from a number (a square, a product with a
        // stiffness or an area) overflows to inf: such numbers are refused where they are typed.
        if (std::isfinite(x) && std::abs(x) > kMaxMagnitude && !(std::isfinite(v.lo) && std::isfinite(v.hi))) {
            fail(t.loc, owner_phrase(owner, spec, v) + " must be a number of magnitude at most 1e100 (got " + t.text +
                            "): what odec computes from larger ones overflows",
                 {}, cmd_->name);
        }
        bool ok = std::isfinite(x);
        if (std::isfinite(v.lo)) ok = ok && (v.lo_kind == Limit::Open ? x > v.lo : x >= v.lo);
        if (std::isfinite(v.hi)) ok = ok && (v.hi_kind == Limit::Open ? x < v.hi : x <= v.hi);
        if (!ok) {
            // A closed range says "finite" by itself; otherwise say it (1e309 is read as infinity).
            const std::string limits = describe_limits(v);
            std::string expected = limits;
            if (limits.empty()) {
                expected = "a finite number";
            } else if (!std::isfinite(x) && !(std::isfinite(v.lo) && std::isfinite(v.hi))) {
                expected = "a finite number " + limits;
            }
            fail(t.loc, owner_phrase(owner, spec, v) + " must be " + expected + " (got " + t.text + ")", {}, cmd_->name);
        }
    }

    Value parse_value(const ValueSpec& v, const std::string& owner, const KeywordSpec& spec, const Token& kw) {
        Value out;
        out.type = v.type;
        if (v.labelled) {
            if (pos_ >= t_.size() || t_[pos_].kind != TokenKind::Word || !abbreviates(t_[pos_].lower, v.name, 2)) {
                const SourceLoc l = pos_ < t_.size() ? t_[pos_].loc : end_loc(kw);
                fail(l, "expected '" + v.name + "' in '" + owner + "'", {"'" + owner + "' takes: " + spec.synopsis()},
                     cmd_->name);
            }
            ++pos_;
        }
        if (pos_ >= t_.size()) missing(owner, spec, v, kw);
        const Token& t = t_[pos_];
        out.loc = t.loc;
        switch (v.type) {
        case ValueType::Int: {
            const double x = number(owner, spec, v, kw);
            if (x != std::floor(x) || std::abs(x) > 2e9) {
                fail(t.loc, "'" + t.text + "' is not an integer: '" + owner + "' expects " + v.name + " (an integer)",
                     {}, cmd_->name);
            }
            check_limits(owner, spec, v, t, x);
            out.number = x;
            break;
        }
        case ValueType::Real: {
            if (t.kind == TokenKind::Word) {
                bool word = false;
                for (const auto& c : v.choices) word = word || t.lower == c;
                if (word) {
                    out.text = t.lower;
                    out.number = std::numeric_limits<double>::quiet_NaN();
                    ++pos_;
                    break;
                }
            }
            out.number = number(owner, spec, v, kw);
            check_limits(owner, spec, v, t, out.number);
            break;
        }
        case ValueType::Vec3: {
            const bool paren = t.kind == TokenKind::LParen;
            if (paren) ++pos_;
            for (int i = 0; i < 3; ++i) {
                if (pos_ >= t_.size()) missing(owner, spec, v, kw);
                if (t_[pos_].kind != TokenKind::Number) {
                    const Token& bad = t_[pos_];
                    fail(bad.loc, "'" + bad.text + "' is not a number: '" + owner + "' expects " + v.name +
                                      " (a vector x,y,z)",
                         {"'" + owner + "' takes: " + (spec.name.empty() ? cmd_->synopsis() : spec.synopsis())},
                         cmd_->name);
                }
                const Token& c = t_[pos_++];
                if (!std::isfinite(c.number)) {
                    fail(c.loc, owner_phrase(owner, spec, v) + " components must be finite numbers (got " + c.text + ")",
                         {}, cmd_->name);
                }
                if (std::abs(c.number) > kMaxMagnitude) {
                    fail(c.loc, owner_phrase(owner, spec, v) + " components must be numbers of magnitude at most 1e100 (got " +
                                    c.text + "): what odec computes from larger ones overflows",
                         {}, cmd_->name);
                }
                out.vec[i] = c.number;
            }
            if (paren) {
                if (pos_ >= t_.size() || t_[pos_].kind != TokenKind::RParen) {
                    const SourceLoc l = pos_ < t_.size() ? t_[pos_].loc : end_loc(kw);
                    fail(l, "expected ')' to close the vector of " + owner_phrase(owner, spec, v), {}, cmd_->name);
                }
                ++pos_;
            }
            break;
        }
        case ValueType::String:
        case ValueType::Word: {
            if (t.kind != TokenKind::String && t.kind != TokenKind::Word && t.kind != TokenKind::Number) {
                fail(t.loc, "expected " + std::string(type_name(v.type)) + " for " + owner_phrase(owner, spec, v) +
                                " but found '" + t.text + "'",
                     {}, cmd_->name);
            }
            out.text = t.text;
            ++pos_;
            break;
        }
        case ValueType::Choice: {
            std::vector<std::pair<std::string, int>> names;
            for (const auto& c : v.choices) names.emplace_back(c, 1);
            std::vector<std::string> cand;
            const int k = t.kind == TokenKind::Word ? match_word(t.lower, names, cand) : -1;
            if (k < 0) {
                std::vector<std::string> notes;
                if (k == -2) notes.push_back("could be " + quoted_list(cand));
                fail(t.loc, "'" + t.text + "' is not a choice of " + owner_phrase(owner, spec, v) + ": expected one of " +
                                join(v.choices),
                     notes, cmd_->name);
            }
            out.text = v.choices[k];
            ++pos_;
            break;
        }
        }
        return out;
    }

    void parse_values(const KeywordSpec& spec, const std::string& owner, const Token& kw, std::vector<Value>& out,
                      bool positional) {
        (void)positional;
        for (size_t i = 0; i < spec.values.size(); ++i) {
            const ValueSpec& v = spec.values[i];
            if (v.optional && !can_start(v)) continue;
            out.push_back(parse_value(v, owner, spec, kw));
        }
        if (spec.repeat_last && !spec.values.empty()) {
            const ValueSpec& v = spec.values.back();
            while (can_start(v)) out.push_back(parse_value(v, owner, spec, kw));
        }
    }

    void parse_range(const Token& kw, Range& r) {
        const auto& filters = range_filters();
        std::vector<std::pair<std::string, int>> names;
        for (const KeywordSpec& f : filters) names.emplace_back(f.name, f.min);
        bool negate = false;
        const Token* not_tok = nullptr;
        const Token* union_tok = nullptr;
        size_t n_filters = 0;
        std::vector<std::string> cand;
        while (pos_ < t_.size()) {
            const Token& w = t_[pos_];
            const int k = w.kind == TokenKind::Word ? match_word(w.lower, names, cand) : -1;
            if (k < 0) {
                if (n_filters == 0 || negate) {
                    std::vector<std::string> all;
                    for (const auto& n : names) all.push_back(n.first);
                    std::vector<std::string> notes;
                    const auto near = w.kind == TokenKind::Word ? closest_words(w.lower, all) : std::vector<std::string>{};
                    if (!near.empty()) notes.push_back("did you mean " + quoted_list(near) + "?");
                    notes.push_back("expected one of: " + join(all));
                    fail(w.loc, "unknown range filter '" + w.text + "'", notes, "range");
                }
                break;
            }
            const KeywordSpec& spec = filters[k];
            ++pos_;
            if (spec.name == "not") {
                negate = !negate;
                not_tok = &w;
                continue;
            }
            if (spec.name == "union") {
                if (union_tok) fail(w.loc, "'union' given twice", {}, "range");
                union_tok = &w;
                continue;
            }
            std::vector<Value> vals;
            parse_values(spec, spec.name, w, vals, false);
            if (union_tok && spec.name != "nrange") {
                fail(union_tok->loc, "'union' must be followed by 'nrange' and the names to join", {}, "range");
            }
            r.filters.push_back(spec.name == "nrange" ? named_filter(vals, union_tok != nullptr, negate)
                                                      : make_filter(spec, vals, negate, w));
            union_tok = nullptr;
            negate = false;
            ++n_filters;
        }
        if (negate) fail(end_loc(*not_tok), "'not' must be followed by a range filter", {}, "range");
        if (union_tok) fail(union_tok->loc, "'union' must be followed by 'nrange' and the names to join", {}, "range");
        if (n_filters == 0) {
            std::vector<std::string> all;
            for (const auto& n : names) all.push_back(n.first);
            fail(end_loc(kw), "missing range filter after 'range'", {"expected one of: " + join(all)}, "range");
        }
    }

    // `nrange a b`: in ranges a and b; `union nrange a b`: in range a or b.
    Filter named_filter(const std::vector<Value>& names, bool any, bool negate) {
        Filter f;
        f.kind = FilterKind::AnyOf;
        f.negate = negate;
        Range all;
        for (const Value& v : names) {
            std::string key = v.text;
            for (char& ch : key) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            const auto it = named_ ? named_->find(key) : NamedRanges::const_iterator();
            if (!named_ || it == named_->end()) {
                fail(v.loc, "there is no range named '" + v.text + "'", {"name one first: range name " + v.text + " <filters>"},
                     "range");
            }
            if (any) {
                f.any_of.push_back(it->second);
            } else {
                all.filters.insert(all.filters.end(), it->second.filters.begin(), it->second.filters.end());
            }
        }
        if (!any) f.any_of.push_back(std::move(all));
        return f;
    }

    Filter make_filter(const KeywordSpec& spec, const std::vector<Value>& v, bool negate, const Token& w) {
        Filter f;
        f.negate = negate;
        // 3DEC's names for the same filters: bid (id), xr, yr, zr (x, y, z).
        const std::string n = spec.name == "bid" ? std::string("id")
                              : (spec.name == "xr" || spec.name == "yr" || spec.name == "zr") ? spec.name.substr(0, 1)
                                                                                                : spec.name;
        if (n == "x" || n == "y" || n == "z") {
            f.kind = n == "x" ? FilterKind::X : n == "y" ? FilterKind::Y : FilterKind::Z;
            f.lo = std::min(v[0].number, v[1].number);
            f.hi = std::max(v[0].number, v[1].number);
        } else if (n == "region") {
            f.kind = FilterKind::Region;
            f.lo = v[0].number;
        } else if (n == "group") {
            f.kind = FilterKind::Group;
            f.name = v[0].text;
        } else if (n == "id") {
            f.kind = FilterKind::Id;
            f.lo = v[0].number;
            f.hi = v.size() > 1 ? v[1].number : v[0].number;
            if (f.hi < f.lo) std::swap(f.lo, f.hi);
        }
        // Geometry filters measure distances: points so far away that their differences
        // overflow would select nothing, silently wrong.
        if (n == "sphere" || n == "cylinder" || n == "plane") {
            for (const Value& x : v) {
                if (x.type == ValueType::Vec3 && !(x.vec.cwiseAbs().maxCoeff() <= 1e100)) {
                    fail(x.loc, "the point of '" + n + "' is too far from the origin: range points must be within 1e+100 m",
                         {}, "range");
                }
            }
        }
        if (n == "sphere") {
            f.kind = FilterKind::Sphere;
            f.a = v[0].vec;
            f.radius = v[1].number;
        } else if (n == "cylinder") {
            f.kind = FilterKind::Cylinder;
            f.a = v[0].vec;
            f.b = v[1].vec;
            f.radius = v[2].number;
            if ((f.b - f.a).norm() == 0) fail(w.loc, "the cylinder's two end points are the same", {}, "range");
        } else if (n == "plane") {
            const double dip = v[0].number * kDegree, dd = v[1].number * kDegree;
            f.kind = v[3].text == "above" ? FilterKind::PlaneAbove : FilterKind::PlaneBelow;
            f.a = v[2].vec;
            f.b = Eigen::Vector3d(std::sin(dip) * std::sin(dd), std::sin(dip) * std::cos(dd), std::cos(dip));
        }
        return f;
    }
};

} // namespace

const KeywordUse* Args::find(const std::string& kw) const {
    for (const KeywordUse& u : uses) {
        if (u.spec->name == kw) return &u;
    }
    return nullptr;
}

std::vector<const KeywordUse*> Args::all(const std::string& kw) const {
    std::vector<const KeywordUse*> out;
    for (const KeywordUse& u : uses) {
        if (u.spec->name == kw) out.push_back(&u);
    }
    return out;
}

const Value& Args::value(const std::string& kw, size_t i) const {
    const KeywordUse* u = find(kw);
    if (!u || i >= u->values.size()) {
        // A handler asked for a value its declaration does not guarantee: a programming error.
        fail(loc, "internal error: '" + kw + "' value " + std::to_string(i) + " is missing");
    }
    return u->values[i];
}

double Args::real_or(const std::string& kw, double fallback, size_t i) const {
    const KeywordUse* u = find(kw);
    return (u && i < u->values.size()) ? u->values[i].number : fallback;
}

std::string Args::chosen(int group) const {
    for (const KeywordUse& u : uses) {
        if (u.spec->choice == group) return u.spec->name;
    }
    return "";
}

const CommandSpec* CommandTable::match(const std::string& w, std::vector<std::string>* ambiguous) const {
    std::vector<std::pair<std::string, int>> names;
    std::vector<const CommandSpec*> owner;
    for (const CommandSpec* c : commands) {
        names.emplace_back(c->name, c->min);
        owner.push_back(c);
        for (const auto& a : c->aliases) {
            names.emplace_back(a, std::min<int>(c->min, static_cast<int>(a.size())));
            owner.push_back(c);
        }
    }
    std::vector<std::string> cand;
    const int k = match_word(w, names, cand);
    if (k >= 0) return owner[k];
    if (k == -2) {
        // Several names of the same command (a verb and its alias) are not ambiguous.
        const CommandSpec* first = nullptr;
        bool same = true;
        for (size_t i = 0; i < names.size(); ++i) {
            if (std::find(cand.begin(), cand.end(), names[i].first) != cand.end()) {
                if (!first) first = owner[i];
                same = same && owner[i] == first;
            }
        }
        if (same && first) return first;
    }
    if (ambiguous) *ambiguous = cand;
    return nullptr;
}

const CommandSpec* CommandTable::find(const std::string& full_name) const {
    for (const CommandSpec* c : commands) {
        if (c->name == full_name) return c;
        for (const auto& a : c->aliases) {
            if (a == full_name) return c;
        }
    }
    return nullptr;
}

Args parse_command(const CommandTable& table, const std::vector<Token>& tokens, const NamedRanges* named) {
    Parser p(table, tokens, named);
    return p.run();
}

std::vector<std::string> closest_words(const std::string& word, const std::vector<std::string>& candidates,
                                       size_t max_results) {
    std::vector<std::pair<size_t, std::string>> scored;
    for (const auto& c : candidates) {
        // Compare with the whole name and with its beginning, since names are often abbreviated.
        size_t d = edit_distance(word, c);
        for (size_t len = word.size() > 1 ? word.size() - 1 : 1; len <= word.size() + 1; ++len) {
            if (len < c.size()) d = std::min(d, edit_distance(word, c.substr(0, len)));
        }
        const size_t limit = std::max<size_t>(1, std::min(word.size(), c.size()) / 3);
        if (d <= limit && d < word.size()) scored.emplace_back(d, c);
    }
    std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (const auto& s : scored) {
        if (std::find(out.begin(), out.end(), s.second) == out.end()) out.push_back(s.second);
        if (out.size() >= max_results) break;
    }
    return out;
}

bool abbreviates(const std::string& word, const std::string& name, int min) {
    if (word == name) return true;
    return static_cast<int>(word.size()) >= min && word.size() <= name.size() && name.compare(0, word.size(), word) == 0;
}

} // namespace odec
