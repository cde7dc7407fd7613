// odec: the command-line program. Runs scripts and command-line commands, or opens the prompt.
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <unistd.h>
#include <vector>

#include "commands.h"
#include "engine/memory.h"
#include "io/save.h"
#include "lang/help.h"
#include "lang/interpreter.h"
#include "lang/prompt.h"
#include "render/vtk_backend.h"

namespace {

const char* kUsage =
    "usage: odec [options] [file.dat ...]\n"
    "  With no file, opens the interactive prompt. Files are run in order; the first error stops\n"
    "  odec with exit status 1.\n"
    "options:\n"
    "  -c, --command TEXT  run the commands in TEXT (lines separated by newlines); may be repeated\n"
    "  -q, --quiet         do not echo script commands or print progress\n"
    "      --manual DIR    write the command reference pages into DIR and exit\n"
    "  -h, --help          show this help and exit\n"
    "  -V, --version       show the version and exit\n";

} // namespace

// Releases the off-screen GL context (if a picture made one) before the program ends.
struct RendererGuard {
    ~RendererGuard() { odec::render::shutdown_renderer(); }
};

namespace {
odec::Interpreter* g_script_interp = nullptr;
extern "C" void on_script_sigint(int) {
    if (g_script_interp) g_script_interp->interrupt.store(true);
}
} // namespace

int main(int argc, char** argv) {
    using namespace odec;
    tune_allocator();
    struct Item {
        bool is_command;
        std::string text;
    };
    std::vector<Item> items;
    bool quiet = false;
    // --check-save (for the tests of the examples; not in the usage): after the scripts ran,
    // the model must save, restore into a fresh model and save again to the same bytes.
    bool check_save = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            std::cout << kUsage;
            return 0;
        } else if (a == "-V" || a == "--version") {
            std::cout << "odec " << ODEC_VERSION << "\n";
            return 0;
        } else if (a == "-q" || a == "--quiet") {
            quiet = true;
        } else if (a == "--check-save") {
            check_save = true;
        } else if (a == "-c" || a == "--command") {
            if (i + 1 >= argc) {
                std::cerr << "odec: " << a << " needs the commands to run\n" << kUsage;
                return 2;
            }
            items.push_back({true, argv[++i]});
        } else if (a == "--manual") {
            if (i + 1 >= argc) {
                std::cerr << "odec: --manual needs a directory\n";
                return 2;
            }
            std::string error;
            if (!write_manual(command_table(), argv[i + 1], error)) {
                std::cerr << "odec: " << error << "\n";
                return 1;
            }
            return 0;
        } else if (a.size() > 1 && a[0] == '-') {
            std::cerr << "odec: unknown option '" << a << "'\n" << kUsage;
            return 2;
        } else {
            items.push_back({false, a});
        }
    }
    // Temporary files of saves killed part way in an earlier run, here in the working directory.
    const std::string note = stale_temporaries_note(remove_stale_save_temporaries("."));
    if (!note.empty()) std::cerr << "odec: note: " << note << "\n";
    RendererGuard renderer_guard;
    Model model;
    Interpreter interp(model, command_table(), std::cout, std::cerr);
    interp.quiet = quiet;
    if (items.empty()) {
        if (isatty(STDIN_FILENO)) {
            if (!quiet) std::cout << "odec " << ODEC_VERSION << ": type 'help' for the commands, Ctrl-D to leave\n";
            return run_prompt(interp, default_history_file());
        }
        // Commands piped in: run them as a script.
        std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
        return interp.run_text("<stdin>", text, true) ? 0 : 1;
    }
    // Ctrl-C while scripts run stops the step or solve under way between two steps, then
    // the scripts (exit status 130); a second Ctrl-C ends odec at once.
    g_script_interp = &interp;
    struct sigaction sa {};
    sa.sa_handler = on_script_sigint;
    sa.sa_flags = SA_RESETHAND;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    for (const Item& it : items) {
        const bool ok = it.is_command ? interp.run_text("<command-line>", it.text, false) : interp.run_file(it.text);
        if (interp.interrupt.load()) return 130;
        if (!ok) return 1;
        if (interp.quit_requested) break;
    }
    if (check_save) {
        const char* tmp = std::getenv("TMPDIR");
        std::string dir = std::string(tmp && *tmp ? tmp : "/tmp") + "/odec-check-save-XXXXXX";
        if (!mkdtemp(&dir[0])) {
            std::cerr << "odec: --check-save: cannot make a directory '" << dir << "': " << std::strerror(errno) << "\n";
            return 1;
        }
        std::string error;
        const bool same = check_save_round_trip(model, dir, error);
        rmdir(dir.c_str());
        if (!same) {
            std::cerr << "odec: --check-save: the model at step " << model.step << " does not round-trip: " << error
                      << "\n";
            return 1;
        }
    }
    return 0;
}
