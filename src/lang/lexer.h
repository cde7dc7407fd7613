// Lexical rules of the odec language (grammar/lexical.md is the language of record):
// case-insensitive words separated by blanks, commas or `=`; `;` starts a comment;
// `&` or `...` at the end of a line continues the command on the next line; `(` and `)`
// group the three numbers of a vector; strings are quoted with ' or ".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "lang/source.h"

namespace odec {

enum class TokenKind { Word, Number, String, LParen, RParen };

struct Token {
    TokenKind kind = TokenKind::Word;
    std::string text;   // as typed (strings without their quotes)
    std::string lower;  // lower-case text, for matching words
    double number = 0;  // for Number
    SourceLoc loc;
};

// One command: the tokens of one logical line (physical lines joined by continuations).
struct LexedCommand {
    std::vector<Token> tokens;
    int first_line = 0; // 1-based physical lines it spans
    int last_line = 0;
};

// True when the whole of s is a number in one of the usual forms: 1, -1.5, .5, 2., 1e9, 1.5E+07.
bool parse_number(const std::string& s, double& value);

// Reads commands one at a time from a source file, so that a script runs every command
// before a later line's lexical error is reported, as a person reading it would expect.
class Lexer {
public:
    explicit Lexer(std::shared_ptr<const SourceFile> file) : file_(std::move(file)) {}
    // Only lines first_line..last_line (1-based, inclusive) of the file.
    Lexer(std::shared_ptr<const SourceFile> file, int first_line, int last_line)
        : file_(std::move(file)), line_(first_line - 1), end_(last_line) {}
    // Next command with at least one token; false at the end of the file.
    // Throws CommandError on an unterminated string.
    bool next(LexedCommand& out);
    // Whether the text so far ends inside a continuation (for the prompt's continuation prompt).
    static bool ends_with_continuation(const std::string& line);
    // The body of a FISH definition whose header was the last command read: the lines up to
    // the next line whose first word is `end`, which is consumed. `first`..`last` (1-based) get
    // the body's lines; false (nothing consumed) when no `end` follows.
    bool take_definition(int& first, int& last);
    const std::shared_ptr<const SourceFile>& file() const { return file_; }

private:
    std::shared_ptr<const SourceFile> file_;
    int line_ = 0; // index of the next physical line to read
    int end_ = -1; // index past the last line to read (-1: the whole file)
};

// The first word of a line, lower case ("" when it has none): what FISH's block structure
// (def ... end) is recognised by.
std::string first_word(const std::string& line);
// Whether text (lines) opens a FISH definition (`def`/`define`) that no `end` has closed yet:
// the prompt then reads more lines before it runs any.
bool definition_open(const std::string& text);

// Tokens of a single line, for tab completion (lenient: an open string is a word).
std::vector<Token> lex_line_lenient(const std::string& line);

} // namespace odec
