// Command declarations: the one table from which parsing, checking, `help`, tab completion
// and the reference manual all come.
//
// A command is a verb (with a minimum abbreviation and aliases), optional positional values,
// and keywords. Each keyword has a minimum abbreviation, a list of typed values (each with
// limits), and one line of help. Keywords in the same nonzero `choice` group exclude each
// other (`poly brick` or `poly prism`, `damp local` or `damp off`); a command may require one
// of its group. The keyword `range` takes the range phrase (see grammar/range.md).
//
// Declarations are written with a small builder so that they read like the manual:
//
//   CommandSpec c("prop", 4, "set block or joint material properties");
//   c.keyword("dens", 3, "mass density").real("rho", 0, kInf, Limit::Open);
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace odec {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Largest magnitude a command takes for a number without limits of its own on both sides:
// squares and products of larger ones (a velocity squared, a load times a stiffness) overflow.
constexpr double kMaxMagnitude = 1e100;

enum class ValueType {
    Int,     // a whole number
    Real,    // any number
    Vec3,    // three numbers: x,y,z or x y z or (x,y,z)
    String,  // quoted, or a bare word (file names, titles)
    Word,    // a bare word or quoted string used as a name (group names)
    Choice,  // one of a declared list of words, abbreviable
};

// Whether a limit itself is allowed.
enum class Limit { Closed, Open };

struct ValueSpec {
    std::string name;            // shown in help: "rho", "x1"
    ValueType type = ValueType::Real;
    double lo = -kInf, hi = kInf;
    Limit lo_kind = Limit::Closed, hi_kind = Limit::Closed;
    std::vector<std::string> choices; // for Choice; for Real, words accepted instead of a number
    bool optional = false;       // may be left out (only at the end of a keyword's values)
    std::string default_text;    // shown in help when optional
    bool labelled = false;       // typed after its own name: `plane dip 30 dd 90 ...`
};

struct CommandContext;
struct Args;

struct KeywordSpec {
    std::string name;
    int min = 1;                 // shortest accepted abbreviation
    std::string help;
    std::vector<ValueSpec> values;
    bool repeat_last = false;    // the last value may be given any number of times (>= 1)
    bool repeatable = false;     // the keyword may appear more than once
    bool is_range = false;       // takes the range phrase
    std::string rest_of;         // takes every word after it, to be parsed as this command's
    int choice = 0;              // nonzero: keywords sharing it exclude each other
    std::string default_text;    // for keywords that stand for a setting with a default

    KeywordSpec& integer(std::string n, double lo = -kInf, double hi = kInf);
    KeywordSpec& real(std::string n, double lo = -kInf, double hi = kInf, Limit lo_kind = Limit::Closed,
                      Limit hi_kind = Limit::Closed);
    KeywordSpec& vec(std::string n);
    KeywordSpec& string(std::string n);
    KeywordSpec& word(std::string n);
    KeywordSpec& one_of(std::string n, std::vector<std::string> words);
    // The last (Real) value may be given as this word instead of a number (`set dt auto`); the
    // value then has the word as its text and no number.
    KeywordSpec& or_word(std::string word);
    // Makes the last value optional, shown with its default in help.
    KeywordSpec& optional(std::string default_text = {});
    KeywordSpec& repeat();
    // The last value is typed after its name as a word (`dip 30`).
    KeywordSpec& labelled();
    KeywordSpec& many();          // the keyword may be repeated
    KeywordSpec& in_choice(int group);
    KeywordSpec& defaults(std::string text);
    // The words after this keyword belong to another command (`set plot ...` -> `plot set ...`).
    KeywordSpec& forward_to(std::string command);
    // The words after this keyword are taken as they are and left to the handler (classic
    // forms odec accepts with a warning, such as 3DEC's `plot add ...`).
    KeywordSpec& rest_as_words();
    // "brick x1 x2 y1 y2 z1 z2"
    std::string synopsis() const;
};

using Handler = std::function<void(CommandContext&, const Args&)>;

struct CommandSpec {
    std::string name;
    int min = 1;
    std::string summary;         // one line of help
    std::vector<std::string> aliases; // full alternative verbs (`cycle` for `step`)
    KeywordSpec positional;      // values right after the verb (its name is empty)
    std::vector<KeywordSpec> keywords;
    std::vector<int> required_choices; // choice groups of which one keyword must be given
    std::string description;     // a paragraph for the manual
    std::vector<std::string> examples;
    // Why the command may not run while the model cycles (from a 'whilestepping' function or
    // a FISH history); empty: it may. The interpreter refuses it there with this reason.
    std::string not_while_cycling;
    Handler handler;

    CommandSpec(std::string n, int min_abbrev, std::string one_line);
    KeywordSpec& keyword(std::string n, int min_abbrev, std::string help);
    // Adds the `range` keyword (the range phrase).
    KeywordSpec& range(std::string help = "which blocks: see 'help range'");
    CommandSpec& alias(std::string a);
    CommandSpec& require_one_of(int group);
    CommandSpec& describe(std::string text);
    CommandSpec& example(std::string text);
    CommandSpec& refuse_while_cycling(std::string why);
    CommandSpec& handle(Handler h);
    // "prop mat n | jmat n  dens rho ..." one line
    std::string synopsis() const;
    const KeywordSpec* find_keyword(const std::string& full_name) const;
};

// The filters of the range phrase, declared like keywords (grammar/range.md).
const std::vector<KeywordSpec>& range_filters();

// Text of a value's limits for messages and help: "> 0", "1 to 100", "".
std::string describe_limits(const ValueSpec& v);
const char* type_name(ValueType t);

} // namespace odec
