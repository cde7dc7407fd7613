// The explicit cycle.
//
// Each step runs named stages in a fixed order, each timed into Model::profile:
//   apply_loads      gravity and applied forces into each block's force
//   detect_contacts  new and lost contacts (only when blocks moved far enough)
//   zones            zone stresses -> gridpoint forces, with gravity and loads (zones.h)
//   update_contacts  relative motion -> joint stresses -> forces on both blocks (or on
//                    the gridpoints of deformable ones)
//   integrate        central differences: velocity at t+dt/2, position at t+dt, with the masses
//                    of the analysis' mode (mass_scaling.h)
//   record           histories every ncyc steps
//   checks           run-aways (speed, sinking, energy) and the unbalanced-force ratio
// Each stage lives in a file of its own (stages.h); this file orders and times them.
//
// Central differences store velocity half a step behind position. When a block's
// velocity is given at a time (creation, `ini xvel`, `reset vel`), its first kick is
// half a step, so that constant acceleration is integrated exactly:
//   z(n dt) = z0 + v0 n dt - g (n dt)^2 / 2   (free fall, round-off aside).
//
// Local damping (Cundall): each component of force and moment is reduced by
// alpha |f| in the direction opposing that component of velocity; alpha = 0.8 by default.
// A freely falling block under it accelerates at (1 - alpha) g.
#pragma once

#include <atomic>
#include <functional>
#include <string>

#include "engine/model.h"

namespace odec {

// Why cycling stopped.
enum class StopReason { Steps, Ratio, Time, Interrupted, BlowUp, Error };

struct CycleLimits {
    long max_steps = 0;       // > 0: stop after this many steps
    double max_time = 0;      // > 0: stop once this much model time has passed
    double ratio = 0;         // > 0: stop when the mean unbalanced-force ratio falls below it
    // Called at the start of every step (FISH 'whilestepping' functions); an empty string goes
    // on, anything else stops the cycle with that message (StopReason::Error).
    std::function<std::string(Model&)> each_step;
};

struct CycleResult {
    StopReason reason = StopReason::Steps;
    long steps = 0;           // steps taken in this call
    std::string message;      // for BlowUp and Error: what and where
};

// Called every `every` steps with the model, to print progress.
using ProgressFn = std::function<void(const Model&)>;

// Check that the model can cycle and choose the timestep. Returns an empty string
// when ready, else what is missing (a block with no mass, no timestep, ...).
std::string prepare_cycle(Model& m);

// The automatic timestep with real masses (what dynamic mode would take before any 'mscale'),
// s; 0 with the reason in *why when the model cannot cycle. Leaves the model as it was.
double real_mass_timestep(Model& m, std::string* why = nullptr);

// Cycle until a limit is reached, the interrupt flag is raised (checked between steps,
// so the model is always left consistent) or the numbers blow up.
CycleResult cycle(Model& m, const CycleLimits& limits, const std::atomic<bool>* interrupt = nullptr,
                  const ProgressFn& progress = nullptr, long progress_every = 0);

// The unbalanced force of a rigid body, along the directions no boundary condition holds: a
// block's own, or for a clump (clump.h) the sum over its pieces, given at its first piece (the
// forces between the pieces cancel; a piece alone is not integrated). False for a block that
// is fixed, excavated or deformable, and for a clump's other pieces.
bool rigid_body_unbalanced(const Model& m, int b, Eigen::Vector3d& force);
// Largest unbalanced force over the free rigid bodies (blocks and clumps) and gridpoints, N.
double max_unbalanced_force(const Model& m);
// Mean unbalanced-force ratio: sum |unbalanced| / sum of the magnitudes of all forces acting,
// over the free rigid bodies (blocks and clumps), gridpoints and structural nodes.
double unbalanced_ratio(const Model& m);

} // namespace odec
