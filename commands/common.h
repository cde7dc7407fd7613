// Small helpers shared by command handlers.
#pragma once

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/clump.h"
#include "engine/flow.h"
#include "engine/model.h"
#include "engine/range.h"
#include "lang/interpreter.h"

namespace odec {

// The pore pressures 'pp p [pgrad g]' or 'wtable z' ask for ('bound', 'insitu'). A water table
// becomes the model's too: flow nodes made later start at its hydrostatic pressure.
inline PressureSpec pressure_spec(Model& m, const Args& a) {
    PressureSpec spec;
    if (a.has("wtable")) {
        m.flow.has_wtable = true;
        m.flow.wtable = a.real("wtable");
        spec.wtable = true;
    } else {
        spec.p = a.real("pp");
        if (a.has("pgrad")) spec.grad = a.vec("pgrad");
    }
    return spec;
}

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

// The pieces of a clump move as one rigid body (clump.h): a command that holds, frees, moves or
// removes blocks takes the whole clump of every piece its range selects, and says so in a line.
inline void take_whole_clumps(CommandContext& ctx, std::vector<int>& blocks, const char* verb) {
    int clumps = 0;
    const int added = complete_clumps(ctx.model.blocks, blocks, &clumps);
    if (added > 0 && !ctx.interp.quiet) {
        ctx.out << "the range takes part of " << clumps << " clump" << (clumps == 1 ? "" : "s")
                << " (a solid that is not convex, one rigid body): " << verb << " the other " << added << " block"
                << (added == 1 ? "" : "s") << " of " << (clumps == 1 ? "it" : "them") << " too\n";
    }
}

// What 'insitu' (or 'gen', applying the in-situ stress given before) set, said in a line, and
// what the joints could not carry, as warnings.
inline void report_insitu(CommandContext& ctx, const SourceLoc& loc, const InsituCount& c, const std::string& prefix) {
    if (!ctx.interp.quiet) {
        ctx.out << prefix << c.zones << " zone" << (c.zones == 1 ? "" : "s") << " and " << c.contacts << " contact"
                << (c.contacts == 1 ? "" : "s") << " (" << c.subs << " sub-contact" << (c.subs == 1 ? "" : "s")
                << ") set";
        if (c.edge_subs > 0) {
            ctx.out << "; " << c.edge_subs << " sub-contact" << (c.edge_subs == 1 ? "" : "s")
                    << " where blocks meet only along an edge or at a corner left unloaded";
        }
        ctx.out << "\n";
    }
    if (c.slipping > 0) {
        warn(ctx, loc, std::to_string(c.slipping) + " of " + std::to_string(c.subs) +
                           " sub-contacts cannot carry the in-situ shear stress (beyond their joint's Coulomb strength): "
                           "they start at that strength, slipping");
    }
    if (c.opened > 0) {
        warn(ctx, loc, std::to_string(c.opened) + " of " + std::to_string(c.subs) +
                           " sub-contacts are pulled apart by the in-situ stress (beyond their joint's tensile strength): "
                           "they start open, unloaded");
    }
    if (c.no_stiffness > 0) {
        warn(ctx, loc, std::to_string(c.no_stiffness) + " contact" + (c.no_stiffness == 1 ? " has" : "s have") +
                           " no joint material with a normal stiffness and start" + (c.no_stiffness == 1 ? "s" : "") +
                           " unloaded ('prop jmat=n jkn=... jks=...', 'change jmat=n')");
    }
}

// A relative path given in a script is taken from that script's directory (at the prompt and
// on the command line, from the working directory).
inline std::string relative_to_script(const SourceLoc& loc, const std::string& path) {
    if (!path.empty() && path[0] != '/' && loc.file && !loc.file->directory.empty()) return loc.file->directory + path;
    return path;
}

// In a session whose files are confined (Interpreter::Limits), refuse a path that could leave
// the working directory: an absolute one, or one with a '..' component.
inline void check_file_allowed(const CommandContext& ctx, const SourceLoc& loc, const std::string& path,
                               const std::string& help_topic) {
    if (!ctx.interp.limits.confine_files) return;
    bool ok = !path.empty() && path[0] != '/';
    for (size_t start = 0; ok && start <= path.size();) {
        const size_t slash = std::min(path.find('/', start), path.size());
        if (path.compare(start, slash - start, "..") == 0 && slash - start == 2) ok = false;
        start = slash + 1;
    }
    if (!ok) {
        fail(loc, "'" + path + "': this session reads and writes files only inside its working directory",
             {"give a relative name without '..'"}, help_topic);
    }
}

// `step` and `solve` in a session with a budget of block-steps (Interpreter::Limits): at most
// as many steps as the budget leaves for the blocks there are. Returns the blocks counted.
// While alive, the model is cycling: commands FISH runs then are checked against their
// declarations (CommandSpec::not_while_cycling).
struct CyclingGuard {
    Interpreter& interp;
    explicit CyclingGuard(Interpreter& in) : interp(in) { ++interp.cycling; }
    ~CyclingGuard() { --interp.cycling; }
    CyclingGuard(const CyclingGuard&) = delete;
    CyclingGuard& operator=(const CyclingGuard&) = delete;
};

// Why `step`, `solve` and their kind may not run from FISH during cycling.
constexpr const char* kNoNestedCycling =
    "a function called while the model cycles cannot cycle it again (it would run steps inside a step)";

inline long long limit_steps_to_budget(CommandContext& ctx, const SourceLoc& loc, long& max_steps,
                                       const std::string& help_topic) {
    const long long budget = ctx.interp.limits.block_steps;
    // Each zone costs about as much per step as a block.
    const long long blocks = std::max<long long>(1, ctx.model.blocks.size() + ctx.model.zones.size());
    if (budget < 0) return blocks;
    const long long steps = budget / blocks;
    if (steps < 1) fail(loc, "this session may take no more steps (its budget of block-steps is spent)", {}, help_topic);
    if (max_steps <= 0 || max_steps > steps) max_steps = static_cast<long>(steps);
    return blocks;
}

inline void spend_step_budget(CommandContext& ctx, long long blocks, long steps) {
    if (ctx.interp.limits.block_steps >= 0) {
        ctx.interp.limits.block_steps = std::max<long long>(0, ctx.interp.limits.block_steps - blocks * steps);
    }
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

// The block material a command's keywords give, starting from `base`: density, bulk modulus
// ('bulk' or 'k'), shear modulus ('shear' or 'g'), Young's modulus and Poisson's ratio (named
// `young` and `poisson` by the command; together they replace K and G), and the Mohr-Coulomb
// cohesion, friction, tension and dilation. Fails, naming the word, when only one of the pair
// is given or when a dilation or friction given leaves the dilation above the friction.
inline Material material_from_args(const Args& a, Material base, const char* young, const char* poisson,
                                   const std::string& help_topic) {
    if (a.has(young) != a.has(poisson)) {
        const KeywordUse* u = a.has(young) ? a.find(young) : a.find(poisson);
        fail(u->loc, std::string("'") + young + "' and '" + poisson + "' go together", {"or give 'bulk' and 'shear'"},
             help_topic);
    }
    Material mat = base;
    mat.defined = true;
    mat.density = a.real_or("density", mat.density);
    mat.bulk = a.real_or("k", a.real_or("bulk", mat.bulk));
    mat.shear = a.real_or("g", a.real_or("shear", mat.shear));
    if (a.has(young)) {
        const double e = a.real(young), nu = a.real(poisson);
        mat.bulk = e / (3 * (1 - 2 * nu));
        mat.shear = e / (2 * (1 + nu));
    }
    mat.cohesion = a.real_or("cohesion", mat.cohesion);
    mat.friction = a.real_or("friction", mat.friction);
    mat.tension = a.real_or("tension", mat.tension);
    mat.dilation = a.real_or("dilation", mat.dilation);
    if (mat.dilation > mat.friction && (a.has("dilation") || a.has("friction"))) {
        const KeywordUse* u = a.has("dilation") ? a.find("dilation") : a.find("friction");
        fail(u->values[0].loc,
             "the dilation angle (" + num(mat.dilation) + " deg) may not exceed the friction angle (" +
                 num(mat.friction) + " deg): a zone would create energy as it yields",
             {"give the dilation at most the friction angle"}, help_topic);
    }
    return mat;
}

} // namespace odec
