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
    // Next command with at least one token; false at the end of the file.
    // Throws CommandError on an unterminated string.
    bool next(LexedCommand& out);
    // Whether the text so far ends inside a continuation (for the prompt's continuation prompt).
    static bool ends_with_continuation(const std::string& line);

private:
    std::shared_ptr<const SourceFile> file_;
    int line_ = 0; // index of the next physical line to read
};

// Tokens of a single line, for tab completion (lenient: an open string is a word).
std::vector<Token> lex_line_lenient(const std::string& line);

} // namespace odec
