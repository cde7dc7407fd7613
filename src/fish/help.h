// Help and the manual's FISH chapter, made from the intrinsic declarations.
#pragma once

#include <string>

namespace odec::fish {

// `help fish`: the statements, then the intrinsics by group, one line each.
std::string help_overview();
// `help fish name`: one intrinsic; "" when there is none of that name.
std::string help_intrinsic(const std::string& lower_name);
// The manual page (markdown).
std::string manual_page();

} // namespace odec::fish
