// The words for how a `solve` ended (engine/verdict.h gives the numbers): the line `solve`
// ends with, and what `print info` says of the last solve.
#pragma once

#include <string>

#include "engine/verdict.h"

namespace odec {

// The verdict, e.g. "equilibrium, ratio 9.8e-06 < 1e-05 after 1234 steps" or
// "mechanism at the step limit (3000 steps): 1 block (id 2) still moving at up to 0.71 m/s, ...".
// A run stopped by its time limit keeps its plain line ("reached the time limit, ...");
// its mechanism, when one is found, is mechanism_text().
std::string verdict_text(const SolveVerdict& v);
// "1 block (id 2) still moving at up to 0.71 m/s, speeding up over the last 600 steps (moved up
// to 0.05 m in them)"; "" when no block moves as a mechanism.
std::string mechanism_text(const SolveVerdict& v);
// The criteria of the run: "ratio limit 1e-05, step limit 200000, no time limit".
std::string criteria_text(const SolveVerdict& v);
// Block ids as a compact list: "12-15, 17" (at most `most` runs, then "...").
std::string id_list(std::vector<int> ids, int most = 8);

} // namespace odec
