// Words of the classic 3DEC/UDEC language that odec does not have yet. A script that uses
// one stops with a plain statement of what is missing, rather than "unknown command".
#pragma once

#include <string>

namespace odec {

// What a command word that odec does not have means and where things stand, or "" when the
// word is not such a command (typed in full or shortened to at least its first 3 letters).
std::string not_yet_available(const std::string& lower_word);

} // namespace odec
