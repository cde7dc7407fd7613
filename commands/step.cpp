#include "analysis_mode.h"
#include "commands.h"
#include "common.h"
#include "engine/cycle.h"
#include "progress.h"

namespace odec {

const CommandSpec& step_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("step", 3, "take a number of timesteps");
        c.alias("cycle");
        c.positional.integer("n", 1, 2e9).optional();
        c.keyword("time", 2, "advance the model time by t, s, instead").real("t", 0, kInf, Limit::Open);
        c.describe("Ctrl-C at the prompt stops the stepping between two steps; the model stays as it "
                   "was after the last whole step. A long run prints its progress every few seconds (step, "
                   "time, unbalanced ratio, time left), unless --quiet or 'set echo off'. Blocks made "
                   "overlapping where they carry no stress yet, deeper than the overlap tolerance ('set "
                   "ovtol'), stop it before its first step with an error that names each pair and how deep "
                   "it overlaps, the model left as it was.");
        c.example("step 1000");
        c.example("cycle time 0.5");
        c.refuse_while_cycling(kNoNestedCycling);
        c.handle([](CommandContext& ctx, const Args& a) {
            CycleLimits lim;
            lim.each_step = ctx.interp.stepping_functions();
            if (!a.positional.empty() && a.has("time")) {
                fail(a.find("time")->loc, "give either a number of steps or 'time', not both", {}, "step");
            }
            if (!a.positional.empty()) {
                lim.max_steps = static_cast<long>(a.positional[0].number);
            } else if (a.has("time")) {
                lim.max_time = a.real("time");
                note_static_time(ctx, "'step time'");
            } else {
                fail(a.loc, "'step' needs a number of steps or 'time t'", {"for example: step 1000"}, "step");
            }
            Model& m = ctx.model;
            const long long counted = limit_steps_to_budget(ctx, a.loc, lim.max_steps, "step");
            ctx.interp.interrupt = false;
            const bool talk = !ctx.interp.quiet && ctx.interp.echo;
            ProgressReporter progress(ctx.out, ctx.interp.progress_seconds, m.step, lim.max_steps, m.time, lim.max_time);
            CyclingGuard cycling(ctx.interp);
            const CycleResult r =
                cycle(m, lim, &ctx.interp.interrupt, talk ? ProgressFn(std::ref(progress)) : ProgressFn(), 100);
            spend_step_budget(ctx, counted, r.steps);
            report_mass_scaling(ctx);
            if (r.reason == StopReason::Error) fail(a.loc, r.message, {}, "step");
            if (r.reason == StopReason::Interrupted) {
                ctx.out << "interrupted after " << r.steps << " steps: step " << m.step << ", time " << num(m.time)
                        << " s\n";
                return; // the flag stays raised: a script running this stops here

            }
            if (r.reason == StopReason::BlowUp) {
                fail(a.loc, "stopped: " + r.message, {"the model is left as it was at that step, for inspection"},
                     "step");
            }
            if (!ctx.interp.quiet) {
                ctx.out << "step " << m.step << "  time " << num(m.time) << " s  dt " << num(m.dt)
                        << " s  max unbalanced force " << num(max_unbalanced_force(m)) << " N\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
