#include "lang/completion.h"

#include <algorithm>

#include "lang/lexer.h"

namespace odec {

namespace {

void add_matching(std::vector<std::string>& out, const std::string& name, const std::string& word) {
    if (name.compare(0, word.size(), word) == 0 && std::find(out.begin(), out.end(), name) == out.end()) {
        out.push_back(name);
    }
}

} // namespace

std::vector<std::string> complete_words(const CommandTable& table, const std::string& before, const std::string& word) {
    std::string w = word;
    for (char& c : w) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::vector<std::string> out;
    const std::vector<Token> toks = lex_line_lenient(before);
    if (toks.empty()) {
        for (const CommandSpec* c : table.commands) {
            add_matching(out, c->name, w);
            for (const auto& a : c->aliases) add_matching(out, a, w);
        }
        return out;
    }
    const CommandSpec* c = table.match(toks[0].lower, nullptr);
    if (!c) return out;
    // Find the last keyword typed and how many values it has had since.
    const KeywordSpec* last = nullptr;
    size_t values_since = 0;
    bool in_range = false;
    for (size_t i = 1; i < toks.size(); ++i) {
        const Token& t = toks[i];
        const KeywordSpec* k = nullptr;
        if (t.kind == TokenKind::Word) {
            for (const KeywordSpec& ks : c->keywords) {
                if (abbreviates(t.lower, ks.name, ks.min)) k = &ks;
            }
        }
        if (k) {
            last = k;
            values_since = 0;
            if (k->is_range) in_range = true;
        } else {
            ++values_since;
        }
    }
    // A choice value expected next: offer its words.
    if (last && values_since < last->values.size() && (last->values[values_since].type == ValueType::Choice ||
                                                       !last->values[values_since].choices.empty())) {
        for (const auto& ch : last->values[values_since].choices) add_matching(out, ch, w);
        return out;
    }
    if (in_range) {
        for (const KeywordSpec& f : range_filters()) add_matching(out, f.name, w);
    }
    for (const KeywordSpec& ks : c->keywords) add_matching(out, ks.name, w);
    return out;
}

} // namespace odec
