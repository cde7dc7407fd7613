#include "lang/source.h"

namespace odec {

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::string cur;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') {
            if (!cur.empty() && cur.back() == '\r') cur.pop_back();
            lines.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    if (!cur.empty() && cur.back() == '\r') cur.pop_back();
    if (!cur.empty()) lines.push_back(cur);
    return lines;
}

std::string format_diagnostic(const Diagnostic& d) {
    std::string out;
    const SourceLoc& l = d.loc;
    if (l.file) {
        out += l.file->name + ":" + std::to_string(l.line) + ":" + std::to_string(l.col) + ": ";
    }
    out += "error: " + d.what + "\n";
    if (l.file && l.line >= 1 && l.line <= static_cast<int>(l.file->lines.size())) {
        std::string text = l.file->lines[l.line - 1];
        // Tabs would misplace the caret: show them as single spaces.
        for (char& c : text) {
            if (c == '\t') c = ' ';
        }
        out += "    " + text + "\n";
        std::string caret(4 + std::max(0, l.col - 1), ' ');
        caret += '^';
        if (l.length > 1) caret += std::string(l.length - 1, '~');
        out += caret + "\n";
    }
    for (const std::string& n : d.notes) out += "  " + n + "\n";
    if (!d.help_topic.empty()) out += "  see 'help " + d.help_topic + "'\n";
    return out;
}

void fail(const SourceLoc& loc, std::string what, std::vector<std::string> notes, std::string help_topic) {
    throw CommandError{Diagnostic{loc, std::move(what), std::move(notes), std::move(help_topic)}};
}

} // namespace odec
