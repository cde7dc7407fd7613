#include "fish/lexer.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>

namespace odec::fish {

namespace {

bool name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == '$'; }
bool name_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$' || c == '.';
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

} // namespace

Line lex_line(const std::shared_ptr<const SourceFile>& file, int line_no, const std::string& text, size_t col0) {
    Line line;
    line.loc.file = file;
    line.loc.line = line_no;
    line.loc.col = static_cast<int>(col0) + 1;
    const size_t n = text.size();
    size_t i = col0;
    auto here = [&](size_t at, size_t len) {
        SourceLoc l;
        l.file = file;
        l.line = line_no;
        l.col = static_cast<int>(at) + 1;
        l.length = static_cast<int>(len == 0 ? 1 : len);
        return l;
    };
    while (i < n) {
        const char c = text[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
            ++i;
            continue;
        }
        if (c == ';') break;
        Token t;
        if (c == '\'' || c == '"') {
            const size_t close = text.find(c, i + 1);
            if (close == std::string::npos) {
                fail(here(i, n - i), std::string("unterminated string: no closing ") + c + " on this line",
                     {"a FISH string ends on the line it starts"}, "fish");
            }
            t.kind = Tok::String;
            t.text = text.substr(i + 1, close - i - 1);
            t.loc = here(i, close - i + 1);
            i = close + 1;
        } else if (std::isdigit(static_cast<unsigned char>(c)) ||
                   (c == '.' && i + 1 < n && std::isdigit(static_cast<unsigned char>(text[i + 1])))) {
            size_t j = i;
            bool is_float = false;
            while (j < n && std::isdigit(static_cast<unsigned char>(text[j]))) ++j;
            if (j < n && text[j] == '.') {
                is_float = true;
                ++j;
                while (j < n && std::isdigit(static_cast<unsigned char>(text[j]))) ++j;
            }
            if (j < n && (text[j] == 'e' || text[j] == 'E')) {
                size_t k = j + 1;
                if (k < n && (text[k] == '+' || text[k] == '-')) ++k;
                if (k < n && std::isdigit(static_cast<unsigned char>(text[k]))) {
                    while (k < n && std::isdigit(static_cast<unsigned char>(text[k]))) ++k;
                    j = k;
                    is_float = true;
                }
            }
            if (j < n && name_start(text[j])) {
                fail(here(i, j - i + 1), "'" + text.substr(i, j - i + 1) + "' is not a number",
                     {"a name starts with a letter or '_'"}, "fish");
            }
            t.text = text.substr(i, j - i);
            t.loc = here(i, j - i);
            if (!is_float) {
                errno = 0;
                const long long v = std::strtoll(t.text.c_str(), nullptr, 10);
                if (errno == ERANGE) {
                    is_float = true;
                } else {
                    t.kind = Tok::Int;
                    t.integer = v;
                }
            }
            if (is_float) {
                t.kind = Tok::Float;
                t.number = std::strtod(t.text.c_str(), nullptr);
            }
            i = j;
        } else if (name_start(c) || (c == '@' && i + 1 < n && name_start(text[i + 1]))) {
            const size_t start = i;
            if (c == '@') {
                t.at = true;
                ++i;
            }
            size_t j = i;
            while (j < n && name_char(text[j])) ++j;
            // A trailing '.' belongs to no name.
            while (j > i + 1 && text[j - 1] == '.') --j;
            t.kind = Tok::Name;
            t.text = text.substr(i, j - i);
            t.loc = here(start, j - start);
            i = j;
        } else {
            static const char* const two[] = {"<=", ">=", "==", "!=", "~=", "<>", "->"};
            t.kind = Tok::Op;
            t.loc = here(i, 1);
            for (const char* op : two) {
                if (i + 1 < n && text[i] == op[0] && text[i + 1] == op[1]) {
                    t.text = op;
                    t.loc.length = 2;
                    break;
                }
            }
            if (t.text.empty()) {
                if (std::string("+-*/^=#<>()&|,[]!:").find(c) == std::string::npos) {
                    fail(here(i, 1), std::string("'") + c + "' has no meaning in FISH",
                         {"expected a name, a number, a string or an operator (+ - * / ^ = # < > & |)"}, "fish");
                }
                t.text = std::string(1, c);
            }
            i += t.text.size();
        }
        t.lower = lower(t.text);
        line.tokens.push_back(std::move(t));
    }
    Token end;
    end.kind = Tok::End;
    end.loc = here(i < n ? i : n, 1);
    line.tokens.push_back(std::move(end));
    if (line.tokens.size() > 1) line.loc = line.tokens.front().loc;
    return line;
}

} // namespace odec::fish
