#include "lang/interpreter.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
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

#include "engine/fos.h"
#include "engine/verdict.h"
#include "fish/ast.h"
#include "fish/intrinsics.h"
#include "fish/runtime.h"

namespace odec {

namespace {

// FISH reaches the session through this.
class SessionHost final : public fish::Host {
public:
    explicit SessionHost(Interpreter& in) : in_(in) {}
    Model& model() override { return in_.model; }
    bool run_commands(const std::shared_ptr<const SourceFile>& file, int first, int last) override {
        const bool ok = in_.run_lines(file, first, last);
        // The commands may have replaced the model ('new', 'restore') or changed its blocks:
        // what FISH derived from it is rebuilt when next asked.
        in_.fish().model_changed();
        return ok;
    }
    std::ostream& out() override { return in_.out; }
    std::ostream& err() override { return in_.err; }
    bool interrupted() override { return in_.interrupt.load(); }
    std::string solve_verdict() override;
    double fos_factor() override { return in_.last_fos ? in_.last_fos->factor : 0.0; }
    bool confine_files() override { return in_.limits.confine_files; }

private:
    Interpreter& in_;
};

std::string SessionHost::solve_verdict() { return in_.last_solve ? outcome_name(in_.last_solve->outcome) : ""; }

} // namespace

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

bool LogBuf::open(const std::string& path, std::string& error) {
    close();
    const int fd = open_for_writing(path, O_APPEND, error);
    if (fd < 0) return false;
    fd_ = fd;
    path_ = path;
    setp(buf_, buf_ + sizeof buf_);
    return true;
}

void LogBuf::close() {
    if (fd_ >= 0 && flush_buffer()) {
        const int fd = fd_;
        fd_ = -1; // the descriptor is released whatever close() says
        setp(nullptr, nullptr);
        if (::close(fd) != 0) fail(errno);
    }
    report_failure();
}

bool LogBuf::flush_buffer() {
    if (fd_ < 0) return false;
    const std::size_t n = static_cast<std::size_t>(pptr() - pbase());
    if (n > 0 && !write_all(fd_, pbase(), n)) {
        fail(errno);
        return false;
    }
    setp(buf_, buf_ + sizeof buf_);
    return true;
}

void LogBuf::fail(int error_number) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    setp(nullptr, nullptr);
    failure_ = "the log '" + path_ + "' cannot be written: " + std::strerror(error_number) + "; the log is closed\n";
}

void LogBuf::report_failure() {
    if (failure_.empty()) return;
    if (report_) {
        report_->sputn(failure_.data(), static_cast<std::streamsize>(failure_.size()));
        report_->pubsync();
    }
    failure_.clear();
}

int LogBuf::overflow(int c) {
    if (!flush_buffer()) return traits_type::eof();
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    *pptr() = static_cast<char>(c);
    pbump(1);
    return c;
}

int LogBuf::sync() { return flush_buffer() ? 0 : -1; }

// A write succeeds when either copy took it: a failing screen (stdout on a full disk, a closed
// pipe) must not put the stream in a failed state, which would silently end the log too.
int TeeBuffer::overflow(int c) {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = static_cast<char>(c);
    const bool logged = logging() && log_->sputc(ch) != traits_type::eof();
    const bool shown = main_->sputc(ch) != traits_type::eof();
    return logged || shown ? c : traits_type::eof();
}

std::streamsize TeeBuffer::xsputn(const char* s, std::streamsize n) {
    const std::streamsize logged = logging() ? log_->sputn(s, n) : 0;
    return std::max(logged, main_->sputn(s, n));
}

int TeeBuffer::sync() {
    // The screen first: a message about the log (written on the screen's error stream) then
    // comes after what was shown before it.
    const bool shown = main_->pubsync() == 0;
    const bool logged = logging() && log_->pubsync() == 0;
    if (log_) log_->report_failure();
    return logged || shown ? 0 : -1;
}

Interpreter::Interpreter(Model& m, const CommandTable& t, std::ostream& o, std::ostream& e)
    : model(m), table(t), out_tee_(o.rdbuf()), err_tee_(e.rdbuf()), out(&out_tee_), err(&err_tee_),
      fish_host_(std::make_unique<SessionHost>(*this)), fish_(std::make_unique<fish::Runtime>(*fish_host_)) {
    fish_->budget = &limits.fish_steps;
    log_file_.set_report(err_tee_.main());
}

