// The energy account ('set energy on'): where the energy of a dynamic model comes from and
// where it goes, term by term, in joules, as the model cycles.
//
// Stored (states, read from the model whenever asked):
//   kinetic   translation and rotation of the free blocks and gridpoints, with their real masses
//   jstrain   the joints' springs: per sub-contact A (sn^2 / 2kn + |ss|^2 / 2ks), which is
//             A (kn un^2 / 2 + |ss|^2 / 2ks) for the closure un (dilation included); a joint in
//             tension, or a joined one pulled apart, stores it as well, an open one nothing
//   zstrain   the zones' elastic strain: per zone V (p^2 / 2K + s:s / 4G), p the mean stress and
//             s the deviator (the stress a zone holds, whatever put it there)
// Work done on the model since the account began (positive: energy put in):
//   gravity   by the weights of blocks and gridpoints: m g . their displacement
//   load      by the applied loads ('bound xload ...', 'bound stress'): F . displacement
//   velocity  by what drives the prescribed velocity components ('bound xvel', a moving 'fix'):
//             the reaction (minus the other forces on them) . displacement
// Dissipated since the account began (positive: energy taken out):
//   damping   by the damping forces (local, adaptive or mass-proportional)
//   slip      in the joints: the mean shear stress of a step times its plastic slip (friction,
//             net of the work dilation does against the normal stress), and what a joint's
//             springs held when it breaks in tension or opens under a shear stress
//   plastic   by the zones' plastic flow: the stress work of a yielding zone less the change
//             of its elastic strain energy
// And:
//   initial   stored energy when the account began
//   given     stored energy changed by commands between steps ('ini', 'insitu', 'change',
//             'delete', 'excavate', FISH ...): not a part of the cycle, so not an error
//   error     stored + dissipated - (initial + given + work): what the cycle made or lost on its
//             own. An explicit step is exact for free flight and for a joint spring that stays
//             closed; contacts that form or break within a step, new sub-contacts taking their
//             closure whole and areas changing at a geometry refresh give or take energy ("contact
//             kicks"), and show here.
//
// Time. The joints and zones hold the stresses of the last step's positions, one step behind
// the blocks' new positions. The account is kept at that time: the work terms are the
// trapezoidal rule over each step's displacement (the force before and after it), and the
// kinetic energy is m v- . v+ / 2 with the two half-step velocities around it, the form central
// differences conserve exactly for a linear spring and for gravity (it dips below zero by
// m a^2 dt^2 / 8 where a block turns back at rest).
//
// Cost and threads. Nothing is computed while the account is off. On, the integration and the
// joint and zone laws add each step's increments into sums per fixed chunk of blocks,
// gridpoints or zones, and per contact, added in a fixed order afterwards: the same bits with
// any number of threads.
//
// Masses. The account is meant for dynamic analysis ('config dyn', real masses). In static
// mode, and where 'mscale' raised masses, the integration moves blocks with masses that are
// not theirs: the kinetic energy (with the real masses) and the balance are not physical.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec {

struct Model;

struct EnergyAccount {
    bool on = false;
    long start_step = 0;       // the step the account began at
    double initial = 0;        // J, stored energy then
    double given = 0;          // J, changed by commands between steps since
    // Work and dissipation since the start, J: the sums of each step's forces times the half
    // displacements before and after it; pending_* is the part that belongs to the displacement
    // of the last step, which the stresses have not yet seen (reported values leave it out).
    double gravity = 0, load = 0, velocity = 0, damping = 0;
    double pending_gravity = 0, pending_load = 0, pending_velocity = 0, pending_damping = 0;
    double slip = 0;           // J, dissipated in the joints
    double plastic = 0;        // J, dissipated by zone plasticity
    double kinetic = 0;        // J, m v- . v+ / 2 at the last step (or when the account began)
    double peak = 0;           // J, the most energy the account has handled (for the relative error)
    // What the model's stored energy was, by state_energy(), when the cycle last left it: a
    // command that changes it between steps changes it by what is then given.
    double mark_kinetic = 0, mark_strain = 0;
    bool cycling = false;      // the cycle has the model (not saved: false between commands)
};

