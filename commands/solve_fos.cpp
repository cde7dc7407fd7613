#include "solve_fos.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analysis_mode.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/cycle.h"
#include "engine/fos.h"
#include "engine/verdict.h"
#include "engine/zones.h"
#include "progress.h"
#include "verdict_text.h"

namespace odec {

namespace {

constexpr double kPerturbation = 2;   // the stresses are multiplied by this to find Nr
constexpr long kMinResponse = 100;    // Nr is at least this many steps
constexpr long kDefaultCap = 50000;   // steps at most to find Nr, and for each trial
// A run of Nr steps whose mean ratio is above this fraction of the run's before: the ratio has
// stopped falling, the model is not coming to equilibrium.
constexpr double kStalled = 0.9;

// A factor: "1", "1.5", "1.41406".
std::string factor_text(double f) { return num(f); }

std::string g3(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2g", x);
    return buf;
}

// "1", "1 and 3", "1, 3 and 4".
std::string number_list(const std::vector<int>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) {
        if (i > 0) s += (i + 1 == v.size()) ? " and " : ", ";
        s += std::to_string(v[i]);
    }
    return s;
}

std::string targets_text(const FosTargets& t, const FosReducible& r) {
    std::vector<std::string> props;
    if (t.friction) props.push_back("friction (its tangent)");
    if (t.cohesion) props.push_back("cohesion");
    if (t.tension) props.push_back("tension");
    std::string p;
    for (size_t i = 0; i < props.size(); ++i) {
        if (i > 0) p += (i + 1 == props.size()) ? " and " : ", ";
        p += props[i];
    }
    std::string where;
    if (!r.joint_materials.empty()) {
        where += std::string("joint material") + (r.joint_materials.size() == 1 ? " " : "s ") +
                 number_list(r.joint_materials);
    }
    if (!r.zone_materials.empty()) {
        if (!where.empty()) where += " and ";
        where += std::string("the Mohr-Coulomb zones of material") + (r.zone_materials.size() == 1 ? " " : "s ") +
                 number_list(r.zone_materials);
    }
    return p + (t.associated ? " (dilation = friction)" : "") + " of " + where;
}

struct Trial {
    bool stable = false;
    bool stalled = false;     // the ratio stopped falling
    long steps = 0;
    double ratio = 0;         // at the end
    double mean = 0, mean_before = 0; // mean ratio over the last run of Nr steps and the one before
    StopReason reason = StopReason::Steps;
    std::string message;      // Error, BlowUp
    std::shared_ptr<SolveVerdict> verdict;
};

// Cycle the model as it is in runs of nr steps until the ratio falls below its limit (stable),
// stops falling from one run to the next, or `cap` steps have passed (fails).
Trial run_trial(CommandContext& ctx, const SourceLoc& loc, long nr, long cap, double ratio_limit) {
    Model& m = ctx.model;
    Trial t;
    SolveRecorder record;
    record.begin(m);
    const bool lines = !ctx.interp.quiet && ctx.interp.echo;
    ProgressReporter progress(ctx.out, ctx.interp.progress_seconds, m.step, 0, m.time, 0);
    double before = -1;
    for (;;) {
        long chunk = std::min(nr, cap - t.steps);
        const long long counted = limit_steps_to_budget(ctx, loc, chunk, "solve");
        double sum = 0;
        long n = 0;
        auto each = [&](const Model& mm) {
            record.observe(mm);
            sum += unbalanced_ratio(mm);
            ++n;
            if (lines && n % 100 == 0) progress(mm);
        };
        CycleLimits lim;
        lim.each_step = ctx.interp.stepping_functions();
        lim.max_steps = chunk;
        lim.ratio = ratio_limit;
        const CycleResult r = cycle(m, lim, &ctx.interp.interrupt, ProgressFn(each), 1);
        spend_step_budget(ctx, counted, r.steps);
        t.steps += r.steps;
        t.reason = r.reason;
        if (r.reason == StopReason::Ratio) {
            t.stable = true;
            break;
        }
        if (r.reason == StopReason::BlowUp) {
            // The motion ran away: the model failed, and this state is not one to keep.
            t.message = r.message;
            return t;
        }
        if (r.reason != StopReason::Steps) {
            t.message = r.message;
            return t;
        }
        const double mean = n > 0 ? sum / n : 0;
        t.mean = mean;
        t.mean_before = before;
        if (before > 0 && mean > kStalled * before) {
            t.stalled = true;
            break;
        }
        if (t.steps >= cap) break;
        before = mean;
    }
    record.finish(m);
    t.ratio = unbalanced_ratio(m);
    CycleLimits whole;
    whole.ratio = ratio_limit;
    whole.max_steps = t.steps;
    t.verdict = std::make_shared<SolveVerdict>(judge_solve(record, m, t.reason, whole, t.steps));
    return t;
}

// How far the model moved in a trial: the largest displacement of a free rigid block's centroid or of
// a gridpoint since the trial's start, and what moved (block id, or -1 and the gridpoint's number).
struct Moved {
    double distance = 0;
    int block = -1;     // id
    int gridpoint = -1; // from 1
};

Moved largest_move(const Model& start, const Model& m) {
    Moved mv;
    const BlockSet& s = m.blocks;
    if (start.blocks.size() == s.size()) {
        for (int b = 0; b < s.size(); ++b) {
            if (s.flags[b] & (kExcavated | kDeformable | kFixed)) continue;
            const double d = (s.centroid[b] - start.blocks.centroid[b]).norm();
            if (d > mv.distance) mv = {d, s.id[b], -1};
        }
    }
    const GridpointSet& g = m.gridpoints;
    if (start.gridpoints.size() == g.size()) {
        for (int i = 0; i < g.size(); ++i) {
            const double d = (g.pos[i] - start.gridpoints.pos[i]).norm();
            if (d > mv.distance) mv = {d, -1, i + 1};
        }
    }
    return mv;
}

// The model's size: the diagonal of the box around its blocks, m.
double model_size(const Model& m) {
    const BlockSet& s = m.blocks;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & kExcavated) continue;
        const Eigen::Matrix3d r = s.orientation[b].toRotationMatrix();
        for (const Vec3& v : s.shape[b].vertices) {
            const Vec3 x = s.centroid[b] + r * v;
            lo = lo.cwiseMin(x);
            hi = hi.cwiseMax(x);
        }
    }
    return hi.x() >= lo.x() ? (hi - lo).norm() : 0.0;
}

