// Runs commands through the real interpreter and command table, capturing what it prints.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "commands.h"
#include "io/save.h"
#include "lang/interpreter.h"

namespace odec::test {

// The whole of a file, as bytes ("" when it cannot be read).
inline std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

struct Session {
    Model model;
    std::ostringstream out, err;
    Interpreter interp{model, command_table(), out, err};
    // Every command run so far succeeded.
    bool all_succeeded = true;
    // At its end, the model a session built must save, restore into a fresh model and save
    // again to the same bytes (every model the suite builds round-trips); a model that save
    // refuses must come from a command that failed (a run-away stops its `step` with an
    // error). Off for a session whose test makes its model unsaveable on purpose.
    bool check_save_at_end = true;

    Session() { interp.quiet = true; }
    ~Session() {
        if (check_save_at_end && !::testing::Test::HasFatalFailure()) check_round_trip();
    }
    // Runs text as a script called "t.dat" (no echo); returns whether it all succeeded.
    bool run(const std::string& text) {
        const bool ok = interp.run_text("t.dat", text, false);
        all_succeeded = all_succeeded && ok;
        return ok;
    }
    std::string error() const { return err.str(); }

    void check_round_trip() const {
        const std::string problem = save_problem(model);
        if (!problem.empty()) {
            EXPECT_FALSE(all_succeeded) << "every command succeeded, but the model cannot be saved: " << problem;
            return;
        }
        const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        std::string error;
        EXPECT_TRUE(check_save_round_trip(model, dir, error)) << "the session's model does not round-trip: " << error;
    }
};

} // namespace odec::test
