// The stages of the explicit cycle, each in a file of its own; cycle.cpp only orders and
// times them (Model::profile, shown by 'print info'):
//   loads      stage_loads.cpp     weights and applied loads into each block's force
//   detection  contact_detect.cpp  new and lost contacts (when blocks moved far enough)
//   zones      zones.cpp           zone stresses -> gridpoint forces, with gravity and loads
//   contacts   joint_law.cpp       relative motion -> joint stresses -> forces on both sides
//   integrate  integrate.cpp       blocks, clumps (clump.cpp) and gridpoints under one damping law
//   checks     checks.cpp          run-aways (energy, jumps, sinking) and the stop criteria
//   record     history.cpp         histories every ncyc steps
// Before the first step (and whenever the blocks change), prepare.cpp checks that the model can
// cycle and chooses the timestep and the masses (mass_scaling.h).
//   flow       flow.cpp            joint fluid flow: pore pressures and their forces on the blocks
// Structural elements other than cables and the 2D engine are to join as stages of their own.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "engine/model.h"
#include "engine/parallel.h"

namespace odec {

inline double sign(double x) { return (x > 0) - (x < 0); }

inline std::string num_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

// Damped force component f acting on a degree of freedom of this mass moving at v (the damping
// law of cycle.h).
inline double damped_force(const Damping& d, double f, double v, double mass, double dt) {
    switch (d.mode) {
    case DampingMode::Local: return f - d.local * std::abs(f) * sign(v);
    case DampingMode::Auto: return f - d.auto_coefficient * mass * v;
    case DampingMode::Rayleigh: {
        // Mass-proportional part of Rayleigh damping: c = 2 xi omega m.
        const double c = 2.0 * d.rayleigh_fraction * 2.0 * M_PI * d.rayleigh_frequency * mass;
        return f - c * v;
    }
    case DampingMode::Off: break;
    }
    (void)dt;
    return f;
}

// A turn by the angle |theta| about theta as a unit quaternion (cos h, sin h theta / |theta|),
// h = |theta| / 2, from theta's squared length t2 (> 0): gives cos h and sin h / |theta|. Below
// 2e-3 rad from their series, within the last bit of a double (the first term left out is
// below 1e-21 of the sum), with no root, division or library function.
inline void half_turn(double t2, double& sin_h_over_angle, double& cos_h) {
    const double h2 = 0.25 * t2;
    if (h2 < 1e-6) {
        // (Multiplied by the constants' reciprocals: the terms they scale are below 1e-6 of the
        // sum, so a last bit of theirs changes the sum by its last bit at most.)
        constexpr double kSixth = 1.0 / 6, kTwelfth = 1.0 / 12, kTwentieth = 1.0 / 20;
        sin_h_over_angle = 0.5 * (1 - h2 * kSixth * (1 - h2 * kTwentieth));
        cos_h = 1 - h2 * 0.5 * (1 - h2 * kTwelfth);
    } else {
        const double angle = std::sqrt(t2);
        sin_h_over_angle = std::sin(0.5 * angle) / angle;
        cos_h = std::cos(0.5 * angle);
    }
}

inline bool is_active(const BlockSet& s, int b) { return !(s.flags[b] & kExcavated); }

// Whether a block's inertial mass is its real mass (as in dynamic mode): then their ratio is 1
// exactly, which nothing need divide by (x / x is 1 for every finite x but 0).
inline bool real_inertia(double inertial_mass, double mass) {
    return inertial_mass == mass && mass > 0 && mass < std::numeric_limits<double>::infinity();
}
// A rigid block that moves as a whole (not excavated, not divided into zones).
inline bool is_rigid_active(const BlockSet& s, int b) { return !(s.flags[b] & (kExcavated | kDeformable)); }

// loads: each block's force starts as its weight plus its applied loads, its moment as the
// applied loads' moment about its centroid.
void apply_loads(Model& m);
// The applied loads ('bound') on rigid block b at time t, with the block's orientation now:
// their force, N, and their moment about the centroid, N m (world axes).
void block_applied_load(const Model& m, int b, double t, Vec3& force, Vec3& moment);
// The largest force the applied loads on block b reach (each table at its largest |y|), N.
double block_applied_force_bound(const Model& m, int b);

// integrate: velocities at t + dt/2 and positions at t + dt of the free blocks and gridpoints,
// forces damped by the model's damping law; adds to adaptive damping's sums when given.
// Returns the index of a block whose motion became non-finite, or -1.
int integrate(Model& m, double dt, AutoDampingSums* sums);
// For tests and benchmarks: whether integration steps the plain rigid blocks four at a time
// (on unless told; the same bits either way).
void set_batched_blocks(bool on);
bool batched_blocks();

// Adaptive damping's coefficient for the next step, from the sums of every free degree of
// freedom of this one (blocks, gridpoints, cable and liner nodes), kept for the next (integrate.cpp).
void adjust_auto_damping(Damping& d, const AutoDampingSums& sums, double dt);

// Gridpoints only (part of integrate): returns the index of a gridpoint whose motion became
// non-finite, or -1; adds to adaptive damping's sums when given, and the step's energy
// increments when given (energy.h).
int integrate_gridpoints(Model& m, const Damping& d, double dt, AutoDampingSums* sums, EnergyStep* energy = nullptr);

// prepare (prepare.cpp): what preparing a cycle changes, kept so that a cycle refused before its
// first step leaves the model exactly as it was; and the preparation itself ("" or why not).
// What preparing a cycle changes (contact detection and the timestep), kept so that a
// cycle refused before its first step leaves the model exactly as it was.
struct PrepareUndo {
    bool saved = false;
    ContactSet contacts;
    std::vector<int> vertex_offset;
    std::vector<Vec3> world_vertices;
    double dt = 0;
    bool geometry_changed = false;
    // Choosing the inertial masses may slow velocities down (mass_scaling.h).
    std::vector<double> block_mass, block_moment, gp_mass;
    std::vector<Vec3> vel, ang_vel, gp_vel;
    MassScalingReport report;
    CableSet cables; // their ties to the rock and their masses
    LinerSet liners;

