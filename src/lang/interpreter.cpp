#include "lang/interpreter.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <new>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace odec {

namespace {

std::string directory_of(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string canonical(const std::string& path) {
    char buf[PATH_MAX];
    if (realpath(path.c_str(), buf)) return buf;
    return path;
}

} // namespace

bool read_file_text(const std::string& path, std::string& text, std::string& error, std::size_t max_bytes) {
    text.clear();
    // O_NONBLOCK: opening a named pipe must not wait for a writer; it is refused below.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        error = std::strerror(errno);
        return false;
    }
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    struct stat st;
    if (::fstat(fd, &st) != 0) {
        error = std::strerror(errno);
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        const char* what = S_ISDIR(st.st_mode)    ? "a directory"
                           : S_ISFIFO(st.st_mode) ? "a named pipe"
                           : S_ISCHR(st.st_mode)  ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "not a plain file";
        error = std::string("it is ") + what + ", not a regular file";
        return false;
    }
    const auto size = static_cast<unsigned long long>(st.st_size);
    if (size > max_bytes) {
        error = "the file is larger than " + std::to_string(max_bytes >> 20) + " MiB (" + std::to_string(size) +
                " bytes)";
        return false;
    }
    text.resize(static_cast<std::size_t>(size));
    std::size_t got = 0;
    char more[4096];
    for (;;) {
        // Into the space the size promised, then in chunks (a file may grow while it is read).
        char* into = got < text.size() ? &text[got] : more;
        const std::size_t room = got < text.size() ? text.size() - got : sizeof more;
        const ssize_t r = ::read(fd, into, room);
        if (r == 0) break;
        if (r < 0) {
            if (errno == EINTR) continue;
            error = std::strerror(errno);
            text.clear();
            return false;
        }
        const auto n = static_cast<std::size_t>(r);
        if (into == more) {
            if (got + n > max_bytes) {
                error = "the file is larger than " + std::to_string(max_bytes >> 20) + " MiB";
                text.clear();
                return false;
            }
            text.append(more, n);
        }
        got += n;
    }
    text.resize(got);
    return true;
}

std::string read_file_text(const std::string& path, bool& ok) {
    std::string text, error;
    ok = read_file_text(path, text, error);
    return text;
}

// A write succeeds when either copy took it: a failing screen (stdout on a full disk, a closed
// pipe) must not put the stream in a failed state, which would silently end the log too.
int TeeBuffer::overflow(int c) {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = static_cast<char>(c);
    const bool logged = log_ && log_->sputc(ch) != traits_type::eof();
    const bool shown = main_->sputc(ch) != traits_type::eof();
    return logged || shown ? c : traits_type::eof();
}

std::streamsize TeeBuffer::xsputn(const char* s, std::streamsize n) {
    const std::streamsize logged = log_ ? log_->sputn(s, n) : 0;
    return std::max(logged, main_->sputn(s, n));
}

int TeeBuffer::sync() {
    const bool logged = log_ && log_->pubsync() == 0;
    const bool shown = main_->pubsync() == 0;
    return logged || shown ? 0 : -1;
}

Interpreter::Interpreter(Model& m, const CommandTable& t, std::ostream& o, std::ostream& e)
    : model(m), table(t), out_tee_(o.rdbuf()), err_tee_(e.rdbuf()), out(&out_tee_), err(&err_tee_) {}

Interpreter::~Interpreter() { close_log(); }

bool Interpreter::open_log(std::string& error) {
    close_log();
    log_file_.open(log_path, std::ios::app);
    if (!log_file_) {
        error = "cannot open the log file '" + log_path + "': " + std::strerror(errno);
        return false;
    }
    out_tee_.set_log(log_file_.rdbuf());
    err_tee_.set_log(log_file_.rdbuf());
    out.clear(); // a screen that failed before must not keep the log from starting
    err.clear();
    return true;
}

void Interpreter::close_log() {
    out.flush();
    err.flush();
    out_tee_.set_log(nullptr);
    err_tee_.set_log(nullptr);
    if (log_file_.is_open()) log_file_.close();
}

bool Interpreter::execute(const LexedCommand& cmd, bool echo_command) {
    if (echo_command && echo && !quiet) {
        const auto& file = cmd.tokens.front().loc.file;
        for (int l = cmd.first_line; l <= cmd.last_line; ++l) {
            const std::string& text = file->lines[l - 1];
            if (l == cmd.first_line) {
                out << file->name << ":" << l << "> " << text << "\n";
            } else {
                out << std::string(file->name.size() + std::to_string(l).size() + 3, ' ') << text << "\n";
            }
        }
        out.flush();
    }
    if (log_is_on() && !(echo_command && echo && !quiet)) {
        // The log reads like a session: each command before its output.
        const auto& file = cmd.tokens.front().loc.file;
        for (int l = cmd.first_line; l <= cmd.last_line; ++l) log_file_ << "odec> " << file->lines[l - 1] << "\n";
    }
    try {
        const Args args = parse_command(table, cmd.tokens, &named_ranges);
        CommandContext ctx{model, *this, out};
        args.command->handler(ctx, args);
        out.flush();
        return true;
    } catch (const CommandError& e) {
        out.flush();
        err << format_diagnostic(e.diag);
        err.flush();
        return false;
    } catch (const ScriptFailed&) {
        return false;
    } catch (const std::bad_alloc&) {
        out_of_memory(cmd);
        return false;
    } catch (const std::length_error&) { // a container asked for more than it can ever hold
        out_of_memory(cmd);
        return false;
    }
}