std::string moved_text(const Moved& mv) {
    return (mv.block > 0 ? "block " + std::to_string(mv.block) : "gridpoint " + std::to_string(mv.gridpoint)) + " moved " +
           g3(mv.distance) + " m";
}

std::string trial_text(const Trial& t, long cap) {
    if (t.stable) return "equilibrium after " + std::to_string(t.steps) + " steps (ratio " + g3(t.ratio) + ")";
    std::string s = "fails after " + std::to_string(t.steps) + " steps: ";
    if (t.reason == StopReason::BlowUp) {
        s += "the motion ran away (" + t.message + "); the model is not kept in this state";
    } else if (t.verdict && t.verdict->outcome == SolveOutcome::Mechanism) {
        s += "mechanism, " + mechanism_text(*t.verdict);
    } else if (t.stalled) {
        s += "no equilibrium, the ratio stopped falling (mean " + g3(t.mean_before) + ", then " + g3(t.mean) + ")";
    } else {
        s += "no equilibrium within the step limit " + std::to_string(cap) + " (ratio " + g3(t.ratio) + ")";
    }
    return s;
}

} // namespace

void solve_fos(CommandContext& ctx, const Args& a) {
    Model& m = ctx.model;
    const KeywordUse* fos = a.find("fos");
    const SourceLoc& loc = fos->loc;
    for (const char* kw : {"time", "elastic"}) {
        if (const KeywordUse* u = a.find(kw)) {
            fail(u->loc, std::string("'solve fos' takes no '") + kw + "'",
                 {"each trial runs until equilibrium or failure; 'cycles n' limits its steps"}, "solve");
        }
    }
    // What is reduced: include narrows the kinds and the strengths to those it names, exclude
    // takes away those it names.
    FosTargets t;
    auto is_kind = [](const std::string& w) { return w == "joints" || w == "zones"; };
    auto set = [&](const std::string& w, bool on) {
        if (w == "joints") t.joints = on;
        else if (w == "zones") t.zones = on;
        else if (w == "friction") t.friction = on;
        else if (w == "cohesion") t.cohesion = on;
        else if (w == "tension") t.tension = on;
    };
    const std::vector<const KeywordUse*> includes = a.all("include");
    bool kinds_named = false, strengths_named = false;
    for (const KeywordUse* u : includes) {
        for (const Value& v : u->values) (is_kind(v.text) ? kinds_named : strengths_named) = true;
    }
    if (kinds_named) t.joints = t.zones = false;
    if (strengths_named) t.friction = t.cohesion = t.tension = false;
    for (const KeywordUse* u : includes) {
        for (const Value& v : u->values) set(v.text, true);
    }
    for (const KeywordUse* u : a.all("exclude")) {
        for (const Value& v : u->values) {
            set(v.text, false);
            if (!(t.joints || t.zones) || !(t.friction || t.cohesion || t.tension)) {
                fail(v.loc, "excluding '" + v.text + "' leaves nothing to reduce", {}, "solve");
            }
        }
    }
    t.associated = a.has("associated");
    double f1 = 0, f2 = 0;
    if (a.has("bracket")) {
        f1 = a.real("bracket", 0);
        f2 = a.real("bracket", 1);
        if (f1 > f2) {
            fail(a.value("bracket", 1).loc, "the bracket's second factor (" + num(f2) + ") is below its first (" + num(f1) + ")",
                 {"give the factor expected stable first, the one expected to fail second"}, "solve");
        }
    }
    FosReducible r = fos_reducible(m, t);
    if (r.empty()) {
        fail(loc, "'solve fos' finds nothing to reduce",
             {"it lowers the friction, cohesion and tension of the joint materials the contacts use and of the "
              "materials of Mohr-Coulomb zones ('change cons=2'); none in use has a nonzero one" +
                  std::string(a.has("include") || a.has("exclude") ? " among those include and exclude leave" : "")},
             "solve");
    }
    if (!fos_model_loaded(m)) {
        fail(loc, "nothing loads the model: no gravity, no load and no stress in a zone or a joint, so nothing can fail",
             {"give gravity ('grav 0 0 -9.81') or loads ('bound ...'), bring the model to equilibrium, then 'solve fos'"},
             "solve");
    }
    // A range narrows the search to the contacts and zoned blocks it selects: copies of their
    // materials are reduced, the rest keep theirs. Checked on a copy first, so that a range
    // that selects nothing leaves the model as it was.
    if (a.has_range) {
        Model probe = m;
        FosReducible rr = r;
        fos_isolate(probe, a.range, rr);
        if (rr.empty()) {
            fail(a.range_loc, "the range selects no contact and no zoned block with a strength to reduce",
                 {"a range on 'solve fos' selects contacts by their centroid and zones by their block; 'not' "
                  "filters leave those out"},
                 "solve");
        }
    }
    const double resolution = a.real_or("resolution", 0.01);
    const double ratio = a.real_or("ratio", 1e-5);
    const long cap = a.has("cycles") ? static_cast<long>(a.real("cycles")) : kDefaultCap;
    std::ostream& o = ctx.out;
    const bool talk = !ctx.interp.quiet;

    // Every trial starts from this state; the model is put back to it if the search stops
    // with an error or is interrupted.
    FosIsolation iso;
    if (a.has_range) iso = fos_isolate(m, a.range, r);
    const Model start = m;
    const FosBase base = fos_base(m);
    struct Rewind {
        Model& m;
        const Model& start;
        const FosIsolation& iso;
        bool armed = true;
        ~Rewind() {
            if (!armed) return;
            m = start;
            fos_unisolate(m, iso);
        }
    } rewind{m, start, iso};
    ctx.interp.last_solve.reset();
    ctx.interp.last_fos.reset();
    ctx.interp.interrupt = false;
    CyclingGuard cycling(ctx.interp);
    const auto t0 = std::chrono::steady_clock::now();
    if (talk) {
        FosReducible shown = r; // the copies a range made, by the numbers they copy
        for (int& k : shown.joint_materials) {
            if (iso.active) k = iso.joint_original[k - iso.n_joint_materials];
        }
        for (int& k : shown.zone_materials) {
            if (iso.active) k = iso.material_original[k - iso.n_materials];
        }
        o << "solve fos: reducing " << targets_text(t, shown) << (iso.active ? " where the range selects" : "")
          << " by trial factors F, each trial from the state at step "
          << start.step << "\n";
    }
    if (!r.zone_materials.empty() && m.settings.large_strain) {
        warn(ctx, loc,
             "large strain ('set large', the default): zones whose strength is reduced may move far enough to find "
             "a new equilibrium, and a trial that fails reads as stable; strength reduction of zones is usually "
             "run in small strain ('set small' before 'solve fos')");
    }
    auto interrupted = [&](const std::string& when) {
        if (talk) o << "solve fos: interrupted " << when << "; the model is as it was before 'solve fos'\n";
    };

    // The characteristic response: steps back to equilibrium after the stresses were doubled
    // with the strengths raised.
    FosResult res;
    res.resolution = resolution;
    long nr = 0;
    if (a.has("nchar")) {
        nr = a.integer("nchar");
        if (talk) o << "solve fos: characteristic response Nr = " << nr << " steps (given)\n";
    } else {
        perturb_for_response(m, r, kPerturbation);
        long limit = cap;
        const long long counted = limit_steps_to_budget(ctx, loc, limit, "solve");
        CycleLimits lim;
        lim.each_step = ctx.interp.stepping_functions();
        lim.max_steps = limit;
        lim.ratio = ratio;
        const CycleResult c = cycle(m, lim, &ctx.interp.interrupt);
        spend_step_budget(ctx, counted, c.steps);
        res.steps += c.steps;
        if (c.reason == StopReason::Interrupted) return interrupted("while finding the characteristic response");
        if (c.reason == StopReason::Error || c.reason == StopReason::BlowUp) {
            fail(loc, "while finding the characteristic response: " + c.message,
                 {"the model is left as it was before 'solve fos'"}, "solve");
        }
        if (c.reason != StopReason::Ratio) {
            fail(loc,
                 "the model does not come back to equilibrium (ratio " + num(ratio) + ") within " + std::to_string(c.steps) +
                     " steps after its stresses were doubled with its strengths raised: no characteristic response to "
                     "run the trials by",
                 {"bring the model to equilibrium first ('solve'), give more steps ('cycles n'), or give the response "
                  "('nchar n')"},
                 "solve");
        }
        nr = std::max(kMinResponse, c.steps);
        if (talk) {
            o << "solve fos: characteristic response Nr = " << nr << " steps (back to equilibrium in " << c.steps
              << " steps after the stresses were doubled with the strengths raised)\n";
        }
    }
    res.nr = nr;
    report_mass_scaling(ctx);

    const double dmax = a.real_or("dmax", 0.0);
    const double size = model_size(m);
    int far_trials = 0;
    FosBracket bracket(resolution, f1, f2);
    std::unique_ptr<Model> failing;
    double failing_factor = 0;
    std::shared_ptr<SolveVerdict> failing_verdict;
    while (bracket.next() > 0) {
        const double F = bracket.next();
        m = start;
        reduce_strengths(m, base, r, t, F);
        Trial tr = run_trial(ctx, loc, nr, cap, ratio);
        res.steps += tr.steps;
        // A stable trial that moved far: said, and with 'dmax' a failure.
        std::string far;
        if (tr.stable) {
            const Moved mv = largest_move(start, m);
            if (dmax > 0 && mv.distance > dmax) {
                tr.stable = false;
                far = "fails after " + std::to_string(tr.steps) + " steps: it came to equilibrium (ratio " + g3(tr.ratio) +
                      ") only after " + moved_text(mv) + ", more than dmax " + num(dmax) +
                      " m: a mechanism that found a new footing";
            } else if (dmax <= 0 && mv.distance > 0.01 * size) {
                far = ", but " + moved_text(mv) + " in the trial (" + g3(100 * mv.distance / size) +
                      " % of the model's size): a mechanism that found a new footing? ('dmax d' counts such a trial as failing)";
                ++far_trials;
            }
        }
        ++res.trials;
        if (tr.reason == StopReason::Interrupted) return interrupted("in the trial at F = " + factor_text(F));
        if (tr.reason == StopReason::Error) {
            fail(loc, "in the trial at F = " + factor_text(F) + ": " + tr.message,
                 {"the model is left as it was before 'solve fos'"}, "solve");
        }
        if (talk) {
            char head[64];
            std::snprintf(head, sizeof head, "  trial %d: F = %-9s ", res.trials, factor_text(F).c_str());
            if (!tr.stable && !far.empty()) o << head << far << "\n";
            else o << head << trial_text(tr, cap) << far << "\n";
            o.flush();
        }
        bracket.report(tr.stable);
        if (!tr.stable && tr.reason != StopReason::BlowUp) {
            if (!failing) failing = std::make_unique<Model>();
            *failing = std::move(m);
            failing_factor = F;
            failing_verdict = tr.verdict;
        }
    }
    // The model: as the last failing trial left it, with its strengths given back.
    if (failing) {
        m = std::move(*failing);
        failing.reset();
        restore_strengths(m, base, r);
    } else {
        m = start;
    }
    fos_unisolate(m, iso);
    rewind.armed = false;
    res.end = bracket.end();
    res.factor = bracket.factor();
    res.stable = bracket.has_stable() ? bracket.stable() : 0;
    res.fails = bracket.has_fail() ? bracket.fails() : 0;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ctx.interp.last_fos = std::make_shared<FosResult>(res);
    if (failing_factor > 0) ctx.interp.last_solve = failing_verdict;
    m.mass_scaling.fresh = false; // said once, before the trials
    if (!talk) return;
    char tail[160];
    std::snprintf(tail, sizeof tail, "%d trial%s, %ld steps (Nr %ld), %.2f s", res.trials, res.trials == 1 ? "" : "s",
                  res.steps, res.nr, res.seconds);
    switch (res.end) {
    case FosBracket::End::Found:
        o << "solve fos: factor of safety " << factor_text(res.factor) << " +/- " << num(0.5 * (res.fails - res.stable))
          << " (stable at " << factor_text(res.stable) << ", fails at " << factor_text(res.fails) << "; resolution "
          << num(resolution) << "): " << tail << "\n";
        break;
    case FosBracket::End::Below:
        o << "solve fos: the model fails at F = " << factor_text(res.fails) << ", the lowest factor tried: the factor of "
          << "safety is below it (" << tail << ")\n";
        break;
    case FosBracket::End::Above:
        o << "solve fos: the model is stable at F = " << factor_text(res.stable) << ", the highest factor tried: the "
          << "factor of safety is above it (" << tail << ")\n";
        break;
    case FosBracket::End::OneStable:
        o << "solve fos: stable at F = " << factor_text(res.stable) << ": the factor of safety is at least that (" << tail
          << ")\n";
        break;
    case FosBracket::End::OneFails:
        o << "solve fos: fails at F = " << factor_text(res.fails) << ": the factor of safety is below that (" << tail
          << ")\n";
        break;
    case FosBracket::End::Running:
        break;
    }
    if (far_trials > 0) {
        warn(ctx, loc,
             std::to_string(far_trials) + " stable trial" + (far_trials == 1 ? "" : "s") +
                 " moved more than 1 % of the model's size before coming to rest: if that is a failure, give "
                 "'solve fos dmax d' with the displacement a failure starts at");
    }
    if (failing_factor > 0) {
        o << "solve fos: the model is left as the trial at F = " << factor_text(failing_factor)
          << " left it (its strengths as they were): 'plot' shows the failure\n";
    } else if (res.fails > 0) {
        o << "solve fos: every failing trial ran away; the model is as it was before 'solve fos'\n";
    } else {
        o << "solve fos: no trial failed; the model is as it was before 'solve fos'\n";
    }
}

} // namespace odec