    explicit PrepareUndo(const Model& m)
        : dt(m.dt), geometry_changed(m.geometry_changed), block_mass(m.blocks.inertial_mass),
          block_moment(m.blocks.inertial_moment), gp_mass(m.gridpoints.inertial_mass), vel(m.blocks.vel),
          ang_vel(m.blocks.ang_vel), gp_vel(m.gridpoints.vel), report(m.mass_scaling), cables(m.cables), liners(m.liners) {
        if (m.geometry_changed) {
            saved = true;
            contacts = m.contacts;
            vertex_offset = m.blocks.vertex_offset;
            world_vertices = m.blocks.world_vertices;
        }
    }
    void undo(Model& m) {
        if (saved) {
            m.contacts = std::move(contacts);
            m.blocks.vertex_offset = std::move(vertex_offset);
            m.blocks.world_vertices = std::move(world_vertices);
        }
        m.dt = dt;
        m.geometry_changed = geometry_changed;
        if (block_mass.size() == m.blocks.inertial_mass.size() && gp_mass.size() == m.gridpoints.inertial_mass.size()) {
            m.blocks.inertial_mass = std::move(block_mass);
            m.blocks.inertial_moment = std::move(block_moment);
            m.blocks.vel = std::move(vel);
            m.blocks.ang_vel = std::move(ang_vel);
            m.gridpoints.inertial_mass = std::move(gp_mass);
            m.gridpoints.vel = std::move(gp_vel);
        }
        m.mass_scaling = report;
        m.cables = std::move(cables);
        m.liners = std::move(liners);
    }
};
std::string prepare_cycle_once(Model& m);

// checks (checks.cpp).
double kinetic_energy(const BlockSet& s, int b);
// The likely cause of a run-away of block b, for the message.
std::string runaway_cause(const Model& m, int b);
// A run-away told by the physics rather than by a speed: with damping at most taking energy
// out, the kinetic energy of the free blocks can never exceed what the model had when the
// cycling began (kinetic energy and the strain energy stored in the joints) plus the work
// the loads have done since (gravity on the free blocks: its force times the displacement,
// exact as it is constant; the applied loads, which may follow a table and turn with the
// block: their force and moment times each step's displacement and rotation, summed) plus
// the work the velocity boundaries can have done (bounded by |force . velocity| dt summed).
// A numerical instability pumps energy in from nowhere, growing it geometrically, so a
// generous margin still stops it within a few steps of its start, long before numbers
// overflow.
// Whether blocks b .. b + 3 are all plain for the energy watch (EnergyWatch::check): active, free
// and rigid, without applied loads or held velocities, with their real inertia tensor and a mass.
bool plain_for_energy(const BlockSet& s, int b);
// Whether any of x[0, n) is beyond (greater than) limit (NaN is not), four at a time.
bool any_beyond(const double* x, int n, double limit);
// Their kinetic energies (kinetic_energy's bits) and the work of their weights since `start`
// ((m g) . (c - start), as check() makes it), four at a time; false (and nothing made) where a
// velocity is not finite (then the work of no loads is not nothing: the block-by-block path).
bool plain_energies4(const BlockSet& s, int b, const Vec3& gravity, const Vec3* start, double e[4], double work[4]);

struct EnergyWatch {
    std::vector<Vec3> start;   // (n_blocks) centroid when the cycling began
    std::vector<double> size;  // (n_blocks) m, largest vertex distance from the centroid
    double least_half_size = 0; // m, half the least of size
    bool neighbours = false;   // more than one block: there is something to pass through
    double initial = 0;        // J, kinetic + joint strain energy then
    double boundary_work = 0;  // J, bound on the work of prescribed velocities since
    double applied_work = 0;   // J, the work of the applied loads since
    double peak_work = 0;      // J, the most work gravity and the applied loads have done
    double floor = 0;          // J, noise level below which nothing is judged
    // The contacts' revision (ContactSet::revision) last found without a loaded contact that
    // has no joint properties: looked for again only once the contacts or (by FISH during the
    // cycle, forget_contacts) the joint materials may have changed.
    long unheld_revision = -1;
    void forget_contacts() { unheld_revision = -1; }
    static constexpr double kMargin = 4.0;

