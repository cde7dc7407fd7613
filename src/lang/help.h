// Help text and manual pages, both made from the command declarations.
#pragma once

#include <string>

#include "lang/parser.h"

namespace odec {

// `help`: every command with its one line.
std::string help_overview(const CommandTable& table);
// `help <command>`: synopsis, description, keywords, examples.
std::string help_command(const CommandSpec& c);
// `help <command> <keyword>`.
std::string help_keyword(const CommandSpec& c, const KeywordSpec& k);
// `help range`: the range phrase.
std::string help_range();

// The reference page of one command, in Markdown.
std::string manual_page(const CommandSpec& c);
// The index page listing every command.
std::string manual_index(const CommandTable& table);
// Write every page into dir (created when missing). Returns false with `error` on failure.
bool write_manual(const CommandTable& table, const std::string& dir, std::string& error);

} // namespace odec
