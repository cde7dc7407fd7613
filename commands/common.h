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

// A warning in the form of an error (file:line:col: warning: ...), on the error stream, in
// scripts and at the prompt alike; the command goes on.
inline void warn(CommandContext& ctx, const SourceLoc& l, const std::string& what) {
    ctx.interp.err << (l.file ? l.file->name : std::string("<input>")) << ":" << l.line << ":" << l.col
                   << ": warning: " << what << "\n";
}

// The blocks a command changes. A range that selects none is said in one line, as a
// warning (a mistyped range would otherwise pass unnoticed); the command goes on, doing nothing.
inline std::vector<int> blocks_to_change(CommandContext& ctx, const Args& args, bool include_hidden = false) {
    std::vector<int> blocks = select_blocks(ctx.model, args.range, include_hidden);
    if (blocks.empty()) {
        warn(ctx, args.loc,
             std::string(ctx.model.blocks.size() == 0 ? "there are no blocks" : "the range selects no blocks") +
                 ", nothing changed");
    }
    return blocks;
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

// A joint material number given with `change jmat` or `set jmat`, checked to have properties:
// contacts of a material never given would have no stiffness and let blocks sink through.
inline int defined_joint_material(const Model& m, const Args& args, const std::string& help_topic) {
    const KeywordUse* u = args.find("jmat");
    const int n = args.integer("jmat");
    const bool defined = n > 0 && n < static_cast<int>(m.joint_materials.size()) && m.joint_materials[n].defined;
    if (!defined) {
        fail(u->loc, "joint material " + std::to_string(n) + " has no properties",
             {"give them first, e.g. 'prop jmat=" + std::to_string(n) + " jkn=1e9 jks=1e9 jfric=30'"}, help_topic);
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
