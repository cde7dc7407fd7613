// 'solve fos': the factor of safety by strength reduction (engine/fos.h), for the `solve`
// command's handler.
#pragma once

#include "lang/interpreter.h"

namespace odec {

void solve_fos(CommandContext& ctx, const Args& a);

} // namespace odec
