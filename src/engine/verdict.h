// What the end of a `solve` says about the model: equilibrium, a mechanism still moving, or a
// run stopped by its limit while the model was still settling.
//
// During the run a SolveRecorder keeps a small rolling record: every `stride` steps a sample
// of the mean unbalanced-force ratio, the kinetic energy and the largest speed; every 8
// samples a snapshot of where each block is (a deformable block: the mean position of its
// gridpoints) and of the unbalanced force on it. When the record is full, every other entry is
// dropped and the stride doubles, so that it always spans the whole run in at most 256
// samples and 33 snapshots.
//
// At the end, judge_solve() looks at the last part of the run (the window: the last fifth of
// the steps, from the snapshot at or before that point):
// - the ratio's trend: a least-squares fit of log10(ratio) against the step;
// - each free block's motion: its net displacement over the first and the second half of the
//   window. A block moves as a mechanism when
//     it moved at least 1e-5 of its size over the window;
//     its rate over the second half is at least its rate over the first (steady or growing),
//     or at least 0.8 of it while the ratio does not fall (by 0.02 decade or more over the
//     window): a block slowing while the ratio falls is settling, not failing;
//     the two halves' displacements point the same way (within 60 degrees) and the second
//     half's rate is at least a quarter of its speed at the end: the displacement
//     accumulates, it is no oscillation about a place of rest;
//     the unbalanced force on it at the window's end is at least half what it was at its
//     start, and so is the sum over all the blocks that pass the tests above: a block
//     swinging back toward a place of rest (a slow sway of a whole wall) speeds up too, but
//     the force on it dies away as it nears that place.
//   Under local damping a block that fails speeds up (a fifth of its net force is left).
// A deformable block counts through its gridpoints: its speed is that of its fastest free
// gridpoint. Fixed, excavated and velocity-driven blocks are left out.
//
// Numbers only; the command layer words them.
#pragma once

#include <vector>

#include "engine/cycle.h"
#include "engine/model.h"

namespace odec {

// One sample of a run.
struct SolveSample {
    long step = 0;          // steps since the run began
    double time = 0;        // s, model time
    double ratio = 0;       // mean unbalanced-force ratio
    double kinetic = 0;     // J, of the free blocks and gridpoints
    double max_speed = 0;   // m/s, of the fastest free block (or gridpoint)
};

class SolveRecorder {
public:
    static constexpr int kSamples = 256;        // samples kept at most
    static constexpr int kSamplesPerSnapshot = 8;
    static constexpr long kFirstStride = 5;     // steps between samples at first

    // Start the record at the model as it is (the run's first snapshot).
    void begin(const Model& m);
    // Called every few steps during the run (every step number divisible by kFirstStride
    // at least); samples when the step falls on the stride.
    void observe(const Model& m);
    // The run has ended: the last sample, unless the last step was sampled.
    void finish(const Model& m);

    struct Snapshot {
        long step = 0;
        double time = 0;
        std::vector<Vec3> where;    // per block, m
        std::vector<double> force;  // per block, N: its unbalanced force (a deformable block:
                                    // the sum of the magnitudes of its gridpoints')
    };
    const std::vector<SolveSample>& samples() const { return samples_; }
    const std::vector<Snapshot>& snapshots() const { return snapshots_; }
    long first_step() const { return first_step_; }
    long stride() const { return stride_; }

private:
    SolveSample sample(const Model& m, long rel) const;
    // A run whose blocks change (a FISH function that cuts or deletes blocks) starts its record
    // again from there: the earlier snapshots speak of other blocks.
    void restart(const Model& m);
    bool same_blocks(const Model& m) const;

    long first_step_ = 0;
    long stride_ = kFirstStride;
    int n_blocks_ = 0, n_gridpoints_ = 0;
    std::vector<SolveSample> samples_;
    std::vector<Snapshot> snapshots_;
};

// How a solve ended.
enum class SolveOutcome {
    Equilibrium,  // the ratio limit was reached
    Mechanism,    // stopped by a limit with blocks still moving at a steady or growing rate
    NotConverged, // stopped by a limit while still settling (or too soon to tell)
    Interrupted,  // Ctrl-C
};

// Its name: equilibrium, mechanism, not converged, interrupted (FISH's solve_verdict).
const char* outcome_name(SolveOutcome o);

// A block that moves as a mechanism.
struct MovingBlock {
    int id = 0;          // block id
    double speed = 0;    // m/s at the end
    double moved = 0;    // m, net displacement over the window
    double growth = 1;   // rate of the window's second half over its first (> 1: speeding up)
};

struct SolveVerdict {
    SolveOutcome outcome = SolveOutcome::NotConverged;
    StopReason stop = StopReason::Steps;
    // The criteria the run was given (0: none).
    double ratio_limit = 0;
    long step_limit = 0;
    double time_limit = 0;
    // The run.
    long end_step = 0;       // the model's step at the end
    long steps = 0;          // steps the run took
    double ratio = 0;        // at the end
    // The trend over the window (trend_known: enough samples in it to fit one).
    bool trend_known = false;
    long window_steps = 0;
    double ratio_from = 0, ratio_to = 0; // the fit at the window's start and end
    double decades_per_step = 0;         // slope of log10(ratio); < 0 falling
    long steps_to_limit = -1;            // at that rate, steps more to the ratio limit (-1: never / no limit)
    double speed_from = 0, speed_to = 0; // m/s, largest speed at the window's start and end
    double kinetic_from = 0, kinetic_to = 0; // J
    // Mechanism: the blocks moving, by id, and the fastest speed among them.
    std::vector<MovingBlock> moving;
    double moving_speed = 0;   // m/s
    double moving_growth = 1;  // of the blocks together (> 1: speeding up)
};

// The verdict of a run recorded by `rec`, ended for `reason`, on the model as it is at the end.
SolveVerdict judge_solve(const SolveRecorder& rec, const Model& m, StopReason reason, const CycleLimits& lim,
                         long steps);

// The speed of each block (m/s; a deformable block: its fastest free gridpoint), and whether
// it is free to move (not fixed, excavated or velocity-driven; a deformable block with at
// least one free gridpoint).
void block_speeds(const Model& m, std::vector<double>& speed, std::vector<char>& free);

} // namespace odec
