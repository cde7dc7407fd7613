// Small helpers shared by command handlers.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "engine/model.h"
#include "engine/range.h"
#include "lang/interpreter.h"

namespace odec {

// Blocks selected by the command's range phrase (all blocks when none was given).
inline std::vector<int> blocks_in_range(const CommandContext& ctx, const Args& args) {
    return select_blocks(ctx.model, args.range);
}

// A relative path given in a script is taken from that script's directory (at the prompt and
// on the command line, from the working directory).
inline std::string relative_to_script(const SourceLoc& loc, const std::string& path) {
    if (!path.empty() && path[0] != '/' && loc.file && !loc.file->directory.empty()) return loc.file->directory + path;
    return path;
}

// The history number a value gives, checked to exist (histories are numbered from 1 as made).
inline int history_number(const Model& m, const Value& v, const std::string& help_topic) {
    const int n = static_cast<int>(v.number);
    const int count = static_cast<int>(m.histories.items.size());
    if (n < 1 || n > count) {
        fail(v.loc, "there is no history " + std::to_string(n) + " (there " +
                        (count == 1 ? std::string("is 1") : "are " + std::to_string(count)) + ")",
             {"make histories with 'hist', e.g. 'hist zdis 0,0,1'"}, help_topic);
    }
    return n;
}

// Grow a property table so that index n exists.
template <class T>
void ensure_index(std::vector<T>& v, int n) {
    if (static_cast<int>(v.size()) <= n) v.resize(n + 1);
}

// "%.6g" of a number.
inline std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
}

inline std::string vec_text(const Vec3& v) { return "(" + num(v.x()) + "," + num(v.y()) + "," + num(v.z()) + ")"; }

} // namespace odec
