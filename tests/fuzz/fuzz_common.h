// What the fuzzing targets share: a scratch working directory, emptied before every input,
// so that whatever an input saves, exports or plots lands there and nowhere else (the session
// confines file names to it, see Interpreter::Limits); an output stream that drops
// everything; and the bounds of a session on unchecked input.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <streambuf>
#include <string>
#include <system_error>

#include "fish/runtime.h"
#include "lang/interpreter.h"

namespace odec::fuzz {

// Made once per process under $TMPDIR (or /tmp), entered, and removed at exit. The process
// works there from its first input on: give libFuzzer absolute paths (corpora, artifacts).
inline const std::string& scratch_dir() {
    static const std::string dir = [] {
        const char* base = std::getenv("TMPDIR");
        std::string tmpl = std::string(base && *base ? base : "/tmp") + "/odec-fuzz-XXXXXX";
        if (!mkdtemp(tmpl.data()) || chdir(tmpl.c_str()) != 0) {
            std::perror("odec fuzz: cannot make a scratch directory");
            std::abort();
        }
        static std::string removed_at_exit;
        removed_at_exit = tmpl;
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(removed_at_exit, ec);
        });
        return tmpl;
    }();
    return dir;
}

// Into the scratch directory, emptied: each input starts from the same files (none).
inline void fresh_scratch_dir() {
    const std::string& dir = scratch_dir();
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        std::error_code ec2;
        std::filesystem::remove_all(entry.path(), ec2);
    }
    if (chdir(dir.c_str()) != 0) std::abort();
}

class NullBuffer : public std::streambuf {
protected:
    int overflow(int c) override { return traits_type::not_eof(c); }
    std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

// The bounds of every fuzzing session: files in the scratch directory only, at most 150
// blocks (from a joint set, a tunnel or 'poly'), 500 zones from one 'gen' and 5,000 from all,
// 400 block-steps of cycling and 200,000 FISH loop iterations in all (a command FISH runs
// costs 50, and 100 more for each block; a FISH open 50, a read, write or close 10).
inline void bound_session(Interpreter& interp) {
    interp.limits.confine_files = true;
    interp.limits.max_blocks = 150;
    interp.limits.max_zones = 500;
    interp.limits.zone_budget = 5000; // each 'gen' forks the mesher: ten of the largest in all
    interp.limits.block_steps = 400;
    interp.limits.fish_steps = 200000;
    interp.fish().max_string = 4096; // arrays of such strings stay below ~0.5 GB
    interp.fish().max_array_items = 100000;
    interp.progress_seconds = 1e30; // progress lines depend on the clock: none
}

} // namespace odec::fuzz
