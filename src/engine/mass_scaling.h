// Static and dynamic analysis: the masses the integration divides forces by.
//
// Gravity always acts on the real masses. What the equations of motion divide the unbalanced
// force by, the inertial mass, depends on the mode (Settings::dynamic):
//
// Dynamic mode (`config dyn`, then `set dyn on`): real masses and real time. The timestep is
// the stable one of the stiffest joint on the lightest block and of the stiffest zone. With
// `mscale dt` (partial density scaling), the few gridpoints and blocks that would need a
// smaller step than dt get just the mass that lets them take dt; everything else keeps its
// real mass, and the mass added is reported.
//
// Static mode (the default, and `set dyn off`): density scaling. An equilibrium does not
// depend on inertia, so every gridpoint and every rigid block gets the mass that makes the
// model's one timestep its own stable step: all converge at the pace of the best, none holds
// the others back. A gridpoint with stiffness k (the zones' bound on it and the joints that can
// press on it) gets m = k (dt / 1.8)^2, the mass with which its stable step 0.9 * 2 sqrt(m / k)
// is dt. A rigid block with joint stiffness kt = sum k_j A_j over its sub-contacts and
// kr = sum k_j A_j |x_j - c|^2 about its centroid gets m = s kt dt^2 and an isotropic
// inertia I = s kr dt^2, s = 1 / 0.9^2: each sub-contact spring at lever r adds at most
// k (1/m + r^2/I) to the block's highest frequency squared, twice over for the spring's other
// block, so omega^2 <= 2 (kt/m + kr/I) = 4 / (s dt^2) and omega dt <= 1.8 < 2. Neither goes
// below 1/16 of the real mass and inertia (larger is always stable): a block whose contact area
// shrinks to nothing as it slides off would otherwise be thrown by its own weight. Block masses
// follow the contacts every step; a block that touches nothing keeps its real mass (it falls
// as it would). When a mass grows, the velocity keeps the momentum; when it shrinks, the
// velocity is kept: kinetic energy never rises from the change (a velocity just given with
// 'ini' is kept as given).
// The timestep in static mode is the median of the gridpoints' own stable steps (so that no
// sliver zone sets the pace) and the blocks' automatic step; `set dt` may force any step.
// Model time then counts steps of that size but is not real time: velocities prescribed by
// 'bound' give displacements per step, and times reached are not physical.
#pragma once

#include <string>

namespace odec {

struct Model;

// Choose the timestep and the inertial masses before cycling, after the contacts and the zone
// surface are up to date. `rigid_dt` and `zone_dt` are the automatic steps of the blocks on
// their joints and of the zones, with real masses (0: none). Sets m.dt and m.mass_scaling;
// returns "" or why no timestep can be chosen.
std::string choose_timestep_and_masses(Model& m, double rigid_dt, double zone_dt);

// Static mode: the rigid blocks' inertial masses from their joints as they are now; every step
// from the stiffness the contact update summed (from_contact_update), else by walking the
// sub-contacts (before the first step).
void scale_block_masses(Model& m, bool from_contact_update);

// The factor of the velocity when an inertial mass goes from m0 to m1, so that the kinetic energy
// never rises from the change: the momentum is kept when it grows, the velocity when it shrinks
// (blocks, gridpoints, cable and liner nodes alike).
inline double velocity_factor(double m0, double m1) { return (m0 > 0 && m1 > m0) ? m0 / m1 : 1.0; }

} // namespace odec