Interpreter::~Interpreter() { close_log(); }

bool Interpreter::fish_running() const { return !fish_->calls.empty(); }

bool Interpreter::open_log(std::string& error) {
    close_log();
    std::string why;
    if (!log_file_.open(log_path, why)) {
        error = "cannot open the log file '" + log_path + "': " + why;
        return false;
    }
    out_tee_.set_log(&log_file_);
    err_tee_.set_log(&log_file_);
    out.clear(); // a screen that failed before must not keep the log from starting
    err.clear();
    return true;
}

void Interpreter::close_log() {
    out.flush();
    err.flush();
    out_tee_.set_log(nullptr);
    err_tee_.set_log(nullptr);
    log_file_.close();
}

bool Interpreter::execute(const LexedCommand& cmd, bool echo_command) {
    ++model.edits; // (ContactSet::rest: whatever a command changes is not trusted to be as it was)
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
        for (int l = cmd.first_line; l <= cmd.last_line && log_is_on(); ++l) {
            const std::string line = "odec> " + file->lines[l - 1] + "\n";
            log_file_.sputn(line.data(), static_cast<std::streamsize>(line.size()));
        }
    }
    // Histories of FISH values read through the runtime (a `new` or `restore` drops the hook).
    if (!model.histories.external) {
        fish::Runtime* rt = fish_.get();
        model.histories.external = [rt](const History& h, int number, double& value, std::string& error) {
            try {
                const fish::Value v = rt->value_for_command(h.source, SourceLoc{});
                if (!v.is_number() && v.type != fish::Type::Bool) { // true and false record 1 and 0
                    error = "'@" + h.source + "' is " + std::string(fish::type_name(v)) + ", not a number";
                    return false;
                }
                value = v.number();
                if (!std::isfinite(value)) {
                    error = "'@" + h.source + "' is " + std::string(std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf") +
                            ", not a finite number";
                    return false;
                }
                return true;
            } catch (CommandError& e) {
                // The call came from the history, not from a line of a file.
                for (std::string& note : e.diag.notes) {
                    const std::string outside = ", called at <input>:0";
                    if (note.size() > outside.size() && note.compare(note.size() - outside.size(), outside.size(), outside) == 0) {
                        note.replace(note.size() - outside.size(), outside.size(), ", sampled by history " + std::to_string(number));
                    }
                }
                // Not located when the name itself is missing (a model restored without its FISH).
                error = e.diag.loc.file ? format_diagnostic(e.diag)
                                        : e.diag.what + (e.diag.notes.empty() ? "" : " (" + e.diag.notes[0] + ")");
            } catch (const std::bad_alloc&) {
                error = "out of memory";
            }
            return false;
        };
    }
    try {
        if (is_fish_statement(cmd)) {
            run_fish_statement(cmd);
            out.flush();
            return true;
        }
        if (is_fish_set(cmd)) {
            run_fish_set(cmd);
            out.flush();
            return true;
        }
        const Args args = parse_command(table, substitute(cmd.tokens), &named_ranges);
        if (cycling > 0 && !args.command->not_while_cycling.empty()) {
            const std::string& name = args.command->name;
            fail(cmd.tokens.front().loc, "'" + name + "' cannot run while the model cycles: " + args.command->not_while_cycling,
                 {"FISH ran it during 'step' or 'solve' (a 'whilestepping' function or a FISH history): run it "
                  "between the steps, from a function called outside them"},
                 name);
        }
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

std::function<std::string(Model&)> Interpreter::stepping_functions() {
    const std::vector<fish::Symbol*> fns = fish_->stepping();
    if (fns.empty()) return {};
    fish::Runtime* rt = fish_.get();
    return [rt, fns](Model&) -> std::string {
        try {
            for (fish::Symbol* s : fns) {
                if (s->fn) rt->call(*s, s->fn->loc);
            }
        } catch (const CommandError& e) {
            return "a 'whilestepping' function failed: " + format_diagnostic(e.diag);
        } catch (const fish::FishError& e) {
            return "a 'whilestepping' function failed: " + format_diagnostic(e.diag);
        }
        return "";
    };
}

bool Interpreter::run_lexer(Lexer& lex, bool echo_commands) {
    LexedCommand cmd;
    for (;;) {
        try {
            if (!lex.next(cmd)) break;
        } catch (const CommandError& e) {
            err << format_diagnostic(e.diag);
            return false;
        } catch (const std::bad_alloc&) {
            err << "error: out of memory reading '" << lex.file()->name << "'\n";
            return false;
        }
        if (interrupted_here(cmd)) return false;
        const std::string& verb = cmd.tokens.front().lower;
        if (cmd.tokens.front().kind == TokenKind::Word && (verb == "def" || verb == "define")) {
            if (!define_fish(cmd, lex, echo_commands)) return false;
            continue;
        }
        if (!execute(cmd, echo_commands)) return false;
        if (quit_requested) break;
        if (return_requested) {
            return_requested = false;
            break;
        }
    }
    return true;
}

bool Interpreter::run_text(const std::string& name, const std::string& text, bool echo_commands) {
    auto file = std::make_shared<SourceFile>();
    file->name = name;
    file->lines = split_lines(text);
    Lexer lex(file);
    return run_lexer(lex, echo_commands);
}

bool Interpreter::run_lines(const std::shared_ptr<const SourceFile>& file, int first, int last) {
    Lexer lex(file, first, last);
    LexedCommand cmd;
    for (;;) {
        try {
            if (!lex.next(cmd)) break;
        } catch (const CommandError& e) {
            err << format_diagnostic(e.diag);
            return false;
        }
        if (interrupted_here(cmd)) return false;
        if (limits.fish_steps >= 0) {
            const long long cost = kCommandFishSteps + kCommandFishStepsPerBlock * model.blocks.size();
            if (limits.fish_steps < cost) {
                const SourceLoc& l = cmd.tokens.front().loc;
                err << (l.file ? l.file->name : std::string("<input>")) << ":" << l.line << ":" << l.col
                    << ": error: this session's bound on FISH work is reached (a command costs " << cost
                    << " loop iterations here)\n";
                return false;
            }
            limits.fish_steps -= cost;
        }
        if (!execute(cmd, false)) return false;
        if (quit_requested) break;
    }
    return true;
}

bool Interpreter::define_fish(const LexedCommand& header, Lexer& lex, bool echo_command) {
    const auto& file = header.tokens.front().loc.file;
    const int line = header.first_line;
    if (echo_command && echo && !quiet) out << file->name << ":" << line << "> " << file->lines[line - 1] << "\n";
    int first = 0, last = 0;
    if (!lex.take_definition(first, last)) {
        Diagnostic d{header.tokens.front().loc,
                     "'" + header.tokens.front().text + "' has no 'end': the definition runs to the end of the " +
                         (file->name == "<prompt>" ? "input" : "file"),
                     {"end the function with a line 'end'"}, "fish"};
        err << format_diagnostic(d);
        return false;
    }
    try {
        const fish::Line head = fish::lex_line(file, line, file->lines[line - 1]);
        std::vector<fish::Line> body;
        body.reserve(static_cast<size_t>(last - first + 1));
        // The lines of a `command ... endcommand` block are commands, read when the block runs:
        // a word FISH has no use for there ('call ./part.dat') is no error of the definition.
        bool in_command = false;
        for (int l = first; l <= last; ++l) {
            fish::Line line;
            try {
                line = fish::lex_line(file, l, file->lines[l - 1]);
            } catch (const CommandError&) {
                if (!in_command) throw;
                line = fish::lex_line(file, l, "");
            }
            const auto& t = line.tokens;
            const bool word = !t.empty() && t[0].kind == fish::Tok::Name;
            if (word && !in_command && t[0].lower == "command" && (t.size() == 1 || t[1].kind == fish::Tok::End)) {
                in_command = true;
            } else if (word && in_command && (t[0].lower == "endcommand" || t[0].lower == "end_command")) {
                in_command = false;
            }
            body.push_back(std::move(line));
        }
        fish_->define(head, body);
    } catch (const CommandError& e) {
        err << format_diagnostic(e.diag);
        return false;
    } catch (const std::bad_alloc&) {
        out_of_memory(header);
        return false;
    }
    return true;
}

bool Interpreter::is_fish_statement(const LexedCommand& cmd) const {
    const Token& t = cmd.tokens.front();
    if (t.kind != TokenKind::Word) return false;
    if (t.text.size() > 1 && t.text[0] == '@') return true;
    // A FISH function named alone, as UDEC scripts call them, when no command has that name.
    if (!fish_->is_function(t.lower)) return false;
    std::vector<std::string> cand;
    return table.match(t.lower, &cand) == nullptr && cand.empty();
}

void Interpreter::run_fish_statement(const LexedCommand& cmd) {
    const auto& file = cmd.tokens.front().loc.file;
    std::string text = file->lines[cmd.first_line - 1];
    const size_t col0 = static_cast<size_t>(cmd.tokens.front().loc.col - 1);
    // A statement continued over lines (`&`) is read as one line.
    for (int l = cmd.first_line + 1; l <= cmd.last_line; ++l) {
        const size_t amp = text.find_last_of('&');
        if (amp != std::string::npos) text.erase(amp);
        text += " " + file->lines[l - 1];
    }
    fish_->run_statement(fish::lex_line(file, cmd.first_line, text, col0));
}

namespace {

// Whether `lower` is a word the command itself knows: a keyword, a range filter or a choice.
bool command_word(const CommandSpec& c, const std::string& lower) {
    auto in = [&](const KeywordSpec& k) {
        if (abbreviates(lower, k.name, k.min)) return true;
        for (const ValueSpec& v : k.values) {
            for (const std::string& w : v.choices) {
                if (w == lower) return true;
            }
        }
        return false;
    };
    if (in(c.positional)) return true;
    for (const KeywordSpec& k : c.keywords) {
        if (in(k)) return true;
    }
    for (const KeywordSpec& k : range_filters()) {
        if (in(k)) return true;
    }
    return false;
}

// Whether an '=' follows token t on its line (`set kp = 7`: the '=' is a separator to the lexer).
bool equals_follows(const Token& t) {
    if (!t.loc.file || t.loc.line < 1 || t.loc.line > static_cast<int>(t.loc.file->lines.size())) return false;
    const std::string& line = t.loc.file->lines[static_cast<size_t>(t.loc.line - 1)];
    size_t k = static_cast<size_t>(t.loc.col - 1) + t.text.size();
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    return k < line.size() && line[k] == '=';
}

} // namespace

namespace {

// Whether `lower` is a keyword (or a choice) of the command itself, range filters aside.
bool own_keyword(const CommandSpec& c, const std::string& lower) {
    for (const KeywordSpec& k : c.keywords) {
        if (abbreviates(lower, k.name, k.min)) return true;
    }
    return false;
}

bool at_word(const Token& t) { return t.kind == TokenKind::Word && t.text.size() > 1 && t.text[0] == '@'; }

std::string lower_of(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

} // namespace

bool Interpreter::is_fish_set(const LexedCommand& cmd) const {
    if (cmd.tokens.size() < 2) return false;
    const CommandSpec* verb = table.match(cmd.tokens[0].lower, nullptr);
    if (!verb || verb->name != "set") return false;
    const Token& t = cmd.tokens[1];
    if (t.kind != TokenKind::Word) return false;
    if (at_word(t)) return true;
    if (own_keyword(*verb, t.lower)) return false;
    // A name FISH knows, or a new name given a value with '='.
    return fish_->find(t.lower) || (equals_follows(t) && !fish::find_intrinsic(t.lower));
}

void Interpreter::run_fish_set(const LexedCommand& cmd) {
    // Pairs `name [=] value`; a value is a number, a string, a vector (x,y,z) or a FISH name.
    // Every pair is checked first; then the values are taken and set in order (`set a = 1
    // b = a` gives b 1). Only a FISH function named as a value, failing, stops part way.
    const std::vector<Token>& t = cmd.tokens;
    const CommandSpec* verb = table.match(t[0].lower, nullptr);
    struct Pair {
        const Token* name;
        std::string text;  // the variable's name as written
        fish::Value value; // a literal value, or
        const Token* word = nullptr; // a FISH name whose value is taken
    };
    std::vector<Pair> pairs;
    size_t k = 1;
    while (k < t.size()) {
        const Token& n = t[k];
        const bool at = at_word(n);
        const std::string name = at ? n.text.substr(1) : n.text;
        const std::string lname = lower_of(name);
        if (n.kind != TokenKind::Word || (!at && own_keyword(*verb, n.lower))) {
            fail(n.loc, "unexpected '" + n.text + "': expected the name of a FISH variable",
                 {"'set name = value' sets FISH variables; give settings on a line of their own"}, "set");
        }
        if (fish_->command_local(lname)) {
            fail(n.loc, "'" + name + "' is an argument or local of '" + fish_->command_function() +
                            "': 'set' gives values to global variables",
                 {"assign it in the function, or as a statement here: @" + name + " = ..."}, "set");
        }
        const fish::Symbol* s = fish_->find(lname);
        if (s && s->fn) fail(n.loc, "'" + name + "' is a FISH function: 'set' gives values to variables", {}, "set");
        if (s && s->array) fail(n.loc, "'" + name + "' is a FISH array: 'set' gives one value", {}, "set");
        if (!s && fish::find_intrinsic(lname)) {
            fail(n.loc, "'" + name + "' is a FISH intrinsic: 'set' gives values to variables", {}, "set");
        }
        if (++k >= t.size()) fail(n.loc, "'" + name + "' needs a value: set " + name + " = value", {}, "set");
        Pair p{&n, name, fish::Value::null()};
        const Token& v = t[k];
        if (v.kind == TokenKind::Number) {
            if (!std::isfinite(v.number)) fail(v.loc, "'" + v.text + "' is not a finite number", {}, "set");
            const bool whole = v.text.find_first_of(".eE") == std::string::npos && std::fabs(v.number) < 9.2e18;
            p.value = whole ? fish::Value::integer(static_cast<long long>(v.number)) : fish::Value::real(v.number);
            ++k;
        } else if (v.kind == TokenKind::String) {
            p.value = fish::Value::string(v.text);
            ++k;
        } else if (v.kind == TokenKind::LParen) {
            Eigen::Vector3d x;
            for (int i = 0; i < 3; ++i) {
                if (k + 1 + i >= t.size() || t[k + 1 + i].kind != TokenKind::Number || !std::isfinite(t[k + 1 + i].number)) {
                    fail(v.loc, "a vector value is three finite numbers in parentheses: (x,y,z)", {}, "set");
                }
                x[i] = t[k + 1 + i].number;
            }
            if (k + 4 >= t.size() || t[k + 4].kind != TokenKind::RParen) {
                fail(v.loc, "a vector value is three finite numbers in parentheses: (x,y,z)", {}, "set");
            }
            p.value = fish::Value::vector(x);
            k += 5;
        } else if (v.kind == TokenKind::Word) {
            const std::string vname = lower_of(at_word(v) ? v.text.substr(1) : v.text);
            const fish::Intrinsic* in = fish::find_intrinsic(vname);
            bool earlier = false; // set by an earlier pair of this line
            for (const Pair& q : pairs) earlier = earlier || lower_of(q.text) == vname;
            if (!earlier && !fish_->command_local(vname) && !fish_->find(vname) && !(in && in->min_args == 0)) {
                fail(v.loc, "'" + v.text + "' is no FISH variable or function: expected the value of '" + name + "'",
                     {"a string value is written in quotes: '" + v.text + "'"}, "set");
            }
            p.word = &v;
            ++k;
        } else {
            fail(v.loc, "unexpected '" + v.text + "': expected the value of '" + name + "'", {}, "set");
        }
        pairs.push_back(p);
    }
    for (Pair& p : pairs) {
        if (p.word) {
            const Token& v = *p.word;
            p.value = fish_->value_for_command(at_word(v) ? v.text.substr(1) : v.text, v.loc);
            if (p.value.is_number() && !std::isfinite(p.value.number())) {
                fail(v.loc, "'" + v.text + "' is not a finite number", {}, "set");
            }
        }
        const std::string lname = lower_of(p.text);
        if (!fish_->find(lname)) {
            // A mistyped setting would otherwise pass unnoticed as a new variable.
            std::vector<std::string> names;
            for (const KeywordSpec& kw : verb->keywords) names.push_back(kw.name);
            const auto near = lname.size() >= 4 ? closest_words(lname, names, 1) : std::vector<std::string>{};
            if (!near.empty()) {
                const SourceLoc& l = p.name->loc;
                err << (l.file ? l.file->name : std::string("<input>")) << ":" << l.line << ":" << l.col
                    << ": warning: '" << p.text << "' is no setting of 'set' (did you mean '" << near.front()
                    << "'?): it is now a FISH variable\n";
            }
        }
        fish::Symbol& s = fish_->symbol(p.text);
        s.value = p.value;
        s.assigned = true;
    }
}

std::vector<Token> Interpreter::substitute(const std::vector<Token>& tokens) {
    const CommandSpec* verb = table.match(tokens.front().lower, nullptr);
    // A FISH variable or function named without '@' where the command expects a value takes
    // its value too, as UDEC and 3DEC 4 scripts write it ('cycle time timeStep', 'save fName'):
    // a word the command does not know itself, naming a function or an assigned variable (in a
    // function's command block, first an argument or local of the function).
    auto bare = [&](const Token& t, size_t k) {
        if (k == 0 || t.kind != TokenKind::Word || !verb || verb->name == "history" || verb->name == "list") return false;
        if (const fish::Value* local = fish_->command_local(t.lower)) {
            return local->type != fish::Type::Array && !command_word(*verb, t.lower);
        }
        const fish::Symbol* s = fish_->find(t.lower);
        if (!s || !(s->fn || s->assigned) || s->array) return false;
        return !command_word(*verb, t.lower);
    };
    // `hist zz` with zz a FISH function or variable (as UDEC and 3DEC 4 write it): `hist @zz`.
    auto bare_history = [&](const Token& t, size_t k) {
        if (k != 1 || t.kind != TokenKind::Word || !verb || verb->name != "history") return false;
        if (fish_->command_local(t.lower)) return !command_word(*verb, t.lower);
        const fish::Symbol* s = fish_->find(t.lower);
        const fish::Intrinsic* in = s ? nullptr : fish::find_intrinsic(t.lower);
        return ((s && !s->array) || (in && in->min_args == 0)) && !command_word(*verb, t.lower);
    };
    bool any = false;
    for (size_t k = 0; k < tokens.size(); ++k) {
        const Token& t = tokens[k];
        any = any || (t.kind == TokenKind::Word && t.text.size() > 1 && t.text[0] == '@') || bare(t, k) ||
              bare_history(t, k);
    }
    if (!any) return tokens;
    std::vector<Token> out;
    out.reserve(tokens.size() + 4);
    for (size_t k = 0; k < tokens.size(); ++k) {
        const Token& t = tokens[k];
        const bool at = t.kind == TokenKind::Word && t.text.size() > 1 && t.text[0] == '@';
        const bool bare_hist = !at && bare_history(t, k);
        if (!at && !bare_hist && !bare(t, k)) {
            out.push_back(t);
            continue;
        }
        const std::string name = at ? t.text.substr(1) : t.text;
        // `list @x` names what it prints.
        if (at && verb && verb->name == "list") {
            out.push_back(t);
            continue;
        }
        // `hist @f` records the function as the model cycles: `hist fish f`.
        if (k == 1 && verb && verb->name == "history") {
            Token w = t;
            w.text = w.lower = "fish";
            out.push_back(w);
            Token n = t;
            n.text = name;
            n.lower = at ? t.lower.substr(1) : t.lower;
            n.kind = TokenKind::String;
            out.push_back(n);
            continue;
        }
        const fish::Value v = fish_->value_for_command(name, t.loc);
        Token r = t;
        switch (v.type) {
        case fish::Type::Int:
        case fish::Type::Float:
        case fish::Type::Bool:
            r.kind = TokenKind::Number;
            r.number = v.number();
            r.text = r.lower = fish::to_text(v.type == fish::Type::Bool ? fish::Value::integer(v.i) : v);
            out.push_back(r);
            break;
        case fish::Type::String:
            r.kind = TokenKind::String;
            r.text = v.s;
            r.lower = v.s;
            for (char& c : r.lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            out.push_back(r);
            break;
        case fish::Type::Vector: {
            Token p = t;
            p.kind = TokenKind::LParen;
            p.text = p.lower = "(";
            out.push_back(p);
            for (int i = 0; i < 3; ++i) {
                Token x = t;
                x.kind = TokenKind::Number;
                x.number = v.v[i];
                x.text = x.lower = fish::to_text(fish::Value::real(v.v[i]));
                out.push_back(x);
            }
            p.kind = TokenKind::RParen;
            p.text = p.lower = ")";
            out.push_back(p);
            break;
        }
        default:
            fail(t.loc, "'" + t.text + "' is " + fish::type_name(v) + ": a command takes a number, a string or a vector", {},
                 "fish");
        }
    }
    return out;
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
    const bool good = run_lexer(lex, true);
    call_stack_.pop_back();
    display_stack_.pop_back();
    return good;
}

} // namespace odec
