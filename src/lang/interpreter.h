// Runs commands: from script files (with `call` nesting), from the command line, and from
// the prompt. Each command is parsed against the declarations, then its handler runs; a
// handler checks everything before it changes the model, so a failed command leaves the
// model exactly as it was.
#pragma once

#include <atomic>
#include <cstddef>
#include <fstream>
#include <functional>
#include <iosfwd>
#include <memory>
#include <ostream>
#include <streambuf>

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "engine/model.h"
#include "io/files.h"
#include "lang/lexer.h"
#include "lang/parser.h"

namespace odec {

namespace fish {
class Runtime;
class Host;
} // namespace fish

class Interpreter;
struct SolveVerdict; // engine/verdict.h
struct FosResult;    // engine/fos.h

// Picture options kept between plots of a session (`plot set ...`).
struct PlotSettings {
    int width = 1024, height = 768;          // pixels
    std::string view = "iso";                // iso, x, -x, y, -y, z, -z or eye
    Eigen::Vector3d eye = Eigen::Vector3d::Zero(); // m, when view is "eye"
    bool view_set = false;                   // a stored view wins over a cut's own view
    std::string background = "white";        // white, black or grey
    std::string map = "auto";                // auto (rainbow, or cool-warm for signed), rainbow, coolwarm, viridis, grey
};

// What a command handler works with.
struct CommandContext {
    Model& model;
    Interpreter& interp;
    std::ostream& out;
};

// The log file (`set log on`): what is written is buffered and written to the file; the first
// write that fails (a full disk) closes it, and report_failure() then says so, once, on
// `report` (the screen's error stream), so that a log never ends silently. The saying waits
// for report_failure() (at the next flush) so that it never cuts a line being shown.
class LogBuf : public std::streambuf {
public:
    LogBuf() = default;
    LogBuf(const LogBuf&) = delete;
    LogBuf& operator=(const LogBuf&) = delete;
    ~LogBuf() override { close(); }
    // Open `path` for appending (a regular file, or a character device such as /dev/null).
    bool open(const std::string& path, std::string& error);
    // Write what is buffered and close; a failure is reported as any other.
    void close();
    bool is_open() const { return fd_ >= 0; }
    void set_report(std::streambuf* report) { report_ = report; }
    // Say that a write failed and the log was closed, if one did since last said.
    void report_failure();

protected:
    int overflow(int c) override;
    int sync() override;

private:
    bool flush_buffer();
    void fail(int error_number);

    int fd_ = -1;
    std::string path_;
    std::streambuf* report_ = nullptr;
    std::string failure_; // the line not yet said
    char buf_[4096];
};

// Copies everything written to it into the log while one is open (`set log on`).
class TeeBuffer : public std::streambuf {
public:
    explicit TeeBuffer(std::streambuf* main) : main_(main) {}
    void set_log(LogBuf* log) { log_ = log; }
    std::streambuf* main() const { return main_; }

protected:
    int overflow(int c) override;
    std::streamsize xsputn(const char* s, std::streamsize n) override;
    int sync() override;

private:
    bool logging() const { return log_ && log_->is_open(); }
    std::streambuf* main_;
    LogBuf* log_ = nullptr;
};

// Thrown by `call` when the called file failed (its error is already reported).
struct ScriptFailed {};

class Interpreter {
public:
    Interpreter(Model& model, const CommandTable& table, std::ostream& out, std::ostream& err);
    ~Interpreter();

    // `set logfile name` and `set log on|off`: a copy of the output and of the commands, appended
    // to the file while on. Returns false with `error` when the file cannot be opened.
    bool open_log(std::string& error);
    void close_log();
    // False too once a write to it failed (which closed it and said so).
    bool log_is_on() const { return log_file_.is_open(); }
    std::string log_path = "odec.log";

    // Run a script; returns false at its first error, which is reported on err.
    // `from` is the `call` command that asked for it (nullptr for top-level files).
    bool run_file(const std::string& path, const SourceLoc* from = nullptr);
    // Run text (lines separated by newlines) under a display name such as "<command-line>".
    bool run_text(const std::string& name, const std::string& text, bool echo_commands);
    // Parse and execute one lexed command; false when it failed (reported on err).
    bool execute(const LexedCommand& cmd, bool echo_command);
    // Run the commands on lines first..last of file (a FISH `command ... endcommand` block),
    // without echo; false at the first error (reported).
    bool run_lines(const std::shared_ptr<const SourceFile>& file, int first, int last);
    // The FISH runtime of this session.
    fish::Runtime& fish() { return *fish_; }
    // What a step must run first: the FISH 'whilestepping' functions (empty when none). It gives
    // "" to go on, or the error that stops the cycle.
    std::function<std::string(Model&)> stepping_functions();
    // True (and said) when Ctrl-C interrupted an earlier command: the script stops before cmd.
    bool interrupted_here(const LexedCommand& cmd);

