// How commands speak of static and dynamic analysis (engine/mass_scaling.h).
#pragma once

#include <string>

#include "common.h"
#include "engine/model.h"

namespace odec {

// One line on the mode: "static (density scaling ...)" or "dynamic (real masses ...)".
inline std::string analysis_mode_text(const Model& m) {
    const MassScalingReport& r = m.mass_scaling;
    std::string t;
    if (!m.settings.dynamic) {
        t = "static, density scaling: masses from stiffness, time not real";
        if (r.is_static && r.dt > 0 && r.real_dt > 0) t += "\n            (real masses would need dt " + num(r.real_dt) + " s)";
    } else {
        t = "dynamic: real masses and real time";
        if (m.settings.mscale_dt > 0) {
            t += "; mscale " + num(m.settings.mscale_dt) + " s";
            if (!r.is_static && r.dt > 0 && (r.n_gridpoints > 0 || r.n_blocks > 0)) {
                t += "\n            (" + std::to_string(r.n_gridpoints) + " gridpoint, " + std::to_string(r.n_blocks) +
                     " block masses scaled; " + num(r.added) + " kg added, " +
                     num(r.total > 0 ? 100.0 * r.added / r.total : 0.0) + " % of the model)";
            }
        }
    }
    return t;
}

// After cycling: say once how the masses were chosen, when that changed.
inline void report_mass_scaling(CommandContext& ctx) {
    MassScalingReport& r = ctx.model.mass_scaling;
    if (!r.fresh) return;
    r.fresh = false;
    if (ctx.interp.quiet || !ctx.interp.echo) return;
    std::ostream& o = ctx.out;
    if (r.is_static) {
        o << "static analysis: density scaling, timestep " << num(r.dt) << " s";
        if (r.real_dt > 0) o << " (real masses would need " << num(r.real_dt) << " s)";
        o << "; model time is not real time\n";
    } else if (ctx.model.settings.mscale_dt > 0) {
        if (r.n_gridpoints == 0 && r.n_blocks == 0 && r.n_nodes == 0) {
            o << "mscale: no mass needs scaling, the timestep " << num(r.dt) << " s is the real masses' own\n";
        } else {
            o << "mscale: " << r.n_gridpoints << " gridpoint" << (r.n_nodes > 0 ? ", " : " and ") << r.n_blocks
              << " block";
            if (r.n_nodes > 0) o << " and " << r.n_nodes << " cable and liner node";
            o << " masses scaled (factors "
              << num(r.min_factor) << " to " << num(r.max_factor) << "), mass added " << num(r.added) << " kg, "
              << num(r.total > 0 ? 100.0 * r.added / r.total : 0.0) << " % of " << num(r.total)
              << " kg; timestep " << num(r.dt) << " s (real masses would need " << num(r.real_dt) << " s)\n";
        }
    }
}

// The note for a command that deals in model time while the analysis is static.
inline void note_static_time(CommandContext& ctx, const std::string& what) {
    if (ctx.model.settings.dynamic || ctx.interp.quiet) return;
    ctx.out << "note: " << what << " in a static analysis: the masses are scaled for convergence, so model time "
               "is not real time ('config dyn' for a dynamic analysis in real time)\n";
}

} // namespace odec
