// The checks stage: run-aways told by speed, by sinking and by energy; the unbalanced force.
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/clump.h"
#include "engine/contact.h"
#include "engine/cable.h"
#include "engine/simd.h"
#include "engine/stages.h"

namespace odec {

// Kinetic energy of a free block, J (velocities at t - dt/2), leaving out the velocity
// components a boundary condition prescribes: those are imposed, not earned.
double kinetic_energy(const BlockSet& s, int b) {
    const Vec3 w = s.ang_vel[b];
    Vec3 v = s.vel[b];
    for (int i = 0; i < 3; ++i) {
        if (s.vel_bc[b] & (1 << i)) v[i] = 0;
    }
    // With the masses the integration uses: what the forces' work turns into (mass_scaling.h).
    const double mass = s.inertial_mass[b];
    double spin;
    if (s.inertial_moment[b] > 0) {
        spin = s.inertial_moment[b] * w.squaredNorm();
    } else {
        // In the body frame: w . (R I R^T w) = (R^T w) . I (R^T w).
        const Vec3 wb = s.orientation[b].conjugate() * w;
        spin = (real_inertia(mass, s.mass[b]) ? 1.0 : mass / s.mass[b]) * wb.dot(s.inertia_body[b] * wb);
    }
    return 0.5 * mass * v.squaredNorm() + 0.5 * spin;
}

ODEC_SIMD_CLONES
bool any_beyond(const double* x, int n, double limit) {
    using simd::M4;
    const simd::V4 lim = simd::splat(limit);
    M4 any = {0, 0, 0, 0};
    int i = 0;
    for (; i + 4 <= n; i += 4) any |= simd::load4(x + i) > lim;
    bool beyond = (any[0] | any[1] | any[2] | any[3]) != 0;
    for (; i < n; ++i) beyond = beyond || x[i] > limit;
    return beyond;
}

bool plain_for_energy(const BlockSet& s, int b) {
    for (int x = b; x < b + 4; ++x) {
        if ((s.flags[x] & (kExcavated | kFixed | kDeformable)) || !s.loads[x].empty() || s.vel_bc[x] ||
            !(s.mass[x] > 0) || s.inertial_moment[x] > 0) {
            return false;
        }
    }
    return true;
}

ODEC_SIMD_CLONES
bool plain_energies4(const BlockSet& s, int b, const Vec3& gravity, const Vec3* start, double e[4], double work[4]) {
    using simd::M4;
    using simd::V4;
    auto lanes = [&](auto&& get) ODEC_INLINE { return V4{get(b), get(b + 1), get(b + 2), get(b + 3)}; };
    V4 v[3], w[3], c[3], c0[3];
    simd::load_xyz4(s.vel[b].data(), v[0], v[1], v[2]);
    simd::load_xyz4(s.ang_vel[b].data(), w[0], w[1], w[2]);
    // Finite velocities only (else the work of no loads is not nothing: the block-by-block path).
    M4 finite = simd::finite4(v[0]);
    for (int i = 0; i < 3; ++i) finite &= simd::finite4(v[i]) & simd::finite4(w[i]);
    if (!(finite[0] & finite[1] & finite[2] & finite[3])) return false;
    simd::load_xyz4(s.centroid[b].data(), c[0], c[1], c[2]);
    simd::load_xyz4(start[b].data(), c0[0], c0[1], c0[2]);
    const simd::Quat4 q = simd::load_quats4(s.orientation[b].coeffs().data());
    const V4 qx = q.x, qy = q.y, qz = q.z, qw = q.w;
    const V4 mass = lanes([&](int x) { return s.inertial_mass[x]; });
    const V4 real_mass = lanes([&](int x) { return s.mass[x]; });
    const V4 zero = simd::splat(0.0), one = simd::splat(1.0), half = simd::splat(0.5);
    const M4 real = (mass == real_mass) & (mass > zero) & (mass < simd::splat(std::numeric_limits<double>::infinity()));
    // wb = q^-1 w (Eigen's rotation of a vector by the conjugate: v + w uv + vec x uv,
    // uv = 2 vec x v, vec = -(x, y, z)).
    const V4 ux = -qx, uy = -qy, uz = -qz;
    V4 uv0 = uy * w[2] - uz * w[1], uv1 = uz * w[0] - ux * w[2], uv2 = ux * w[1] - uy * w[0];
    uv0 = uv0 + uv0;
    uv1 = uv1 + uv1;
    uv2 = uv2 + uv2;
    const V4 wb[3] = {(w[0] + qw * uv0) + (uy * uv2 - uz * uv1), (w[1] + qw * uv1) + (uz * uv0 - ux * uv2),
                      (w[2] + qw * uv2) + (ux * uv1 - uy * uv0)};
    // wb . (I wb), the sums as Eigen adds them.
    V4 iw[3];
    for (int i = 0; i < 3; ++i) {
        const V4 r0 = lanes([&](int x) { return s.inertia_body[x](i, 0); });
        const V4 r1 = lanes([&](int x) { return s.inertia_body[x](i, 1); });
        const V4 r2 = lanes([&](int x) { return s.inertia_body[x](i, 2); });
        iw[i] = simd::sum3(r0 * wb[0], r1 * wb[1], r2 * wb[2]);
    }
    const V4 dot = simd::sum3(wb[0] * iw[0], wb[1] * iw[1], wb[2] * iw[2]);
    V4 ratio = one;
    if (!(real[0] & real[1] & real[2] & real[3])) ratio = real ? one : mass / real_mass;
    const V4 spin = ratio * dot;
    const V4 sq = simd::sum3(v[0] * v[0], v[1] * v[1], v[2] * v[2]);
    const V4 energy = half * mass * sq + half * spin;
    // (m g) . (c - start).
    const V4 g0 = real_mass * simd::splat(gravity[0]), g1 = real_mass * simd::splat(gravity[1]),
             g2 = real_mass * simd::splat(gravity[2]);
    const V4 wk = simd::sum3(g0 * (c[0] - c0[0]), g1 * (c[1] - c0[1]), g2 * (c[2] - c0[2]));
    for (int l = 0; l < 4; ++l) {
        e[l] = energy[l];
        work[l] = wk[l];
    }
    return true;
}

// The likely cause of a run-away of block b, for the message.
std::string runaway_cause(const Model& m, int b) {
    std::string cause = m.settings.dt_fixed > 0
                            ? "the forced timestep (set dt " + num_text(m.settings.dt_fixed) +
                                  ") is too large for the stiffnesses: try 'set dt auto'"
                            : "the timestep is too large for the stiffnesses";
    const double f = block_applied_force_bound(m, b);
    if (f > 0) {
        cause = "the load applied to block " + std::to_string(m.blocks.id[b]) + " ('bound ...load', up to " +
                num_text(f) + " N) is too large for what holds it, or " + cause;
    } else if (m.settings.dt_fixed <= 0) {
        cause += ", or a load is unbounded";
    }
    return cause;
}

// A contact that carries load but has a joint material without properties (one made while
// cycling takes 'set jmat', 1 by default, unless its faces lie on a joint plane with one): it
// would hold nothing, and its blocks would pass through each other.
static std::string unheld_contact(const Model& m) {
    const int c = contact_without_joint_properties(m, true);
    if (c < 0) return "";
    const ContactSet& cs = m.contacts;
    const BlockSet& s = m.blocks;
    const int jm = cs.jmat(c);
    return "contact " + std::to_string(cs.id[c]) + " between blocks " + std::to_string(s.id[cs.block_a[c]]) + " and " +
           std::to_string(s.id[cs.block_b[c]]) + " (step " + std::to_string(m.step) + ") has joint material " +
           std::to_string(jm) +
           ", which has no properties: it would hold nothing, and the blocks would pass through each other. "
           "Give them with 'prop jmat=" + std::to_string(jm) +
           " jkn ... jks ...', or choose the joint material of contacts made while cycling with 'set jmat n'";
}

std::string runaway_after_step(EnergyWatch& watch, const Model& m) {
    if (watch.unheld_revision != m.contacts.revision) {
        const std::string unheld = unheld_contact(m);
        if (!unheld.empty()) return unheld;
        watch.unheld_revision = m.contacts.revision;
    }
    double energy = 0, available = 0;
    int jumper = -1;
    const int runaway = watch.check(m, energy, available, jumper);
    if (jumper >= 0) {
        return "the motion of block " + std::to_string(m.blocks.id[jumper]) + " has run away (step " +
               std::to_string(m.step) + "): it moved " + num_text(m.blocks.vel[jumper].stableNorm() * m.dt) +
               " m in one step, more than half its size, passing through the blocks in its way "
               "unseen; likely cause: " + runaway_cause(m, jumper);
    }
    double depth = 0;
    const int deep = runaway < 0 ? watch.sunk(m, depth) : -1;
    if (deep >= 0) {
        const ContactSet& cs = m.contacts;
        const BlockSet& s = m.blocks;
        // The block that moves: the free one, or the lighter.
        int mover = cs.block_b[deep], other = cs.block_a[deep];
        if ((s.flags[mover] & kFixed) || (!(s.flags[other] & kFixed) && s.mass[other] < s.mass[mover])) {
            std::swap(mover, other);
        }
        const int jm = cs.jmat(deep);
        const bool has_jmat = jm > 0 && jm < static_cast<int>(m.joint_materials.size());
        return "the motion of block " + std::to_string(s.id[mover]) + " has run away (step " +
               std::to_string(m.step) + "): it has sunk " + num_text(depth) + " m into block " +
               std::to_string(s.id[other]) + ", more than half the smaller block's size; likely cause: " +
               (has_jmat ? "the joints (jmat " + std::to_string(jm) + ", jkn " +
                               num_text(m.joint_materials[jm].kn) + " Pa/m) are too soft for the load on them"
                         : std::string("the contact has no joint material to hold it")) +
               (m.settings.dt_fixed > 0 ? ", or the forced timestep is too large" : "");
    }
    if (runaway >= 0) {
        return "the motion of block " + std::to_string(m.blocks.id[runaway]) + " has run away (step " +
               std::to_string(m.step) + "): the kinetic energy, " + num_text(energy) +
               " J, is far beyond the " + num_text(available) +
               " J that the loads and the initial state could have given; likely cause: " +
               runaway_cause(m, runaway);
    }
    return "";
}

namespace {

// The part of an unbalanced force along the directions a boundary condition leaves free.
inline Vec3 free_part(Vec3 f, std::uint8_t held) {
    for (int i = 0; i < 3; ++i) {
        if (held & (1 << i)) f[i] = 0;
    }
    return f;
}

// The unbalanced force of the clump of pieces p[0..n) along its free directions, and the sum of
// the magnitudes of the forces on its pieces; false when a piece is fixed or excavated (the
// clump is held as a whole, as integrate_clumps holds it).
bool clump_unbalanced(const BlockSet& s, const int* p, int n, Vec3& force, double& scale) {
    Vec3 sum = Vec3::Zero();
    double sum_scale = 0;
    std::uint8_t held = 0;
    for (int i = 0; i < n; ++i) {
        const int b = p[i];
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) return false;
        sum += s.force[b];
        sum_scale += s.force_scale[b];
        held = static_cast<std::uint8_t>(held | s.vel_bc[b]);
    }
    force = free_part(sum, held);
    scale = sum_scale;
    return true;
}

// Each free rigid body's unbalanced force along its free directions, with the sum of the
// magnitudes of the forces on it: f(first block, force, scale). Blocks alone first, then the
// clumps as wholes.
template <class F>
void each_rigid_body(const Model& m, F&& f) {
    const BlockSet& s = m.blocks;
    bool clumps = false;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) continue;
        if (s.clump[b] != 0) {
            clumps = true;
            continue;
        }
        f(b, free_part(s.force[b], s.vel_bc[b]), s.force_scale[b]);
    }
    if (!clumps) return;
    thread_local ClumpList cl;
    list_clumps(s, cl);
    for (int c = 0; c < cl.size(); ++c) {
        const int* p = cl.pieces.data() + cl.offset[c];
        Vec3 force;
        double scale;
        if (clump_unbalanced(s, p, cl.offset[c + 1] - cl.offset[c], force, scale)) f(p[0], force, scale);
    }
}

} // namespace

