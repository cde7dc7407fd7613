// Runs commands through the real interpreter and command table, capturing what it prints.
#pragma once

#include <sstream>
#include <string>

#include "commands.h"
#include "lang/interpreter.h"

namespace odec::test {

struct Session {
    Model model;
    std::ostringstream out, err;
    Interpreter interp{model, command_table(), out, err};
    Session() { interp.quiet = true; }
    // Runs text as a script called "t.dat" (no echo); returns whether it all succeeded.
    bool run(const std::string& text) { return interp.run_text("t.dat", text, false); }
    std::string error() const { return err.str(); }
};

} // namespace odec::test
