// Where text came from: a file (or the prompt, or the command line) and a line and column in
// it, so that every error can point at the word that caused it.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace odec {

struct SourceFile {
    std::string name;               // as shown in messages: the path as given, "<prompt>", ...
    std::string directory;          // for `call` with a relative path
    std::vector<std::string> lines; // without line ends
};

struct SourceLoc {
    std::shared_ptr<const SourceFile> file;
    int line = 0;   // 1-based
    int col = 0;    // 1-based
    int length = 1; // characters under the caret
};

// Split text into lines, dropping "\n" and "\r\n" line ends.
std::vector<std::string> split_lines(const std::string& text);

// An error a person can act on. `what` is the first line after "error: "; `notes` follow
// on lines of their own; `help_topic` adds "see 'help <topic>'".
struct Diagnostic {
    SourceLoc loc;
    std::string what;
    std::vector<std::string> notes;
    std::string help_topic;
};

// file:line:col: error: what
//     <the source line>
//     ^~~~ under the offending word
//   note lines
//   see 'help topic'
std::string format_diagnostic(const Diagnostic& d);

// Thrown by the parser and by command handlers before they change anything.
struct CommandError {
    Diagnostic diag;
};

[[noreturn]] void fail(const SourceLoc& loc, std::string what, std::vector<std::string> notes = {},
                       std::string help_topic = {});

} // namespace odec