    Model& model;
    const CommandTable& table;

private:
    TeeBuffer out_tee_, err_tee_;
    LogBuf log_file_;

public:
    std::ostream out;   // the output stream given, copied into the log while it is on
    std::ostream err;

    bool echo = true;             // `set echo on|off`: echo script commands with file and line
    double progress_seconds = 3;  // wall time between progress lines of a long step or solve
    bool quiet = false;           // --quiet: no echo, no banner
    bool quit_requested = false;  // `quit`
    bool return_requested = false;// `return`: leave the current file
    std::atomic<bool> interrupt{false}; // raised by Ctrl-C; cycling stops between steps
    // `step` or `solve` is cycling the model (> 0): commands that FISH runs then (whilestepping
    // functions, FISH histories) may not replace the model or cycle it again (their
    // declarations say which: CommandSpec::not_while_cycling).
    int cycling = 0;
    // A FISH function is running: `new` then keeps FISH's functions and variables.
    bool fish_running() const;
    bool new_in_fish_noted = false; // the note on `new` inside FISH is given once a session
    bool at_prompt = false;       // commands typed at the prompt are not echoed
    PlotSettings plot;            // kept between plots
    // How the last `solve` ended: its criteria and verdict (null before any; `new` and `restore`
    // clear it). `print info` and FISH's solve_verdict read it.
    std::shared_ptr<const SolveVerdict> last_solve;
    // What the last `solve fos` found (null before any; `new` and `restore` clear it). FISH's
    // fos_f reads it.
    std::shared_ptr<const FosResult> last_fos;
    NamedRanges named_ranges;     // `range name X ...`, for `nrange X`

    // Bounds for a session that runs input nobody wrote by hand (the fuzzing targets of
    // tests/fuzz/); the program sets none of them. A command that would go past one fails
    // with an error and leaves the model as it was.
    struct Limits {
        // Files only by a relative name without '..': whatever `save`, `export`, `plot`,
        // `hist write`, `set logfile`, `call`, `restore` and `table read` name stays inside
        // the working directory.
        bool confine_files = false;
        // Block-steps (blocks and zones times steps) that `step` and `solve` may still take in all;
        // < 0: no limit.
        long long block_steps = -1;
        // Blocks a `jset` may leave at most, counting every plane that crosses a block as a cut,
        // and that `poly` may add to; 0: no limit.
        long max_blocks = 0;
        // Zones a `generate` may make at most; 0: the built-in limit.
        long max_zones = 0;
        // Zones all `generate` commands together may still make; < 0: no limit (each `gen`
        // forks the mesher: a FISH loop of them must end, so each costs at least 250, zoned or
        // not).
        long long zone_budget = -1;
        // FISH loop iterations that may still run in all; < 0: no limit. A command that FISH
        // runs (a line of a `command` block) costs kCommandFishSteps of them, and
        // kCommandFishStepsPerBlock more for each block of the model.
        long long fish_steps = -1;
    } limits;

    // What a command run from FISH costs of Limits::fish_steps: a command does far more than a
    // loop iteration, and more the more blocks there are ('jset' cuts each of them), and a FISH
    // loop of commands must end within a fuzzing session's time.
    static constexpr long long kCommandFishSteps = 50;
    static constexpr long long kCommandFishStepsPerBlock = 100;

    // How many files may run at once through `call` (each level takes C++ stack).
    static constexpr int kMaxCallDepth = 64;

private:
    void out_of_memory(const LexedCommand& cmd);
    // Run every command the lexer gives; false at the first error.
    bool run_lexer(Lexer& lex, bool echo_commands);
    // `def name ... end`: compile it; false when it failed (reported).
    bool define_fish(const LexedCommand& header, Lexer& lex, bool echo_command);
    // `@f(...)`, `@x = 1`, or a FISH function named alone (UDEC): run it as FISH.
    bool is_fish_statement(const LexedCommand& cmd) const;
    void run_fish_statement(const LexedCommand& cmd);
    // `set name = value ...` where name is no setting: FISH variables set from a command.
    bool is_fish_set(const LexedCommand& cmd) const;
    void run_fish_set(const LexedCommand& cmd);
    // The command's tokens with `@name` replaced by the values FISH has now.
    std::vector<Token> substitute(const std::vector<Token>& tokens);

    std::unique_ptr<fish::Host> fish_host_;
    std::unique_ptr<fish::Runtime> fish_;

    std::vector<std::string> call_stack_; // canonical paths of the files being run
    std::vector<std::string> display_stack_;
};

} // namespace odec