    // Kinetic energy of the free blocks, J.
    double kinetic(const Model& m) const {
        const BlockSet& s = m.blocks;
        double e = 0;
        for (int b = 0; b < s.size(); ++b) {
            if ((s.flags[b] & (kExcavated | kFixed)) || !(s.mass[b] > 0)) continue;
            e += kinetic_energy(s, b);
        }
        return e;
    }
    // Energy given to the blocks from outside the cycle (by FISH between steps).
    void given(double energy) {
        if (energy > 0 && std::isfinite(energy)) initial += energy;
    }
    // Whether the blocks changed in number since begin(): the arrays no longer match.
    bool stale(const Model& m) const { return start.size() != static_cast<size_t>(m.blocks.size()); }

    void begin(const Model& m) {
        const BlockSet& s = m.blocks;
        unheld_revision = -1;
        start = s.centroid;
        size.assign(s.size(), 0.0);
        int active = 0;
        for (int b = 0; b < s.size(); ++b) {
            for (const Vec3& v : s.shape[b].vertices) size[b] = std::max(size[b], v.norm());
            if (!(s.flags[b] & kExcavated)) ++active;
        }
        least_half_size = size.empty() ? 0.0 : 0.5 * *std::min_element(size.begin(), size.end());
        neighbours = active > 1;
        initial = 0;
        double mass = 0;
        for (int b = 0; b < s.size(); ++b) {
            if ((s.flags[b] & (kExcavated | kFixed)) || !(s.mass[b] > 0)) continue;
            initial += kinetic_energy(s, b);
            mass += s.inertial_mass[b];
        }
        const ContactSet& cs = m.contacts;
        for (int c = 0; c < cs.size(); ++c) {
            const JointMaterial* jp = contact_joint_material(m, c);
            if (!jp) continue;
            const JointMaterial& j = *jp;
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                const double u = sub_closure(m, c, k) + cs.sub_dilation(k);
                double un = u > 0 ? u : (cs.joined(c) ? -u : std::min(-u, j.kn > 0 ? j.tension / j.kn : 0.0));
                if (!(un >= 0)) un = 0;
                double e = 0.5 * j.kn * un * un;
                if (j.ks > 0) e += 0.5 * cs.sub_ss[k].squaredNorm() / j.ks;
                initial += cs.sub_area[k] * e;
            }
        }
        // The elastic energy of the cables (a pretension) may be given to the blocks.
        initial += cable_strain_energy(m);
        initial += liner_strain_energy(m);
        boundary_work = 0;
        applied_work = 0;
        peak_work = 0;
        // A millimetre per second over all the free mass: below it, nothing is judged.
        floor = 0.5 * mass * 1e-6;
    }

