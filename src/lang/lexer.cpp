#include "lang/lexer.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace odec {

namespace {

bool is_separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == '=' || c == '\r' || c == '\f' || c == '\v'; }

std::string to_lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Tokens of one physical line. Returns true when the line ends in a continuation mark
// (which is removed). Unterminated strings throw unless lenient.
bool lex_physical_line(const std::shared_ptr<const SourceFile>& file, int line_no, const std::string& text,
                       std::vector<Token>& out, bool lenient) {
    const size_t first_new = out.size();
    size_t i = 0;
    const size_t n = text.size();
    while (i < n) {
        const char c = text[i];
        if (is_separator(c)) {
            ++i;
            continue;
        }
        if (c == ';') break;
        Token t;
        t.loc.file = file;
        t.loc.line = line_no;
        t.loc.col = static_cast<int>(i) + 1;
        if (c == '\'' || c == '"') {
            const size_t close = text.find(c, i + 1);
            if (close == std::string::npos) {
                if (!lenient) {
                    SourceLoc loc = t.loc;
                    loc.length = static_cast<int>(n - i);
                    fail(loc, std::string("unterminated string: no closing ") + c + " on this line",
                         {"expected the string to end with " + std::string(1, c) + " before the end of the line"});
                }
                t.kind = TokenKind::Word;
                t.text = text.substr(i + 1);
                t.loc.length = static_cast<int>(n - i);
                i = n;
            } else {
                t.kind = TokenKind::String;
                t.text = text.substr(i + 1, close - i - 1);
                t.loc.length = static_cast<int>(close - i + 1);
                i = close + 1;
            }
        } else if (c == '(' || c == ')') {
            t.kind = c == '(' ? TokenKind::LParen : TokenKind::RParen;
            t.text = std::string(1, c);
            ++i;
        } else {
            size_t j = i;
            while (j < n && !is_separator(text[j]) && text[j] != ';' && text[j] != '(' && text[j] != ')' &&
                   text[j] != '\'' && text[j] != '"') {
                ++j;
            }
            t.text = text.substr(i, j - i);
            t.loc.length = static_cast<int>(j - i);
            i = j;
            t.kind = parse_number(t.text, t.number) ? TokenKind::Number : TokenKind::Word;
        }
        t.lower = to_lower(t.text);
        out.push_back(std::move(t));
    }
    // A continuation mark ends the line: `&` alone or glued to the last word, or `...`.
    if (out.size() > first_new) {
        Token& last = out.back();
        if (last.kind == TokenKind::Word && (last.text == "..." || last.text == "&")) {
            out.pop_back();
            return true;
        }
        if (last.kind == TokenKind::Word && last.text.size() > 1 && last.text.back() == '&') {
            last.text.pop_back();
            last.lower.pop_back();
            last.loc.length -= 1;
            last.kind = parse_number(last.text, last.number) ? TokenKind::Number : TokenKind::Word;
            return true;
        }
    }
    return false;
}

} // namespace

bool parse_number(const std::string& s, double& value) {
    // Accept [+-] digits [. digits] [(e|E) [+-] digits], with at least one digit in the mantissa.
    size_t i = 0;
    const size_t n = s.size();
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    size_t digits = 0;
    while (i < n && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; ++digits; }
    if (i < n && s[i] == '.') {
        ++i;
        while (i < n && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; ++digits; }
    }
    if (digits == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        size_t exp_digits = 0;
        while (i < n && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; ++exp_digits; }
        if (exp_digits == 0) return false;
    }
    if (i != n) return false;
    value = std::strtod(s.c_str(), nullptr);
    return true;
}

bool Lexer::next(LexedCommand& out) {
    const auto& lines = file_->lines;
    const int end = end_ < 0 ? static_cast<int>(lines.size()) : std::min(end_, static_cast<int>(lines.size()));
    out.tokens.clear();
    while (line_ < end) {
        out.first_line = line_ + 1;
        bool more = true;
        while (more && line_ < end) {
            const int line_no = line_ + 1;
            more = lex_physical_line(file_, line_no, lines[line_], out.tokens, false);
            out.last_line = line_no;
            ++line_;
        }
        if (!out.tokens.empty()) return true;
    }
    return false;
}

std::string first_word(const std::string& line) {
    size_t i = 0;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r' || line[i] == '\f' || line[i] == '\v')) ++i;
    size_t j = i;
    while (j < line.size() && !is_separator(line[j]) && line[j] != ';' && line[j] != '(' && line[j] != ')') ++j;
    return to_lower(line.substr(i, j - i));
}

bool definition_open(const std::string& text) {
    bool open = false;
    for (const std::string& l : split_lines(text)) {
        const std::string w = first_word(l);
        if (!open && (w == "def" || w == "define")) open = true;
        else if (open && w == "end") open = false;
    }
    return open;
}

bool Lexer::take_definition(int& first, int& last) {
    const auto& lines = file_->lines;
    const int end = end_ < 0 ? static_cast<int>(lines.size()) : std::min(end_, static_cast<int>(lines.size()));
    for (int k = line_; k < end; ++k) {
        if (first_word(lines[k]) == "end") {
            first = line_ + 1;
            last = k;
            line_ = k + 1;
            return true;
        }
    }
    return false;
}

bool Lexer::ends_with_continuation(const std::string& line) {
    std::vector<Token> toks;
    return lex_physical_line(nullptr, 1, line, toks, true);
}

std::vector<Token> lex_line_lenient(const std::string& line) {
    std::vector<Token> toks;
    lex_physical_line(nullptr, 1, line, toks, true);
    return toks;
}

} // namespace odec