void Interpreter::out_of_memory(const LexedCommand& cmd) {
    // What could not be allocated is gone by now, and it was usually large: the few small
    // strings of the message still fit. If even they do not, say it without them.
    out.flush();
    try {
        const Token& verb = cmd.tokens.front();
        std::vector<std::string> cand;
        const CommandSpec* spec = table.match(verb.lower, &cand);
        const std::string name = spec ? spec->name : verb.text;
        Diagnostic d{verb.loc, "out of memory while running '" + name + "'",
                     {"the command stopped part way: the model may keep what it had done"}, spec ? spec->name : ""};
        err << format_diagnostic(d);
    } catch (const std::bad_alloc&) {
        err << "error: out of memory\n";
    }
    err.flush();
}

bool Interpreter::interrupted_here(const LexedCommand& cmd) {
    if (!interrupt.load()) return false;
    // Ctrl-C stopped a command (a step, a solve): the rest of the script, and of every
    // script that called it, is not run. At the prompt the next line starts afresh.
    if (!cmd.tokens.empty()) {
        const SourceLoc& l = cmd.tokens.front().loc;
        err << (l.file ? l.file->name : std::string("<input>")) << ":" << l.line << ":" << l.col << ": ";
    }
    err << "interrupted: the script stops before this command\n";
    return true;
}

bool Interpreter::run_text(const std::string& name, const std::string& text, bool echo_commands) {
    auto file = std::make_shared<SourceFile>();
    file->name = name;
    file->lines = split_lines(text);
    Lexer lex(file);
    LexedCommand cmd;
    for (;;) {
        try {
            if (!lex.next(cmd)) break;
        } catch (const CommandError& e) {
            err << format_diagnostic(e.diag);
            return false;
        }
        if (interrupted_here(cmd)) return false;
        if (!execute(cmd, echo_commands)) return false;
        if (quit_requested) break;
        if (return_requested) {
            return_requested = false;
            break;
        }
    }
    return true;
}

bool Interpreter::run_file(const std::string& path, const SourceLoc* from) {
    const std::string canon = canonical(path);
    for (size_t k = 0; k < call_stack_.size(); ++k) {
        if (call_stack_[k] == canon) {
            std::string chain;
            for (size_t j = k; j < display_stack_.size(); ++j) chain += display_stack_[j] + " -> ";
            chain += path;
            Diagnostic d{from ? *from : SourceLoc{}, "'" + path + "' calls itself (" + chain + ")",
                         {"a file may not call a file that is still running"}, "call"};
            err << format_diagnostic(d);
            return false;
        }
    }
    if (call_stack_.size() >= static_cast<size_t>(kMaxCallDepth)) {
        // Each level of `call` takes C++ stack: thousands would overflow it.
        Diagnostic d{from ? *from : SourceLoc{},
                     "calls nest too deeply: calling '" + path + "' would make a chain of " +
                         std::to_string(call_stack_.size() + 1) + " files (at most " + std::to_string(kMaxCallDepth) +
                         ")",
                     {"the chain starts at '" + display_stack_.front() + "'"}, "call"};
        err << format_diagnostic(d);
        return false;
    }
    std::string text, why;
    bool ok = false;
    try {
        ok = read_file_text(path, text, why);
    } catch (const std::bad_alloc&) {
        why = "out of memory";
    } catch (const std::length_error&) {
        why = "out of memory";
    }
    if (!ok) {
        Diagnostic d{from ? *from : SourceLoc{}, "cannot open '" + path + "': " + why, {}, from ? "call" : ""};
        err << format_diagnostic(d);
        return false;
    }
    auto file = std::make_shared<SourceFile>();
    file->name = path;
    file->directory = directory_of(path);
    try {
        file->lines = split_lines(text);
    } catch (const std::bad_alloc&) {
        Diagnostic d{from ? *from : SourceLoc{}, "out of memory reading '" + path + "'", {}, from ? "call" : ""};
        err << format_diagnostic(d);
        return false;
    }
    call_stack_.push_back(canon);
    display_stack_.push_back(path);
    Lexer lex(file);
    LexedCommand cmd;
    bool good = true;
    for (;;) {
        try {
            if (!lex.next(cmd)) break;
        } catch (const CommandError& e) {
            err << format_diagnostic(e.diag);
            good = false;
            break;
        } catch (const std::bad_alloc&) {
            err << format_diagnostic(Diagnostic{from ? *from : SourceLoc{}, "out of memory reading '" + path + "'", {},
                                                from ? "call" : ""});
            good = false;
            break;
        }
        if (interrupted_here(cmd)) {
            good = false;
            break;
        }
        if (!execute(cmd, true)) {
            good = false;
            break;
        }
        if (quit_requested) break;
        if (return_requested) {
            return_requested = false;
            break;
        }
    }
    call_stack_.pop_back();
    display_stack_.pop_back();
    return good;
}

} // namespace odec