    // After a step: the block whose motion ran away, or -1. `energy` and `available`
    // receive the totals.
    // The contact whose closure has gone deeper than half the smaller of its two blocks (one
    // block is passing through the other), or -1; `depth` receives that closure.
    int sunk(const Model& m, double& depth) const {
        const ContactSet& cs = m.contacts;
        const int nc = cs.size();
        // First one flat pass over the closures: none beyond half the smallest block's size (as
        // at almost every step), none is sunk.
        bool beyond = false;
        const double* un = cs.sub_un.data();
        beyond = any_beyond(un, cs.n_subs(), least_half_size);
        if (!beyond) return -1;
        auto deep = [&](int c) {
            const double limit = 0.5 * std::min(size[cs.block_a[c]], size[cs.block_b[c]]);
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                // (One held by reference, its closure now.)
                if (cs.sub_un[k] > limit && sub_closure(m, c, k) > limit) return k;
            }
            return -1;
        };
        // The first such contact, looked for on the threads.
        const int c = parallel_first(nc, 4096, thread_count(), nc >= kParallelMinItems, [&](int i) { return deep(i) >= 0; });
        if (c < 0) return -1;
        depth = sub_closure(m, c, deep(c));
        return c;
    }

    // What check() sums over one chunk of blocks.
    struct Part {
        double boundary = 0, applied = 0, work = 0, ke = 0, ke_max = -1;
        int worst = -1, jumper = -1;
    };
    std::vector<Part> parts;   // (chunks of blocks) buffer of check()

    int check(const Model& m, double& energy, double& available, int& jumper) {
        jumper = -1;
        const BlockSet& s = m.blocks;
        // The blocks in fixed chunks, on the threads; the chunks' sums added in order, so
        // that the totals do not depend on the threads.
        constexpr int kChunk = 512;
        const int n = s.size();
        const int nch = (n + kChunk - 1) / kChunk;
        parts.assign(nch, Part{});
        // What a free block adds to its chunk's part: whether it jumps, its kinetic energy e and
        // the work w of its weight.
        auto take = [&](Part& p, int b, double e, double w) {
            // Moving more than half its size in one step, a block jumps past the blocks in
            // its way: contact detection cannot see them.
            // (Its largest component first, which neither overflows nor underflows; then the
            // squared length, cheaper than a scaled norm. NaN compares as not larger.)
            if (p.jumper < 0 && neighbours) {
                const Vec3 d = s.vel[b] * m.dt;
                const double half = 0.5 * size[b];
                if (d.cwiseAbs().maxCoeff() > half || d.squaredNorm() > half * half) p.jumper = b;
            }
            p.ke += e;
            if (!(e <= p.ke_max)) {
                p.ke_max = e;
                p.worst = b;
            }
            p.work += w;
        };
        parallel_for(nch, thread_count(), n >= kParallelMinBlocks, [&](int ch) {
            Part& p = parts[ch];
            const int b1 = std::min(n, (ch + 1) * kChunk);
            for (int b = ch * kChunk; b < b1; ++b) {
                // Four plain blocks in a row (free, without loads or held velocities, with their
                // real inertia tensor and finite velocities; no flow): their kinetic energies and
                // the work of their weights made four at a time, then taken in order.
                double e4[4], work4[4];
                if (!m.flow.on && b + 4 <= b1 && plain_for_energy(s, b) && plain_energies4(s, b, m.gravity, start.data(), e4, work4)) {
                    for (int l = 0; l < 4; ++l) take(p, b + l, e4[l], work4[l]);
                    b += 3;
                    continue;
                }
                if (s.flags[b] & kExcavated) continue;
                // The applied loads of the step just taken (at its start time).
                Vec3 applied = Vec3::Zero(), applied_moment = Vec3::Zero();
                if (!s.loads[b].empty()) block_applied_load(m, b, m.time - m.dt, applied, applied_moment);
                if (s.vel_bc[b]) {
                    const Vec3 load = s.mass[b] * m.gravity + applied;
                    p.boundary += m.dt * (std::abs(s.force[b].dot(s.vel[b])) + std::abs(load.dot(s.vel[b])));
                }
                if ((s.flags[b] & kFixed) || !(s.mass[b] > 0)) continue;
                p.applied += m.dt * (applied.dot(s.vel[b]) + applied_moment.dot(s.ang_vel[b]));
                // The pore pressure in the joints works on the blocks as a load does (flow.h).
                if (m.flow.on && static_cast<int>(m.flow.block_force.size()) == s.size()) {
                    p.applied += m.dt * (m.flow.block_force[b].dot(s.vel[b]) + m.flow.block_moment[b].dot(s.ang_vel[b]));
                }
                take(p, b, kinetic_energy(s, b), (s.mass[b] * m.gravity).dot(s.centroid[b] - start[b]));
            }
        });
        double work = 0, ke = 0, ke_max = -1;
        int worst = -1;
        for (const Part& p : parts) {
            boundary_work += p.boundary;
            applied_work += p.applied;
            work += p.work;
            ke += p.ke;
            if (jumper < 0) jumper = p.jumper;
            if (p.worst >= 0 && !(p.ke_max <= ke_max)) {
                ke_max = p.ke_max;
                worst = p.worst;
            }
        }
        work += applied_work;
        // Cable nodes driven at a velocity work on the cables and, through them, the rock.
        const CableSet& cbl = m.cables;
        for (int i = 0; i < cbl.n_nodes(); ++i) {
            if (cbl.vel_bc[i]) boundary_work += m.dt * std::abs(cbl.force[i].dot(cbl.vel_bc_value[i]));
        }
        energy = ke;
        // The most work the loads have done at any time: the energy they put in may have been
        // carried back up since (an undamped block bouncing), and explicit impacts do not
        // conserve energy exactly, so the budget is the largest the exchange has been.
        peak_work = std::max(peak_work, work);
        available = initial + peak_work + boundary_work;
        if (std::isfinite(ke) && ke <= kMargin * available + floor && jumper < 0) return -1;
        return worst;
    }
};
// After a step: the run-away verdict (a message) or "".
std::string runaway_after_step(EnergyWatch& watch, const Model& m);

} // namespace odec