bool rigid_body_unbalanced(const Model& m, int b, Vec3& force) {
    const BlockSet& s = m.blocks;
    if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) return false;
    if (s.clump[b] == 0) {
        force = free_part(s.force[b], s.vel_bc[b]);
        return true;
    }
    const std::vector<int> pieces = clump_pieces(s, b);
    if (pieces.empty() || pieces.front() != b) return false;
    double scale;
    return clump_unbalanced(s, pieces.data(), static_cast<int>(pieces.size()), force, scale);
}

double max_unbalanced_force(const Model& m) {
    double fmax = 0;
    each_rigid_body(m, [&](int, const Vec3& f, double) { fmax = std::max(fmax, f.norm()); });
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || g.vel_bc[i] == 7) continue;
        fmax = std::max(fmax, free_part(g.force[i], g.vel_bc[i]).norm());
    }
    return std::max(std::max(fmax, cable_max_unbalanced(m)), liner_max_unbalanced(m));
}

double unbalanced_ratio(const Model& m) {
    double unbal = 0, total = 0;
    each_rigid_body(m, [&](int, const Vec3& f, double scale) {
        unbal += f.norm();
        total += scale;
    });
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || g.vel_bc[i] == 7) continue;
        unbal += free_part(g.force[i], g.vel_bc[i]).norm();
        total += g.force_scale[i];
    }
    cable_unbalanced_sums(m, unbal, total);
    liner_unbalanced_sums(m, unbal, total);
    return total > 0 ? unbal / total : 0.0;
}

} // namespace odec
