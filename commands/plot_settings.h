// Plot options kept between pictures: `plot set size ... view ... background ... map ...`.
// They belong to a session, not to the model (`new` keeps them, like `set echo`), so the
// Interpreter holds them (Interpreter::plot).
#pragma once

#include "lang/interpreter.h"

namespace odec {

// The settings of this session.
PlotSettings& plot_settings(const Interpreter& interp);

} // namespace odec