// Every term as reported now (energy.h), J.
struct EnergyReading {
    double kinetic = 0, jstrain = 0, zstrain = 0, gravity = 0, load = 0, velocity = 0, damping = 0, slip = 0,
           plastic = 0, initial = 0, given = 0;
    double stored() const { return kinetic + jstrain + zstrain; }
    double work() const { return gravity + load + velocity; }
    double dissipated() const { return damping + slip + plastic; }
    double error() const { return stored() + dissipated() - (initial + given + work()); }
};
EnergyReading energy_reading(const Model& m);

// The stored energies of the model now, J.
double joint_strain_energy(const Model& m);
double zone_strain_energy(const Model& m);
// Kinetic energy from the velocities stored (at t - dt/2; at t when just given), real masses,
// prescribed velocity components left out: the reading the account compares between steps.
double stored_kinetic_energy(const Model& m);

// 'set energy on': the account starts afresh from the model as it is.
void start_energy_account(Model& m);
// The cycle, when it has left the model (end of a run of steps, before a FISH function runs):
// remember the stored energy; and when it takes the model back: what changed is given.
void mark_energy(Model& m);
void take_energy(Model& m);

// A term of the account as reported (now), by name; false when there is no such term.
bool energy_term(const Model& m, const std::string& name, double& value);
// The names of the terms, in the order 'print energy' shows them, and a line saying what each is.
struct EnergyTermInfo {
    const char* name;
    const char* help;
};
const std::vector<EnergyTermInfo>& energy_terms();
bool is_energy_term(const std::string& name);
// What makes the account unphysical now (static mode, masses raised by mscale), or "".
std::string energy_caveat(const Model& m);

// ---- the hooks in the cycle's stages ----

// One step's increments, summed per chunk (integrate.cpp).
struct EnergyStep {
    double gravity = 0, load = 0, velocity = 0, damping = 0;
    double pending_gravity = 0, pending_load = 0, pending_velocity = 0, pending_damping = 0;
    double kinetic = 0;
    void add(const EnergyStep& o) {
        gravity += o.gravity; load += o.load; velocity += o.velocity; damping += o.damping;
        pending_gravity += o.pending_gravity; pending_load += o.pending_load;
        pending_velocity += o.pending_velocity; pending_damping += o.pending_damping;
        kinetic += o.kinetic;
    }
};

// One translational degree of freedom over a step: real mass, its weight and applied load
// (components), the total force f and the force the damping leaves fd, the velocity before
// (v0) and after (v1) the step, whether it is prescribed, and whether its velocity was given at t
// (the first kick is half a step: no displacement before t belongs to the step).
inline void energy_dof(EnergyStep& e, double mass, double weight, double load, double f, double fd, double v0,
                       double v1, bool held, bool half, double dt) {
    const double before = half ? 0.0 : v0;       // velocity over the displacement before t
    const double minus = half ? 2 * v0 - v1 : v0; // velocity half a step before t
    const double w = 0.5 * (before + v1) * dt, p = 0.5 * v1 * dt;
    e.gravity += weight * w;
    e.pending_gravity += weight * p;
    e.load += load * w;
    e.pending_load += load * p;
    if (held) {
        e.velocity -= f * w;
        e.pending_velocity -= f * p;
    } else {
        e.damping -= (fd - f) * w;
        e.pending_damping -= (fd - f) * p;
        e.kinetic += 0.5 * mass * minus * v1;
    }
}

// The rotation of a rigid block over a step: its real inertia (world axes), the moment m and the
// moment the damping leaves md, the moment of its applied loads (about the centroid), the spin
// before (w0) and after (w1).
void energy_rotation(EnergyStep& e, const Eigen::Matrix3d& inertia, const Eigen::Vector3d& m,
                     const Eigen::Vector3d& md, const Eigen::Vector3d& load_moment, const Eigen::Vector3d& w0,
                     const Eigen::Vector3d& w1, bool half, double dt);

// After the integration stage: the step's sums into the account.
void add_energy_step(Model& m, const EnergyStep& e);

} // namespace odec
