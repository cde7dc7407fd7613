// What tab completion offers at the cursor: command names at the start of a line, then the
// keywords of that command, the range filters after `range`, and the words of a choice.
#pragma once

#include <string>
#include <vector>

#include "lang/parser.h"

namespace odec {

// Words that complete `word`, given the text of the line before it.
std::vector<std::string> complete_words(const CommandTable& table, const std::string& before, const std::string& word);

} // namespace odec
