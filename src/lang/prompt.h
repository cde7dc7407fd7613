// The interactive prompt: GNU readline with line editing, history kept across sessions,
// tab completion from the command declarations, a continuation prompt after `&`, Ctrl-C
// that stops a long `step` (or clears the line) without leaving, and Ctrl-D to leave.
#pragma once

#include <string>

#include "lang/interpreter.h"

namespace odec {

// Runs until `quit` or Ctrl-D. Returns the process exit status.
int run_prompt(Interpreter& interp, const std::string& history_file);

// ~/.odec_history, or $ODEC_HISTORY when set.
std::string default_history_file();

} // namespace odec
