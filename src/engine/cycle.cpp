#include "engine/cycle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "engine/blocks.h"
#include "engine/cable.h"
#include "engine/contact.h"
#include "engine/flow.h"
#include "engine/stages.h"

namespace odec {

namespace {

using Clock = std::chrono::steady_clock;

// Times a stage from `lap`, the end of the stage before it (or the start of the step's stages),
// to its own end, which becomes the next stage's start: one reading of the clock per stage. (What
// runs between two stages is a test or two, counted in the next; what is not a stage, the
// functions called at every step and the progress report, is left out by restarting `lap`.)
struct StageTimer {
    Profile& p;
    Stage s;
    Clock::time_point& lap;
    ~StageTimer() {
        const Clock::time_point t = Clock::now();
        p.seconds[static_cast<int>(s)] += std::chrono::duration<double>(t - lap).count();
        lap = t;
    }
};

} // namespace

CycleResult cycle(Model& m, const CycleLimits& lim, const std::atomic<bool>* interrupt,
                  const ProgressFn& progress, long progress_every) {
    CycleResult res;
    // (What was done to the model between two runs is not known to the stages: ContactSet::rest.)
    ++m.contacts.cycle_runs;
    // The step counter stops at kMaxStep rather than overflow (a model restored at a step
    // near it could otherwise count past what a long holds).
    auto step_limit_reached = [&] {
        if (m.step < kMaxStep && m.profile.steps < kMaxStep) return false;
        res.reason = StopReason::Error;
        res.message = "the step number has reached " + std::to_string(std::max(m.step, m.profile.steps)) +
                      ", the most odec counts (1e18): the model cannot cycle further";
        return true;
    };
    if (step_limit_reached()) return res;
    // Kept only until the cycling is accepted: its copies (the contact set when the geometry
    // changed, the masses and velocities) are given back before the first step.
    std::optional<PrepareUndo> undo(std::in_place, m);
    const std::string problem = prepare_cycle_once(m);
    if (!problem.empty()) {
        undo->undo(m);
        res.reason = StopReason::Error;
        res.message = problem;
        return res;
    }
    // A time limit so far away that no run of steps reaches it would cycle for ever.
    constexpr double kMaxSteps = 2e9;
    if (lim.max_time > 0 && !(lim.max_time / m.dt <= kMaxSteps)) {
        res.reason = StopReason::Error;
        res.message = "a time of " + num_text(lim.max_time) + " s is more than 2e9 steps of " + num_text(m.dt) +
                      " s, the most one command may take (" + num_text(kMaxSteps * m.dt) + " s)";
        undo->undo(m);
        return res;
    }
    undo.reset();
    const double t_start = m.time;
    Profile& prof = m.profile;
    EnergyWatch watch;
    watch.begin(m);
    // The energy account (energy.h): what commands changed since the last cycle is given, and
    // the cycle leaves the model marked however it stops.
    take_energy(m);
    struct LeaveEnergy {
        Model& m;
        ~LeaveEnergy() { mark_energy(m); }
    } leave_energy{m};
    // Nothing outside the stages sees world vertices behind the blocks (refresh_block_rotations):
    // the commands after the cycle, the functions and histories within it.
    struct LeaveVertices {
        Model& m;
        ~LeaveVertices() { catch_up_world_vertices(m); }
    } leave_vertices{m};
    for (;;) {
        if (lim.max_steps > 0 && res.steps >= lim.max_steps) {
            res.reason = StopReason::Steps;
            break;
        }
        if (lim.max_time > 0 && m.time - t_start >= lim.max_time * (1 - 1e-12)) {
            res.reason = StopReason::Time;
            break;
        }
        if (interrupt && interrupt->load(std::memory_order_relaxed)) {
            res.reason = StopReason::Interrupted;
            break;
        }
        if (step_limit_reached()) break;
        if (!std::isfinite(m.time + m.dt)) {
            res.reason = StopReason::Error;
            res.message = "the model time, " + num_text(m.time) + " s, would pass the largest number odec holds "
                          "with a step of " + num_text(m.dt) + " s: the model cannot cycle further";
            break;
        }
        if (lim.each_step) {
            catch_up_world_vertices(m);
            // What the functions give the blocks ('ini xvel', 'b_xvel(b) = ...') is energy the
            // run-away check must allow for, as it allows for what the loads give.
            const double ke_before = watch.kinetic(m);
            mark_energy(m);
            const std::string p = lim.each_step(m);
            watch.forget_contacts(); // (the functions may have changed the joints)
            if (!p.empty()) {
                res.reason = StopReason::Error;
                res.message = p;
                break;
            }
            if (!watch.stale(m)) watch.given(watch.kinetic(m) - ke_before);
            if (!m.geometry_changed && !watch.stale(m)) take_energy(m);
        }
        // The functions may have changed the blocks (a 'jset', 'poly' or 'gen' in a command
        // block): contacts, masses and timestep follow, and the run-away checks start afresh
        // from the new blocks.
        if (m.geometry_changed || watch.stale(m)) {
            catch_up_world_vertices(m);
            const std::string p = prepare_cycle_once(m);
            if (!p.empty()) {
                res.reason = StopReason::Error;
                res.message = p;
                break;
            }
            watch.begin(m);
            take_energy(m);
        }
        Clock::time_point lap = Clock::now();
        {
            StageTimer t{prof, Stage::ApplyLoads, lap};
            apply_loads(m);
        }
        {
            StageTimer t{prof, Stage::DetectContacts, lap};
            detect_contacts(m);
        }
        if (m.zones.size() > 0) {
            // Zone forces first: they start the gridpoints' forces, which contacts add to.
            StageTimer t{prof, Stage::Zones, lap};
            zone_forces(m, m.dt);
        }
        {
            StageTimer t{prof, Stage::UpdateContacts, lap};
            update_contacts(m, m.dt);
        }
        if (m.cables.size() > 0) {
            // Cable forces after the joints': they add into the same blocks and gridpoints.
            StageTimer t{prof, Stage::Cables, lap};
            cable_forces(m, m.dt);
        }
        if (m.flow.on) {
            // The pore pressures advance and push on both faces of each joint (flow.h).
            StageTimer t{prof, Stage::Flow, lap};
            const std::string why = flow_step(m, m.dt);
            if (!why.empty()) {
                res.reason = StopReason::Error;
                res.message = why;
                break;
            }
        }
        if (m.liners.size() > 0) {
            // Liner forces after the cables': they add into the same gridpoints.
            StageTimer t{prof, Stage::Liners, lap};
            liner_forces(m, m.dt);
        }
        int bad;
        // Adaptive damping gathers over every free degree of freedom (integrate.cpp).
        AutoDampingSums auto_sums;
        AutoDampingSums* sums = m.damping.mode == DampingMode::Auto ? &auto_sums : nullptr;
        {
            StageTimer t{prof, Stage::Integrate, lap};
            bad = integrate(m, m.dt, sums);
            // (The rigid blocks' world vertices wait for what reads them: catch_up_world_vertices.)
            refresh_block_rotations(m);
        }
        int bad_node = -1;
        if (m.cables.size() > 0) {
            // The nodes follow the rock across their axis: after the blocks and gridpoints moved.
            StageTimer t{prof, Stage::Cables, lap};
            bad_node = integrate_cables(m, m.dt, sums);
        }
        if (m.liners.size() > 0 && bad_node < 0) {
            StageTimer t{prof, Stage::Liners, lap};
            const int i = integrate_liners(m, m.dt, sums);
            if (i >= 0) bad_node = -2 - i;
        }
        if (sums) adjust_auto_damping(m.damping, auto_sums, m.dt);
        m.time += m.dt;
        ++m.step;
        ++res.steps;
        ++prof.steps;
        // Said before the histories are sampled: a FISH history may change the blocks.
        if (bad >= 0) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of block " + std::to_string(m.blocks.id[bad]) + " has run away (step " +
                          std::to_string(m.step) + "): its velocity is no longer a finite number; likely cause: " +
                          runaway_cause(m, bad);
        } else if (bad_node <= -2) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of liner node " + std::to_string(-2 - bad_node + 1) + " has run away (step " +
                          std::to_string(m.step) + "): its position is no longer a finite number";
            bad = -2;
        } else if (bad_node >= 0) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of cable node " + std::to_string(bad_node + 1) + " has run away (step " +
                          std::to_string(m.step) + "): its position is no longer a finite number";
            bad = -2;
        }
        {
            StageTimer t{prof, Stage::Record, lap};
            if (m.histories.ncyc > 0 && m.step % m.histories.ncyc == 0) {
                // A contact's history reads its point, and a function anything.
                if (std::any_of(m.histories.items.begin(), m.histories.items.end(), [](const History& h) {
                        switch (h.kind) {
                        case HistoryKind::Fish:
                        case HistoryKind::NForce:
                        case HistoryKind::SForce:
                        case HistoryKind::NStress:
                        case HistoryKind::SStress:
                        case HistoryKind::NDis:
                        case HistoryKind::SDis: return true;
                        default: return false;
                        }
                    })) {
                    catch_up_world_vertices(m);
                }
                // A FISH history may give the blocks energy too.
                bool fish = false;
                for (const History& h : m.histories.items) fish = fish || h.kind == HistoryKind::Fish;
                const double ke_before = fish ? watch.kinetic(m) : 0.0;
                if (fish) mark_energy(m);
                const std::string failed = m.histories.sample(m);
                if (fish) watch.forget_contacts();
                if (!failed.empty() && bad == -1) {
                    // The step stands; the sample of it is not taken, so every history still
                    // has the same samples. What the failed function changed is given.
                    if (fish && !m.geometry_changed && !watch.stale(m)) take_energy(m);
                    res.reason = StopReason::Error;
                    res.message = failed;
                    break;
                }
                if (fish && !watch.stale(m)) watch.given(watch.kinetic(m) - ke_before);
                if (fish && !m.geometry_changed && !watch.stale(m)) take_energy(m);
            }
        }
        if (bad != -1) break;
        if (m.geometry_changed || watch.stale(m)) {
            // A FISH history changed the blocks: the checks below wait for the next step, which
            // prepares the model again first.
            if (progress && progress_every > 0 && res.steps % progress_every == 0) {
                catch_up_world_vertices(m);
                progress(m);
                lap = Clock::now();
            }
            continue;
        }
        {
            StageTimer t{prof, Stage::Checks, lap};
            res.message = runaway_after_step(watch, m);
        }
        if (!res.message.empty()) {
            res.reason = StopReason::BlowUp;
            break;
        }
        if (progress && progress_every > 0 && res.steps % progress_every == 0) {
            catch_up_world_vertices(m);
            progress(m);
            lap = Clock::now();
        }
        bool balanced = false;
        if (lim.ratio > 0) {
            StageTimer t{prof, Stage::Checks, lap};
            balanced = unbalanced_ratio(m) < lim.ratio;
            // With water in the joints, the flow must have settled too (flow.h).
            if (balanced && m.flow.on) balanced = flow_unbalance(m) < lim.ratio;
        }
        if (balanced) {
            res.reason = StopReason::Ratio;
            break;
        }
    }
    return res;
}

} // namespace odec
