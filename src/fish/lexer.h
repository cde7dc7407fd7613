// Tokens of FISH lines. A FISH line is one statement; `;` starts a comment (outside strings);
// names are case-insensitive and may carry a leading `@` (as written in commands).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "lang/source.h"

namespace odec::fish {

enum class Tok { Name, Int, Float, String, Op, End };

struct Token {
    Tok kind = Tok::End;
    std::string text;   // as typed (strings without quotes, names without '@')
    std::string lower;  // lower case, for names and keywords
    double number = 0;  // Float
    long long integer = 0; // Int
    bool at = false;    // a name typed with a leading '@'
    SourceLoc loc;
};

// One line of FISH source: where it is and its tokens (the last is an End token).
struct Line {
    SourceLoc loc;      // the first token (or the line start)
    std::vector<Token> tokens;
};

// Tokens of one physical line (text), from column col0 (0-based) on. Throws CommandError on an
// unterminated string or a character FISH does not know.
Line lex_line(const std::shared_ptr<const SourceFile>& file, int line_no, const std::string& text, size_t col0 = 0);

} // namespace odec::fish
