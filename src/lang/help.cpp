#include "lang/help.h"

#include "fish/help.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

namespace odec {

namespace {

std::string value_line(const ValueSpec& v) {
    std::string s = v.name + ": " + type_name(v.type);
    if (v.type == ValueType::Choice) {
        s += " (";
        for (size_t k = 0; k < v.choices.size(); ++k) s += (k ? ", " : "") + v.choices[k];
        s += ")";
    }
    if (v.type == ValueType::Real && !v.choices.empty()) {
        for (const auto& w : v.choices) s += ", or '" + w + "'";
    }
    const std::string lim = describe_limits(v);
    if (!lim.empty()) s += ", " + lim;
    if (v.optional) s += v.default_text.empty() ? ", optional" : ", default " + v.default_text;
    return s;
}

std::string abbreviation(const std::string& name, int min) {
    if (min >= static_cast<int>(name.size())) return name;
    return name.substr(0, min) + "[" + name.substr(min) + "]";
}

std::string pad(const std::string& s, size_t w) { return s.size() >= w ? s + " " : s + std::string(w - s.size(), ' '); }

} // namespace

std::string help_overview(const CommandTable& table) {
    std::string s = "Commands (type 'help <command>' for one of them, 'help range' for the range phrase):\n";
    for (const CommandSpec* c : table.commands) {
        std::string name = c->name;
        for (const auto& a : c->aliases) name += ", " + a;
        s += "  " + pad(name, 18) + c->summary + "\n";
    }
    s += "Words may be shortened to any unique prefix at least as long as shown in 'help <command>'.\n";
    return s;
}

std::string help_command(const CommandSpec& c) {
    std::string s = c.synopsis() + "\n  " + c.summary + "\n";
    if (!c.aliases.empty()) {
        s += "  also written:";
        for (const auto& a : c.aliases) s += " " + a;
        s += "\n";
    }
    s += "  shortest form: " + abbreviation(c.name, c.min) + "\n";
    if (!c.description.empty()) s += "\n" + c.description + "\n";
    if (!c.not_while_cycling.empty()) s += "\nNot while the model cycles: " + c.not_while_cycling + "\n";
    if (!c.positional.values.empty()) {
        s += "\nValues:\n";
        for (const ValueSpec& v : c.positional.values) s += "  " + value_line(v) + "\n";
    }
    if (!c.keywords.empty()) {
        s += "\nKeywords:\n";
        for (const KeywordSpec& k : c.keywords) {
            s += "  " + pad(k.synopsis(), 30) + k.help;
            if (!k.default_text.empty()) s += " (default " + k.default_text + ")";
            s += "\n";
        }
    }
    if (!c.examples.empty()) {
        s += "\nExample:\n";
        for (const auto& e : c.examples) s += "  " + e + "\n";
    }
    return s;
}

std::string help_keyword(const CommandSpec& c, const KeywordSpec& k) {
    std::string s = c.name + " " + k.synopsis() + "\n  " + k.help + "\n";
    s += "  shortest form: " + abbreviation(k.name, k.min) + "\n";
    if (!k.default_text.empty()) s += "  default: " + k.default_text + "\n";
    for (const ValueSpec& v : k.values) s += "  " + value_line(v) + "\n";
    if (k.repeat_last && !k.values.empty()) s += "  (" + k.values.back().name + " may be repeated)\n";
    if (k.is_range) s += help_range();
    return s;
}

std::string help_range() {
    std::string s = "range <filter> [<filter> ...]: the blocks that pass every filter\n";
    for (const KeywordSpec& f : range_filters()) {
        s += "  " + pad(f.synopsis(), 42) + f.help + "\n";
    }
    return s;
}

std::string manual_page(const CommandSpec& c) {
    std::string s = "# " + c.name + "\n\n";
    s += c.summary + "\n\n";
    s += "```\n" + c.synopsis() + "\n```\n\n";
    s += "Shortest form: `" + abbreviation(c.name, c.min) + "`";
    if (!c.aliases.empty()) {
        s += "; also written";
        for (size_t k = 0; k < c.aliases.size(); ++k) s += (k ? ", `" : " `") + c.aliases[k] + "`";
    }
    s += ".\n\n";
    if (!c.description.empty()) s += c.description + "\n\n";
    if (!c.not_while_cycling.empty()) s += "Not while the model cycles: " + c.not_while_cycling + "\n\n";
    if (!c.positional.values.empty()) {
        s += "## Values\n\n";
        for (const ValueSpec& v : c.positional.values) s += "- " + value_line(v) + "\n";
        s += "\n";
    }
    if (!c.keywords.empty()) {
        s += "## Keywords\n\n| keyword | shortest | values | meaning |\n|---|---|---|---|\n";
        for (const KeywordSpec& k : c.keywords) {
            std::string vals;
            if (k.is_range) vals = "the range phrase (see [the range phrase](range-phrase.md))";
            if (k.rest_of == "*") vals = "the rest of the line, as words";
            else if (!k.rest_of.empty()) vals = "the options of `" + k.rest_of + " set` (see [" + k.rest_of + "](" + k.rest_of + ".md))";
            for (const ValueSpec& v : k.values) vals += (vals.empty() ? "" : "; ") + value_line(v);
            if (k.repeat_last && !k.values.empty()) vals += " (repeatable)";
            std::string meaning = k.help;
            if (!k.default_text.empty()) meaning += " (default " + k.default_text + ")";
            if (k.choice) meaning += " [one of a choice]";
            s += "| `" + k.name + "` | `" + abbreviation(k.name, k.min) + "` | " + vals + " | " + meaning + " |\n";
        }
        s += "\n";
    }
    if (!c.examples.empty()) {
        s += "## Example\n\n```\n";
        for (const auto& e : c.examples) s += e + "\n";
        s += "```\n";
    }
    return s;
}

std::string manual_index(const CommandTable& table) {
    std::string s = "# Command reference\n\n";
    s += "Generated from the command declarations (`odec --manual manual/commands`); do not edit by hand.\n\n";
    s += "| command | meaning |\n|---|---|\n";
    for (const CommandSpec* c : table.commands) {
        s += "| [`" + c->name + "`](" + c->name + ".md) | " + c->summary + " |\n";
    }
    s += "\nThe range phrase that selects blocks: [range-phrase](range-phrase.md).\n";
    s += "\nThe FISH language and its intrinsics: [fish](fish.md).\n";
    return s;
}

static std::string range_page() {
    std::string s = "# The range phrase\n\nThe range phrase selects blocks by their centroid, region, group or id. "
                    "It follows the keyword `range` in the commands that take one; every filter must hold, "
                    "and `not` inverts the filter after it.\n\n| filter | values | meaning |\n|---|---|---|\n";
    for (const KeywordSpec& f : range_filters()) {
        std::string vals;
        for (const ValueSpec& v : f.values) vals += (vals.empty() ? "" : "; ") + value_line(v);
        s += "| `" + f.name + "` | " + vals + " | " + f.help + " |\n";
    }
    s += "\n## Example\n\n```\nfix range z -1 0\nchange mat=2 range region 3 not group 'lining'\n```\n";
    return s;
}

bool write_manual(const CommandTable& table, const std::string& dir, std::string& error) {
    ::mkdir(dir.c_str(), 0755);
    auto write = [&](const std::string& name, const std::string& text) {
        const std::string path = dir + "/" + name;
        FILE* f = std::fopen(path.c_str(), "w");
        if (!f) {
            error = "cannot write '" + path + "': " + std::strerror(errno);
            return false;
        }
        std::fwrite(text.data(), 1, text.size(), f);
        return std::fclose(f) == 0;
    };
    if (!write("index.md", manual_index(table))) return false;
    if (!write("range-phrase.md", range_page())) return false;
    if (!write("fish.md", fish::manual_page())) return false;
    for (const CommandSpec* c : table.commands) {
        if (!write(c->name + ".md", manual_page(*c))) return false;
    }
    return true;
}

} // namespace odec
