#include "lang/prompt.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sys/select.h>
#include <unistd.h>

#include "fish/runtime.h"

#include <readline/history.h>
#include <readline/readline.h>

#include "lang/completion.h"

namespace odec {

namespace {

// Readline's callbacks are plain functions: they reach the session through these.
Interpreter* g_interp = nullptr;
std::string g_history_file;
std::string g_pending;            // lines joined by continuation so far
bool g_done = false;
volatile std::sig_atomic_t g_sigint = 0;

const char* kPrompt = "odec> ";
const char* kContinuation = "...> ";

void on_sigint(int) {
    g_sigint = 1;
    if (g_interp) g_interp->interrupt.store(true);
}

char* completion_generator(const char* text, int state) {
    static std::vector<std::string> words;
    static size_t next = 0;
    if (state == 0) {
        const std::string before = g_pending + std::string(rl_line_buffer, rl_point - std::strlen(text));
        words = complete_words(g_interp->table, before, text);
        // FISH functions and variables, as @name (and by name where a command word is expected).
        const std::string typed(text);
        const bool typed_at = !typed.empty() && typed[0] == '@';
        // Readline breaks words at '@' by default: the '@' is then just before the word.
        const bool at = typed_at || (!before.empty() && before.back() == '@');
        const std::string stem = typed_at ? typed.substr(1) : typed;
        for (const std::string& n : g_interp->fish().names()) {
            std::string lower = n, want = stem;
            for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            for (char& c : want) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            if (lower.compare(0, want.size(), want) != 0) continue;
            if (at) words.push_back(typed_at ? "@" + n : n);
            else if (before.find_first_not_of(" \t") == std::string::npos && g_interp->fish().is_function(lower)) words.push_back(n);
        }
        next = 0;
    }
    if (next < words.size()) return strdup(words[next++].c_str());
    return nullptr;
}

char** attempt_completion(const char* text, int start, int) {
    const std::string before = std::string(rl_line_buffer, start);
    const std::vector<Token> toks = lex_line_lenient(g_pending + before);
    // File names after `call`.
    if (toks.size() == 1 && g_interp->table.match(toks[0].lower, nullptr) == g_interp->table.find("call")) {
        rl_attempted_completion_over = 0;
        return nullptr;
    }
    rl_attempted_completion_over = 1;
    return rl_completion_matches(text, completion_generator);
}

void on_line(char* line) {
    if (!line) { // Ctrl-D
        std::printf("\n");
        g_done = true;
        return;
    }
    std::string text(line);
    std::free(line);
    if (Lexer::ends_with_continuation(text) || definition_open(g_pending + text)) {
        g_pending += text + "\n";
        rl_set_prompt(kContinuation);
        return;
    }
    const std::string full = g_pending + text;
    g_pending.clear();
    rl_set_prompt(kPrompt);
    if (full.find_first_not_of(" \t\n") == std::string::npos) return;
    add_history(full.c_str());
    if (!g_history_file.empty()) append_history(1, g_history_file.c_str());
    g_interp->interrupt = false;
    g_sigint = 0;
    // Ctrl-C must reach a running command (a long `step`) at any moment.
    sigset_t sigint;
    sigemptyset(&sigint);
    sigaddset(&sigint, SIGINT);
    sigprocmask(SIG_UNBLOCK, &sigint, nullptr);
    g_interp->run_text("<prompt>", full, false);
    sigprocmask(SIG_BLOCK, &sigint, nullptr);
    g_sigint = 0;
    g_interp->interrupt = false;
    if (g_interp->quit_requested) g_done = true;
}

} // namespace

std::string default_history_file() {
    if (const char* h = std::getenv("ODEC_HISTORY")) return h;
    if (const char* home = std::getenv("HOME")) return std::string(home) + "/.odec_history";
    return "";
}

int run_prompt(Interpreter& interp, const std::string& history_file) {
    g_interp = &interp;
    g_history_file = history_file;
    g_done = false;
    interp.at_prompt = true;
    rl_readline_name = "odec";
    rl_catch_signals = 0;
    rl_attempted_completion_function = attempt_completion;
    rl_basic_word_break_characters = const_cast<char*>(" \t\n,=()");
    using_history();
    if (!history_file.empty()) {
        FILE* f = std::fopen(history_file.c_str(), "a"); // make sure it exists for append_history
        if (f) std::fclose(f);
        read_history(history_file.c_str());
    }
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0; // no SA_RESTART: select() must wake up on Ctrl-C
    sigaction(SIGINT, &sa, nullptr);

    // SIGINT stays blocked except inside pselect (and while a command runs), so a Ctrl-C is
    // never lost between checking the flag and waiting for input.
    sigset_t sigint, wait_mask;
    sigemptyset(&sigint);
    sigaddset(&sigint, SIGINT);
    sigprocmask(SIG_BLOCK, &sigint, &wait_mask);
    sigdelset(&wait_mask, SIGINT);

    rl_callback_handler_install(kPrompt, on_line);
    while (!g_done) {
        fd_set fds;
        FD_ZERO(&fds);
        FD_SET(STDIN_FILENO, &fds);
        const int r = g_sigint ? -1 : pselect(STDIN_FILENO + 1, &fds, nullptr, nullptr, nullptr, &wait_mask);
        if (r < 0) {
            if (g_sigint) {
                // Ctrl-C at the prompt: drop the line being typed, and any continuation.
                g_sigint = 0;
                interp.interrupt = false;
                g_pending.clear();
                rl_set_prompt(kPrompt);
                rl_replace_line("", 0);
                std::printf("^C\n");
                rl_on_new_line();
                rl_redisplay();
                continue;
            }
            if (errno == EINTR) continue;
            break;
        }
        rl_callback_read_char();
    }
    rl_callback_handler_remove();
    sigprocmask(SIG_UNBLOCK, &sigint, nullptr);
    if (!history_file.empty()) history_truncate_file(history_file.c_str(), 2000);
    return 0;
}

} // namespace odec
