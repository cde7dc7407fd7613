// From tokens to typed arguments, checked against the command's declaration.
//
// Matching a word: it must be at least the declared minimum long and a prefix of exactly
// one word allowed at that point (an exact match always wins). Values are checked for type
// and limits here, so handlers read typed values and never raw text.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "engine/range.h"
#include "lang/decl.h"
#include "lang/lexer.h"

namespace odec {

struct Value {
    ValueType type = ValueType::Real;
    double number = 0;
    Eigen::Vector3d vec = Eigen::Vector3d::Zero();
    std::string text;   // String, Word, and Choice (the full choice word)
    SourceLoc loc;
};

struct KeywordUse {
    const KeywordSpec* spec = nullptr;
    SourceLoc loc;
    std::vector<Value> values;
    std::vector<Token> rest;      // for a keyword that forwards the words after it
};

struct Args {
    const CommandSpec* command = nullptr;
    SourceLoc loc;                // the verb
    std::vector<Value> positional;
    std::vector<KeywordUse> uses; // in the order typed
    Range range;                  // the range phrase, when given
    bool has_range = false;
    SourceLoc range_loc;

    bool has(const std::string& kw) const { return find(kw) != nullptr; }
    const KeywordUse* find(const std::string& kw) const;
    std::vector<const KeywordUse*> all(const std::string& kw) const;
    // Value i of keyword kw (which must have been given).
    const Value& value(const std::string& kw, size_t i = 0) const;
    double real(const std::string& kw, size_t i = 0) const { return value(kw, i).number; }
    int integer(const std::string& kw, size_t i = 0) const { return static_cast<int>(value(kw, i).number); }
    const Eigen::Vector3d& vec(const std::string& kw, size_t i = 0) const { return value(kw, i).vec; }
    const std::string& text(const std::string& kw, size_t i = 0) const { return value(kw, i).text; }
    // Value i of kw when given, else the fallback.
    double real_or(const std::string& kw, double fallback, size_t i = 0) const;
    // The keyword given from choice group g, or "" when none.
    std::string chosen(int group) const;
};

// The command table the parser matches verbs against.
struct CommandTable {
    std::vector<const CommandSpec*> commands;
    // The command whose name or alias is `word` or starts with it (respecting minimums);
    // nullptr when none. `ambiguous` gets the candidates when several match.
    const CommandSpec* match(const std::string& lower_word, std::vector<std::string>* ambiguous) const;
    const CommandSpec* find(const std::string& full_name) const;
};

// Ranges given a name by `range name X ...`, by lower-case name; `nrange X` refers to them.
using NamedRanges = std::map<std::string, Range>;

// Parse one command. Throws CommandError with a located, explained message.
Args parse_command(const CommandTable& table, const std::vector<Token>& tokens, const NamedRanges* named = nullptr);

// Closest words to `word` among `candidates` by edit distance (for "did you mean").
std::vector<std::string> closest_words(const std::string& word, const std::vector<std::string>& candidates,
                                       size_t max_results = 3);

// Whether `word` (lower case) selects `name` given its minimum abbreviation.
bool abbreviates(const std::string& word, const std::string& name, int min);

} // namespace odec
