#include <algorithm>
#include <memory>

#include "analysis_mode.h"
#include "commands.h"
#include "common.h"
#include "engine/cycle.h"
#include "engine/fos.h"
#include "engine/verdict.h"
#include "progress.h"
#include "solve_fos.h"
#include "verdict_text.h"

namespace odec {

namespace {
// The cohesion and tension of the joints in the first stage of 'solve elastic'.
constexpr double kElasticStrength = 1e30;
} // namespace

const CommandSpec& solve_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("solve", 3, "cycle until the model is in equilibrium (or a limit is reached)");
        c.keyword("ratio", 2, "stop when the mean unbalanced-force ratio falls below r")
            .real("r", 0, 1, Limit::Open, Limit::Open)
            .defaults("1e-5");
        c.keyword("cycles", 2, "stop after n steps at most").integer("n", 1, 2e9).defaults("200000");
        c.keyword("time", 2, "run for model time t, s (with 'ratio' too: whichever comes first)")
            .real("t", 0, kInf, Limit::Open);
        c.keyword("elastic", 3, "(3DEC) solve first with joints that cannot slip or open, then with their "
                                "strengths: the start of a model whose joints would fail under the first jolt");
        c.keyword("fos", 3, "(3DEC) the factor of safety by strength reduction: see below");
        c.keyword("resolution", 3, "with fos: stop when the bracket of the factor is no wider than f")
            .real("f", 0, 1, Limit::Open, Limit::Closed)
            .defaults("0.01");
        c.keyword("bracket", 3, "with fos: start from f1 (must be stable) and f2 (must fail); f1 = f2: test that one")
            .real("f1", 0, kFosFar, Limit::Open, Limit::Closed)
            .real("f2", 0, kFosFar, Limit::Open, Limit::Closed);
        c.keyword("nchar", 3, "with fos: the characteristic response Nr, steps (instead of finding it)")
            .integer("n", 1, 2e9);
        c.keyword("associated", 3, "with fos: the dilation angle made equal to the reduced friction angle");
        c.keyword("dmax", 2, "with fos: a trial that comes to equilibrium after a block or gridpoint moved more than d, m, "
                             "fails (a mechanism that found a new footing)")
            .real("d", 0, kMaxMagnitude, Limit::Open, Limit::Closed);
        c.keyword("include", 3, "with fos: reduce only these (kinds: joints, zones; strengths: friction, cohesion, tension)")
            .one_of("what", {"joints", "zones", "friction", "cohesion", "tension"})
            .repeat()
            .many();
        c.keyword("exclude", 3, "with fos: leave these as they are (the same words as include)")
            .one_of("what", {"joints", "zones", "friction", "cohesion", "tension"})
            .repeat()
            .many();
        c.range();
        c.describe("The mean unbalanced-force ratio is the sum over free blocks of the unbalanced force "
                   "divided by the sum of the magnitudes of all the forces acting on them. A long run prints "
                   "its progress every few seconds (step, time, ratio, and the time left when it runs to a "
                   "number of steps or a time), unless --quiet or 'set echo off'. Ctrl-C stops it at the prompt. "
                   "It ends with one verdict: 'equilibrium' (the ratio limit was reached: the ratio and the "
                   "steps); 'mechanism' (stopped by the step limit with blocks still moving one way at a "
                   "steady or growing rate: their ids, how many, their largest speed in m/s, and how far they "
                   "moved over the last part of the run); or 'not converged' (stopped by the step limit while "
                   "settling: how the ratio fell over the last fifth of the steps, about how many steps a "
                   "decade takes, how many more the ratio limit would take at that rate, and whether the "
                   "largest speed is falling). A run stopped by its time limit or by Ctrl-C says so, and a "
                   "time-limited run names a mechanism too. A deformable block counts through its gridpoints; "
                   "fixed and velocity-driven blocks are left out. 'print info' shows the last solve's "
                   "criteria and verdict, and FISH's solve_verdict gives it in a word. Blocks made "
                   "overlapping where they carry no stress yet, deeper than the overlap tolerance ('set "
                   "ovtol'), stop it before its first step with an error that names each pair.\n\n"
                   "'solve fos' (3DEC's SOLVE fos) finds the factor of safety F by strength reduction: the factor by "
                   "which the strengths must be divided for the model, as it is now (bring it to equilibrium "
                   "first), to just fail. A trial factor F gives tan(phi)/F, c/F and t/F to the joint materials "
                   "the contacts use (a joint model 2's residual friction too) and to the materials of "
                   "Mohr-Coulomb zones, each from its value before; the dilation angle is kept at most the reduced "
                   "friction angle, or made equal to it with 'associated'. 'include' narrows what is reduced to "
                   "the kinds (joints, zones) and strengths (friction, cohesion, tension) it names, 'exclude' "
                   "leaves out those it names. Without a range whole materials are reduced, wherever they are; a "
                   "range narrows the search to the contacts whose centroid it selects and the zones of the blocks "
                   "it selects ('not' filters leave some out): they get copies of their materials, and only the "
                   "copies are reduced (contacts made during a trial are not). First the "
                   "characteristic response Nr is found (unless 'nchar' gives it): the steps the model takes to "
                   "come back to equilibrium after its joint closures, shear stresses and zone stresses are "
                   "doubled with its strengths raised (at least 100). Each trial starts from the state before "
                   "'solve fos' and cycles in runs of Nr steps: it is stable when the mean unbalanced-force ratio "
                   "falls below 'ratio' (1e-5), and fails when the mean ratio over a run of Nr steps is more than "
                   "0.9 of that over the run before (it stopped falling) or when 'cycles' steps (50000) have "
                   "passed. The first trial is at F = 1; the factor doubles while stable and halves while failing "
                   "until one of each is known (up to 1024 or down to 1/1024), then the middle of the bracket is "
                   "tried until the bracket is no wider than 'resolution' (0.01). 'bracket f1 f2' starts instead "
                   "from f1, which must be stable, and f2, which must fail (the search ends saying the factor is "
                   "below f1 or above f2 otherwise); with f1 = f2 only that factor is tried. Each trial prints its "
                   "factor and verdict: equilibrium (steps, ratio) or fails (a mechanism: the blocks moving, as "
                   "'solve' names them; the ratio that stopped falling; or a motion that ran away, whose state is not kept). The search ends with the factor of "
                   "safety, the middle of the final bracket, +/- half its width, and the trials, steps, Nr and "
                   "wall time. The model is then left as the last failing trial left it (positions, velocities, "
                   "displacements, contacts and stresses, step and time), so that 'plot' shows the failure "
                   "mechanism and 'print info' and FISH's solve_verdict its verdict, but with its strengths "
                   "given back their values from before 'solve fos'; when no trial failed it is left as it was. "
                   "A stable trial in which a block or gridpoint moved more than 1 % of the model's size says so "
                   "(which one, how far): a mechanism that slid until it found a new footing (a dam whose base "
                   "lost its water, a wedge that came to rest on the next bench) stands at the end of its trial. "
                   "'dmax d' counts a trial in which anything moved more than d metres as failing; without it, "
                   "as in 3DEC, only the unbalanced force decides. "
                   "FISH's fos_f gives the factor. An error or Ctrl-C during the search leaves the model as it "
                   "was before it. The search holds up to three copies of the model in memory. Zones are reduced "
                   "as they are in small strain ('set small'): in large strain, the default, a failing slope of "
                   "zones may move far enough to find a new equilibrium and read as stable, and 'solve fos' "
                   "warns when it reduces zones in large strain.");
        c.example("solve");
        c.example("solve ratio 1e-6 cycles 50000");
        c.example("solve fos");
        c.example("solve fos resolution 0.005 exclude tension");
        c.refuse_while_cycling(kNoNestedCycling);
        c.handle([](CommandContext& ctx, const Args& a) {
            if (a.has("fos")) {
                solve_fos(ctx, a);
                return;
            }
            if (a.has_range) {
                fail(a.range_loc, "a range belongs to 'solve fos' (it narrows what is reduced)",
                     {"'solve' cycles the whole model"}, "solve");
            }
            for (const char* kw : {"resolution", "bracket", "nchar", "associated", "include", "exclude", "dmax"}) {
                if (const KeywordUse* u = a.find(kw)) {
                    fail(u->loc, std::string("'") + kw + "' belongs to 'solve fos'", {"add 'fos' to search for the factor of safety"},
                         "solve");
                }
            }
            Model& m = ctx.model;
            CycleLimits lim;
            lim.each_step = ctx.interp.stepping_functions();
            // 'solve time t' runs for t seconds of model time; with 'ratio' too, whichever
            // comes first.
            lim.ratio = a.has("ratio") ? a.real("ratio") : (a.has("time") ? 0.0 : 1e-5);
            lim.max_steps = a.has("cycles") ? static_cast<long>(a.real("cycles")) : (a.has("time") ? 0 : 200000);
            lim.max_time = a.real_or("time", 0);
            std::ostream& o = ctx.out;
            const bool talk = !ctx.interp.quiet;
            auto line = [&](const Model& mm) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "step %ld  time %.6g s  max unbalanced force %.6g N  ratio %.3e\n",
                              mm.step, mm.time, max_unbalanced_force(mm), unbalanced_ratio(mm));
                o << buf;
                o.flush();
            };
            const long long counted = limit_steps_to_budget(ctx, a.loc, lim.max_steps, "solve");
            ctx.interp.interrupt = false;
            // The time left is known only when the ratio cannot end the run first.
            const bool known_end = !(lim.ratio > 0);
            ProgressReporter progress(o, ctx.interp.progress_seconds, m.step, known_end ? lim.max_steps : 0, m.time,
                                      known_end ? lim.max_time : 0);
            const bool lines = talk && ctx.interp.echo;
            // 'solve elastic': a first stage whose joints keep their stiffness but cannot slip, open
            // or fail (strengths made huge for it), then the joints as they are.
            // Only the strengths the first stage raised are given back: a joint material that a
            // function running during the stage added or changed ('prop jmat' in a
            // whilestepping function) keeps what it was given.
            std::vector<JointMaterial> strengths = m.joint_materials;
            struct Restore {
                Model& m;
                std::vector<JointMaterial>& saved;
                bool active = false;
                void give_back() {
                    const size_t n = std::min(saved.size(), m.joint_materials.size());
                    for (size_t k = 0; k < n; ++k) {
                        JointMaterial& j = m.joint_materials[k];
                        if (j.cohesion == kElasticStrength) j.cohesion = saved[k].cohesion;
                        if (j.tension == kElasticStrength) j.tension = saved[k].tension;
                        if (j.dilation == 0) j.dilation = saved[k].dilation;
                    }
                    active = false;
                }
                ~Restore() {
                    if (active) give_back();
                }
            } restore{m, strengths};
            if (a.has("time")) note_static_time(ctx, "'solve time'");
            ctx.interp.last_solve.reset();
            // The verdict at the end comes from a small record of the run (engine/verdict.h),
            // sampled through the cycle's progress call, made every step.
            SolveRecorder record;
            long stage_first = m.step;
            auto each = [&](const Model& mm) {
                record.observe(mm);
                if (lines && (mm.step - stage_first) % 100 == 0) progress(mm);
            };
            CycleResult r;
            CyclingGuard cycling(ctx.interp);
            for (int stage = a.has("elastic") ? 0 : 1; stage < 2; ++stage) {
                if (stage == 0) {
                    for (JointMaterial& j : m.joint_materials) {
                        j.cohesion = j.tension = kElasticStrength;
                        j.dilation = 0;
                    }
                    restore.active = true;
                } else if (restore.active) {
                    restore.give_back();
                    if (talk && r.reason == StopReason::Ratio) {
                        o << "solve elastic: equilibrium with elastic joints reached; now with their strengths\n";
                    } else if (talk) {
                        // The first stage ran out of its steps or time: what follows starts from a
                        // model that is still moving, and the user should know.
                        o << "solve elastic: the elastic stage stopped at its " << (r.reason == StopReason::Time ? "time" : "step")
                          << " limit after " << r.steps << " steps, short of equilibrium (ratio " << num(unbalanced_ratio(m))
                          << "); now with their strengths\n";
                    }
                }
                stage_first = m.step;
                record.begin(m);
                r = cycle(m, lim, &ctx.interp.interrupt, ProgressFn(each), 1);
                spend_step_budget(ctx, counted, r.steps);
                report_mass_scaling(ctx);
                if (r.reason == StopReason::Error) fail(a.loc, r.message, {}, "solve");
                if (r.reason == StopReason::BlowUp) {
                    fail(a.loc, "stopped: " + r.message, {"the model is left as it was at that step, for inspection"}, "solve");
                }
                if (r.reason == StopReason::Interrupted) break;
            }
            record.finish(m);
            auto verdict = std::make_shared<SolveVerdict>(judge_solve(record, m, r.reason, lim, r.steps));
            ctx.interp.last_solve = verdict;
            if (!talk) return;
            line(m);
            o << "solve: " << verdict_text(*verdict) << "\n";
            // A run for a time keeps its plain line; a mechanism found in it is said too.
            if (r.reason == StopReason::Time && verdict->outcome == SolveOutcome::Mechanism) {
                o << "solve: mechanism: " << mechanism_text(*verdict) << "\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
