// The joint law at sub-contacts, the forces it puts on the blocks, and the timestep.
//
// Each step, every sub-contact reads the motion of the two blocks at its point: the
// relative velocity of block b with respect to block a there, times dt, is this step's
// displacement increment (the block velocities are the half-step ones that moved the
// blocks from t - dt to t). Along the contact normal it closes or opens the joint; across
// it, it shears. Stresses follow (Pa, stiffnesses in Pa/m):
//   normal   sn = kn (un + udil)            total form, so a standing contact cannot drift
//   shear    ss <- ss - ks dus              incremental, as the slip history demands
//   Coulomb  |ss| <= c + sn tan(phi)        beyond it the joint slips at the limit
//   tension  sn >= -T                       beyond it the joint opens: sn = ss = 0
// A sub-contact that slips or opens past its strength has failed: its cohesion and
// tensile strength are gone for good, and under joint model 2 its friction drops to the
// residual angle. While slipping, the joint dilates by |dus| tan(dilation) while the shear
// displacement is below zdilation (0: no limit), pushing the blocks apart or, if they are
// held, raising the normal stress. As in the classical Coulomb slip joint, the dilation
// follows the direction of shearing: it grows while the increment points the way of the total
// shear displacement us (riding up the asperities) and shrinks, never below zero, while it
// points back (riding down them). A joined (glued) contact has no strength limits at all.
//
// Each sub-contact carries (sn n + ss) times its area. The force acts at the sub-contact
// point on block b, and its opposite on block a, each with its moment about the block
// centroid.
//
// The timestep. A rigid block of mass m on a joint spring of stiffness k (stress per unit
// closure times area) oscillates at omega = sqrt(k/m); central differences are stable for
// dt < 2/omega = 2 sqrt(m/k). The model takes the worst pair, the lightest free block
// against the stiffest contact, and a safety fraction dtfrac (0.1 by default, because a
// block has several contacts and rotational modes):
//   dt = dtfrac * 2 sqrt(m_min / k_max),   k_max = max over contacts of max(kn, ks) * area.
// Before any contact exists (blocks placed apart), k_max is estimated from the stiffest
// defined joint material times the largest face of any block: the stiffest contact that
// could form, so the step stays stable when the first contacts close.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "engine/blocks.h"
#include "engine/clump.h"
#include "engine/contact.h"
#include "engine/contact_axes.h"
#include "engine/parallel.h"
#include "engine/model.h"
#include "engine/stages.h"

namespace odec {

namespace {

using Vec2 = Eigen::Vector2d;

struct LawParams {
    double kn = 0, ks = 0, tan_phi = 0, coh = 0, ten = 0, tan_dil = 0, zdil = 0, tan_res = 0;
    bool model2 = false;
};

LawParams law_params(const Model& m, int jmat, int jcons) {
    LawParams p;
    if (jmat <= 0 || jmat >= static_cast<int>(m.joint_materials.size())) return p;
    const JointMaterial& j = m.joint_materials[jmat];
    if (!j.defined) return p;
    const double deg = M_PI / 180.0;
    p.kn = j.kn;
    p.ks = j.ks;
    p.tan_phi = std::tan(j.friction * deg);
    p.coh = j.cohesion;
    p.ten = j.tension;
    p.tan_dil = std::tan(j.dilation * deg);
    p.zdil = j.zdilation;
    p.model2 = jcons == 2;
    p.tan_res = p.model2 ? std::tan(j.res_friction * deg) : p.tan_phi;
    return p;
}

// The force a sub-contact's step puts on block b, on the contact's axes: its normal part and
// its parts along the shear axes e1, e2. (Plain numbers, which stay in registers in the contact
// update's loop.)
struct AxesForce {
    double n, s1, s2;
};

// One step of the joint law at sub-contact k, for the displacement increment du of block b
// relative to block a there. Returns the force on b (a takes its opposite). With the energy
// account on (dissipated not null), adds what the step dissipates there (energy.h): while it
// slips, the mean shear stress of the step times the plastic slip, less the work of dilation
// against the normal stress; when it opens, what the shear spring held beyond the shear work of
// the step, and what the normal spring held in tension if that breaks it.
// The increment is given on the contact's axes (n, e1, e2): dun along the normal, dus1 and dus2
// along the shear axes; so is the force returned.
// An open sub-contact between rigid blocks keeps its closure by reference (contact.h,
// sub_closure): for one, open_shift is how far its blocks have moved towards each other at its
// point since their geometry references (null for a deformable block's). Returns, in
// *to_reference, whether sub_un now holds the closure of a sub-contact that has just opened (or
// was made open by a refresh), which the caller gives by reference.
[[gnu::always_inline]] inline AxesForce joint_step_on_axes(ContactSet& cs, int k, const LawParams& p, bool joined, double dun,
                                                           double dus1_step, double dus2_step, double* dissipated,
                                                           const double* open_shift, bool* to_reference) {
    std::uint8_t flags = cs.sub_flags(k);
    // The normal stress before the step (for the energy account alone), as its last step left it.
    const double dil = cs.sub_dilation(k);
    const double un_prev = cs.sub_un[k];
    const double sn_old = !dissipated || (flags & (kSubOpen | kSubNew | kSubFresh))
                              ? 0.0
                              : p.kn * (joined ? un_prev : un_prev + dil);
    const double un_old = un_prev + dil; // (where sn_old is not 0)
    const bool was_open = held_open(flags);
    const bool by_reference = open_shift && was_open;
    // Its closure now. A new or fresh one's was measured from the geometry at t: the step is
    // already in it. A fresh one's shear, taken over from the sub-contact before, takes the
    // step; a new one takes none this step.
    const double un = (flags & (kSubNew | kSubFresh)) ? un_prev : by_reference ? un_prev - *open_shift : un_prev - dun;
    const bool shears = !(flags & kSubNew);
    const double dus1 = shears ? dus1_step : 0.0, dus2 = shears ? dus2_step : 0.0; // on e1, e2 (ContactSet::sub_us)
    flags &= shears ? ~kSubFresh : ~kSubNew;
    flags &= ~(kSubSlip | kSubOpen);
    double sn;
    const Vec2 ss_old = cs.sub_ss[k];
    double ss1 = ss_old[0] - p.ks * dus1, ss2 = ss_old[1] - p.ks * dus2;
    bool open = false;
    if (joined) {
        sn = p.kn * un;
    } else {
        const bool failed = flags & kSubFailed;
        double coh = failed ? 0.0 : p.coh;
        const double ten = failed ? 0.0 : p.ten;
        double tan_phi = failed ? p.tan_res : p.tan_phi;
        sn = p.kn * (un + dil);
        if (sn < -ten || (sn <= 0 && ten <= 0)) {
            open = true;
            if (dissipated && p.ks > 0) {
                // Never below zero: where the step's own shear work is more than the spring held
                // (a trial that reverses within the step), the difference is the step's error.
                *dissipated += std::max(0.0, cs.sub_area[k] * 0.5 * (ss_old[0] * ss1 + ss_old[1] * ss2) / p.ks);
            }
            if (dissipated && sn < -ten && ten > 0 && p.kn > 0) {
                // Broken in tension: the normal work of the step less the change of what the
                // spring held (all of it).
                *dissipated += cs.sub_area[k] * (0.5 * sn_old * (un + dil - un_old) + 0.5 * sn_old * sn_old / p.kn);
            }
            // Open: past its tensile strength, which (if any) is lost with cohesion.
            if (sn < -ten && (coh > 0 || ten > 0)) flags |= kSubFailed;
            sn = 0;
            ss1 = 0;
            ss2 = 0;
            flags |= kSubOpen;
        } else {
            double tmax = std::max(0.0, coh + sn * tan_phi);
            // The root only where it slips (most sub-contacts stick).
            const double t2 = ss1 * ss1 + ss2 * ss2;
            if (t2 > tmax * tmax) {
                const double t = std::sqrt(t2);
                if (!failed && (coh > 0 || ten > 0 || p.model2)) {
                    flags |= kSubFailed;
                    coh = 0;
                    tan_phi = p.tan_res;
                    tmax = std::max(0.0, sn * tan_phi);
                }
                const double trial1 = ss1, trial2 = ss2;
                const double back = tmax / t;
                ss1 *= back;
                ss2 *= back;
                flags |= kSubSlip;
                if (dissipated && p.ks > 0) {
                    *dissipated += std::max(0.0, cs.sub_area[k] * 0.5 *
                                                     ((ss_old[0] + ss1) * (trial1 - ss1) + (ss_old[1] + ss2) * (trial2 - ss2)) /
                                                     p.ks);
                }
                const Vec2 us = cs.sub_us[k] + Vec2(dus1, dus2);
                if (p.tan_dil != 0 && (p.zdil <= 0 || us.norm() < p.zdil)) {
                    const double rise = std::sqrt(dus1 * dus1 + dus2 * dus2) * p.tan_dil;
                    const double d = us[0] * dus1 + us[1] * dus2 >= 0 ? rise : -std::min(rise, dil);
                    cs.sub_udil[k] += d;
                    if (dissipated) *dissipated -= cs.sub_area[k] * sn * d;
                }
            }
        }
    }
    // Open by reference and still open, its closure stays as it is; open and still open, its
    // shear displacement does too (the shear's increment is summed only while the joint touches).
    if (!(by_reference && open)) cs.sub_un[k] = un;
    if (!(was_open && open)) {
        Vec2& us = cs.sub_us[k];
        us[0] += dus1;
        us[1] += dus2;
    }
    *to_reference = open && !by_reference;
    Vec2& ss = cs.sub_ss[k];
    ss[0] = ss1;
    ss[1] = ss2;
    cs.set_sub_flags(k, flags);
    const double area = cs.sub_area[k];
    return AxesForce{area * sn, area * ss1, area * ss2};
}

// The same for the increment du and force as vectors (world axes).
[[gnu::always_inline]] inline Vec3 joint_step(ContactSet& cs, int k, const LawParams& p, bool joined, const Vec3& nrm,
                                              const Vec3& e1, const Vec3& e2, const Vec3& du, double* dissipated = nullptr) {
    bool to_reference;
    const AxesForce f = joint_step_on_axes(cs, k, p, joined, du.dot(nrm), du.dot(e1), du.dot(e2), dissipated, nullptr,
                                           &to_reference);
    return f.n * nrm + f.s1 * e1 + f.s2 * e2;
}

} // namespace

void color_contacts(ContactSet& cs, int n_blocks) {
    // Greedy: each contact that carries sub-contacts, in order, takes the lowest of 64 colours
    // that neither of its blocks has yet; a contact whose blocks have used them all goes to the
    // list after the colours. Contacts without sub-contacts (blocks near one another, or meeting
    // along an edge: most of a jointed rock mass's) are not listed: the contact update would
    // only look at them to find nothing to do (a refresh that makes one carry colours again).
    // Two passes of the same greedy choice, the first counting each colour's contacts, the second
    // placing them, so that no colour is kept per contact.
    constexpr int kColors = 64;
    const int nc = cs.size();
    std::vector<std::uint64_t> used(n_blocks, 0);
    auto each_colored = [&](auto&& put) {
        std::fill(used.begin(), used.end(), 0);
        for (int c = 0; c < nc; ++c) {
            if (cs.sub_offset[c] == cs.sub_offset[c + 1]) continue;
            const std::uint64_t free = ~(used[cs.block_a[c]] | used[cs.block_b[c]]);
            const int k = free ? __builtin_ctzll(free) : kColors;
            if (k < kColors) {
                used[cs.block_a[c]] |= std::uint64_t{1} << k;
                used[cs.block_b[c]] |= std::uint64_t{1} << k;
            }
            put(c, k);
        }
    };
    std::vector<int> count(kColors + 1, 0);
    int listed = 0;
    each_colored([&](int, int k) {
        ++count[k];
        ++listed;
    });
    int n_colors = 0;
    for (int k = 0; k < kColors; ++k) {
        if (count[k] > 0) n_colors = k + 1;
    }
    cs.color_offset.assign(n_colors + 1, 0);
    for (int k = 0; k < n_colors; ++k) cs.color_offset[k + 1] = cs.color_offset[k] + count[k];
    std::vector<int> fill(cs.color_offset.begin(), cs.color_offset.end() - 1);
    fill.push_back(cs.color_offset.back()); // the uncoloured, after the colours
    cs.color_order.assign(listed, 0);
    each_colored([&](int c, int k) { cs.color_order[fill[std::min(k, n_colors)]++] = c; });
    cs.colored = true;
}

namespace {
std::atomic<bool> g_rest_open{true};
} // namespace

void set_rest_open_contacts(bool on) { g_rest_open = on; }
bool rest_open_contacts() { return g_rest_open; }

namespace {
std::atomic<bool> g_batched_subs{true};
} // namespace

void set_batched_sub_contacts(bool on) { g_batched_subs = on; }
bool batched_sub_contacts() { return g_batched_subs; }

void update_contacts(Model& m, double dt) {
    ContactSet& cs = m.contacts;
    BlockSet& s = m.blocks;
    GridpointSet& g = m.gridpoints;
    const int n = s.size();
    const int threads = thread_count();
    // What each block did over the last step: its displacement, and its turn about its
    // centroid by the angle |w| dt about w (integrate.cpp), as the axis and the sine and
    // 1 - cosine of the angle. A material point at r from the centroid (now) moved by
    // disp + (r - R(-turn) r): its exact displacement, not v dt + w x r dt, which leaves out
    // the half of the centripetal term (w x (w x r)) dt^2 / 2 that the turn gave it. A closure
    // built from v dt + w x r dt drifts from the points' motion step by step, at a block that
    // pivots on a corner by as much as its springs' work of order dt, unmatched by the work
    // the joint forces do on the blocks' turn (the energy the joints hold and give back would
    // not be what the blocks put in). In static mode the path to equilibrium is not physical
    // (scaled masses and inertias) and keeps the first-order form, v dt + w x r dt.
    // The displacement is the velocity's over the step (made where it is used, block_disp), and
    // for a piece of a clump what its turn about the clump's centroid adds (clump_shift, kept
    // only in a model with clumps).
    // The blocks' rotation matrices are made with their world vertices (BlockSet::rotation),
    // after each step's integration.
    if (static_cast<int>(s.rotation.size()) != n) refresh_world_vertices(m);
    const Mat3* rot_of = s.rotation.data();
    thread_local std::vector<Vec3> axis, clump_shift;
    thread_local std::vector<double> turn_sin, turn_cos1;
    axis.resize(n);
    turn_sin.resize(n);
    turn_cos1.resize(n);
    {
        // Block by block, each on its own: on the threads in a large model (the pointers: a
        // thread_local named inside the loop would be each worker's own).
        Vec3* axis_w = axis.data();
        double* sin_w = turn_sin.data();
        double* cos1_w = turn_cos1.data();
        const bool dynamic = m.settings.dynamic;
        // A block whose velocity was given at t has not moved with it yet.
        thread_local std::vector<std::uint8_t> still;
        still.resize(n);
        for (int b = 0; b < n; ++b) still[b] = s.half_kick[b] || ((s.flags[b] & kFixed) && !s.vel_bc[b]);
        const std::uint8_t* still_of = still.data();
        // Four at a time (make_block_turns), in chunks on the threads in a large model.
        constexpr int kChunk = 512;
        const int n_chunks = (n + kChunk - 1) / kChunk;
        parallel_for(n_chunks, threads, n >= kParallelMinBlocks, [&](int ch) {
            make_block_turns(s.ang_vel.data(), still_of, ch * kChunk, std::min(n, (ch + 1) * kChunk), dt, dynamic, axis_w,
                             sin_w, cos1_w);
        });
    }
    // A piece of a clump turned about the clump's centroid (clump.cpp): its velocity is that of
    // the rigid motion at its centroid now, not its centroid's displacement over the step.
    {
        thread_local ClumpList clumps;
        list_clumps(s, clumps);
        if (clumps.size() > 0) clump_shift.assign(n, Vec3::Zero());
        else std::vector<Vec3>().swap(clump_shift);
        for (int c = 0; c < clumps.size(); ++c) {
            const int* p = clumps.pieces.data() + clumps.offset[c];
            const int np = clumps.offset[c + 1] - clumps.offset[c];
            const Vec3 centre = clump_body(s, p, np).centroid;
            for (int i = 0; i < np; ++i) {
                const int b = p[i];
                if (s.half_kick[b] || ((s.flags[b] & kFixed) && !s.vel_bc[b])) continue;
                const Vec3 r = s.centroid[b] - centre, k = axis[b];
                clump_shift[b] = turn_cos1[b] * (r - k.dot(r) * k) + turn_sin[b] * k.cross(r) - s.ang_vel[b].cross(r) * dt;
            }
        }
    }
    // So does a gridpoint.
    auto gp_vel = [&g](int i) { return g.half_kick[i] ? Vec3(Vec3::Zero()) : g.vel[i]; };
    // Joint-law constants once per material and model, not per contact.
    thread_local std::vector<LawParams> params;
    const int n_jmat = static_cast<int>(m.joint_materials.size());
    params.resize(2 * std::max(1, n_jmat));
    bool dilation = false;
    for (int j = 0; j < n_jmat; ++j) {
        params[2 * j] = law_params(m, j, 1);
        params[2 * j + 1] = law_params(m, j, 2);
        dilation = dilation || params[2 * j].tan_dil != 0;
    }
    // The sub-contacts' dilations are kept once some joint can dilate (ContactSet::sub_udil).
    if (dilation && cs.sub_udil.empty()) cs.sub_udil.assign(cs.n_subs(), 0.0);
    const LawParams none;
    // The threads reach the caller's thread_local arrays through these pointers (a thread_local
    // named inside the parallel loop would be each worker's own, empty).
    const LawParams* law = params.data();
    const Vec3* shift_of = clump_shift.empty() ? nullptr : clump_shift.data();
    // The displacement of block b's centroid over the last step (a block whose velocity was
    // given at t has not moved with it yet).
    auto block_disp = [&s, dt, shift_of](int b) -> Vec3 {
        if (s.half_kick[b] || ((s.flags[b] & kFixed) && !s.vel_bc[b])) return Vec3::Zero();
        const Vec3 d = s.vel[b] * dt;
        return shift_of && s.clump[b] != 0 ? Vec3(d + shift_of[b]) : d;
    };
    // Each block's, once per step for all its contacts (put_in_batch).
    thread_local std::vector<Vec3> disp;
    disp.resize(n);
    for (int b = 0; b < n; ++b) disp[b] = block_disp(b);
    const Vec3* disp_of = disp.data();
    const Vec3* axis_of = axis.data();
    const double* sin_of = turn_sin.data();
    const double* cos1_of = turn_cos1.data();
    // The displacement over the last step of the point at r from the centroid of block b, whose
    // own displacement is d (block_disp, made once for all the points of a contact).
    auto moved_by = [=](int b, const Vec3& d, const Vec3& r) -> Vec3 {
        const Vec3& k = axis_of[b];
        return d + cos1_of[b] * (r - k.dot(r) * k) + sin_of[b] * k.cross(r);
    };
    auto moved = [=](int b, const Vec3& r) -> Vec3 { return moved_by(b, block_disp(b), r); };
    auto law_of = [&](int c) -> const LawParams& {
        const int jm = cs.jmat(c);
        return (jm > 0 && jm < n_jmat) ? law[2 * jm + (cs.jcons(c) == 2 ? 1 : 0)] : none;
    };
    // Static mode: the joint stiffness each rigid block feels, for its mass (mass_scaling.h).
    const bool stiffness = !m.settings.dynamic;
    if (stiffness) {
        cs.joint_kt.assign(n, 0.0);
        cs.joint_kr.assign(n, 0.0);
    }
    // The contacts between rigid blocks, on the threads, colour by colour: no two contacts of a
    // colour share a block, so each adds its forces straight into its blocks, and every block
    // takes its contacts' forces in colour order, whatever the threads (each sub-contact belongs
    // to one contact, so the joint law's state is never shared either).
    if (!cs.colored) {
        color_contacts(cs, n);
        cs.rest.quiet.clear(); // (its bits are by entry of the colouring)
    }
    // The energy account: what each contact dissipates, summed in contact order afterwards.
    thread_local std::vector<double> contact_dissipation;
    const bool account = m.energy.on;
    if (account) contact_dissipation.assign(cs.size(), 0.0);
    double* dissipation = account ? contact_dissipation.data() : nullptr;
    // The displacement over the last step of the point at r from the centroid of a block,
    // d + cos1 (r - (k.r) k) + sin k x r (moved_by), is d + T r with T = cos1 (I - k k^T) + sin [k]x
    // (the turn matrix, made in make_contact_axes).
    // Open sub-contacts keep their closures by reference (contact.h), with how far each block has
    // moved since its geometry reference (detect_contacts measured it this step).
    // Dynamic mode holds them so (the contacts it can leave alone are worth it there); static
    // mode as they are (every contact is looked at for its stiffness anyway). A change of mode
    // gives them as the new one holds them within the step, after the joint law, so that each
    // takes the step's increment once: `held` is the form they are in, `want` the form they leave in.
    const bool held = cs.open_by_reference, want = m.settings.dynamic;
    // (While they are given the new form, shift_open_closures works in both directions.)
    if (want) cs.open_by_reference = true;
    // (A block without a reference yet has not moved from it: reference_shift.)
    const size_t n_refs = std::min(cs.geo_centroid.size(), cs.geo_orientation.size());
    const double* motion_of =
        cs.motion_fresh && cs.block_motion.size() == static_cast<size_t>(n) && cs.radius.size() == static_cast<size_t>(n)
            ? cs.block_motion.data()
            : nullptr;
    cs.motion_fresh = false;
    // A contact whose sub-contacts are all open, by more than its blocks can have moved towards
    // each other at any of them since their references, stays open this step whatever it is
    // shown: it is left as it is (in dynamic mode: static mode's masses count the open joints'
    // stiffness too). A point of a contact lies within ctol of the other block, so a turn by t
    // about that block's centroid moves it by at most t (radius + ctol).
    const bool rest_open = motion_of && held && want && rest_open_contacts();
    const double ctol = cs.ctol;
    // How far contact c's blocks can have moved towards each other at any of its points since
    // their references (asked only where rest_open: each block's share made once for all its
    // contacts).
    thread_local std::vector<double> reach_share;
    // The largest reach of any contact: reach_of for the block of largest share taken twice (no
    // pair's is above it, each sum's rounding being monotonic), or NaN where some share is not a
    // number (then every contact is looked at).
    double reach_bound = std::numeric_limits<double>::quiet_NaN();
    if (rest_open) {
        reach_share.resize(n);
        double most = 0;
        bool unknown = false;
        for (int b = 0; b < n; ++b) {
            const double v = motion_of[b] * (1 + ctol / std::max(cs.radius[b], 1e-300));
            reach_share[b] = v;
            unknown = unknown || v != v;
            most = std::max(most, v);
        }
        if (!unknown) reach_bound = (most + most) + 1e-9 * ctol;
    }
    const double* share_of = reach_share.data();
    auto reach_of = [=](int a, int b) { return share_of[a] + share_of[b] + 1e-9 * ctol; };
    // A closer bound on the same, for a contact whose blocks moved far but together (the side
    // faces of two columns that settle side by side): the blocks' points move towards each other
    // by at most the difference of their centroids' displacements since the references, plus
    // each block's turn t times (radius + ctol) (as in reach_of). The turn's share of a block's
    // movement is what its displacement leaves (movement: dx + t radius). Asked only where
    // reach_of does not leave the contact alone; the slack covers the roundings of both this and
    // the joint law's own closure by reference (shift_at), as in reach_of. NaN without references.
    const bool have_refs = rest_open && n_refs >= static_cast<size_t>(n);
    auto close_reach_of = [&, have_refs, ctol](int a, int b) {
        if (!have_refs) return std::numeric_limits<double>::quiet_NaN();
        const Vec3 &ca = s.centroid[a], &cb = s.centroid[b];
        const Vec3 da = ca - cs.geo_centroid[a], db = cb - cs.geo_centroid[b];
        auto turn_share = [&](int x, const Vec3& d) {
            const double t = std::max(0.0, motion_of[x] - d.norm()) + 1e-12 * motion_of[x];
            return t * (1 + ctol / std::max(cs.radius[x], 1e-300));
        };
        const double apart = (db - da).norm();
        const double size = ca.cwiseAbs().maxCoeff() + cb.cwiseAbs().maxCoeff();
        return (apart + turn_share(a, da) + turn_share(b, db)) * (1 + 1e-12) + 1e-14 * size + 1e-9 * ctol;
    };
    // Whether sub-contact q (of a contact not glued) is open by reference, to stay open this step
    // if its blocks cannot have closed it (one of a joint with strength that has not failed would
    // fail on its step, and one with tension could hold on: looked at).
    auto open_by_reference = [&](int q, bool strength) {
        const std::uint8_t f = cs.sub_flags(q);
        return held_open(f) && (!strength || (f & kSubFailed));
    };
    // Whether each joint material has strength (tension or cohesion), for stays_open.
    thread_local std::vector<char> strong;
    strong.assign(std::max(1, n_jmat), 0);
    for (int j = 0; j < n_jmat; ++j) strong[j] = law[2 * j].ten > 0 || law[2 * j].coh > 0;
    const char* strong_of = strong.data();
    const double* udil = cs.sub_udil.empty() ? nullptr : cs.sub_udil.data();
    // All of contact c's sub-contacts open by reference, each by more than reach: the same test as
    // open_by_reference with the contact's strength, asked of the joint only where some
    // sub-contact has not failed.
    auto strong_joint = [&](int c) {
        const int jm = cs.jmat(c);
        return jm > 0 && jm < n_jmat && strong_of[jm];
    };
    // Whether contact c, whose sub-contacts' largest closure plus dilation is ud, stays open: by
    // its blocks' reach, else by the closer bound (close_reach_of; counted in n_by_close).
    auto beyond_reach = [&](int c, double ud, double reach, int& n_by_close) {
        if (ud + reach < 0) return true;
        if (!(ud + close_reach_of(cs.block_a[c], cs.block_b[c]) < 0)) return false;
        ++n_by_close;
        return true;
    };
    // (*largest: the largest closure plus dilation of its sub-contacts, made where it returns true.)
    auto stays_open = [&](int c, double reach, double* largest, int& n_by_close) {
        if (cs.joined(c)) return false;
        bool intact = false;
        double most = -std::numeric_limits<double>::infinity();
        for (int q = cs.sub_offset[c], q1 = cs.sub_offset[c + 1]; q < q1; ++q) {
            const std::uint8_t f = cs.sub_flags(q);
            const double ud = cs.sub_un[q] + (udil ? udil[q] : 0.0);
            if (!held_open(f)) return false;
            most = std::max(most, ud);
            intact = intact || !(f & kSubFailed);
        }
        if (intact && strong_joint(c)) return false;
        *largest = most;
        return beyond_reach(c, most, reach, n_by_close);
    };
    // The memory of the open contacts left alone at the last step (ContactSet::rest): a
    // contact whose sub-contacts have not changed since stays open while its largest closure plus
    // dilation plus reach is below zero, which is stays_open's answer (ud + reach < 0 for every
    // sub-contact just when it holds for the largest: adding reach keeps the order), and its
    // joint has no strength now (else it is looked at in full).
    const int nc_all = cs.size();
    if (rest_open) {
        auto& r = cs.rest;
        const bool valid = static_cast<int>(r.margin.size()) == nc_all && r.step + 1 == m.step && r.revision == cs.revision &&
                           r.edits == m.edits && r.run == cs.cycle_runs;
        if (!valid) {
            r.margin.assign(nc_all, std::numeric_limits<double>::quiet_NaN());
            r.quiet.clear();
        }
        r.step = m.step;
        r.revision = cs.revision;
        r.edits = m.edits;
        r.run = cs.cycle_runs;
    } else if (!cs.rest.margin.empty()) {
        cs.rest = ContactSet::RestMemory{};
    }
    // The quiet contacts (ContactSet::RestMemory::quiet): left alone without a look while no
    // contact's reach can have brought any of them to close, which is when every margin plus
    // the reach bound stays below zero (the test of `steps` below for each of them).
    const bool quiet = rest_open && !cs.rest.quiet.empty() && cs.rest.quiet.size() == (cs.color_order.size() + 63) / 64 &&
                       reach_bound < cs.rest.slack;
    const std::uint64_t* quiet_bits = quiet ? cs.rest.quiet.data() : nullptr;
    double* margin = cs.rest.margin.data();
    int by_margin = 0; // (ContactSet::RestMemory::used)
    int by_close = 0;  // (ContactSet::RestMemory::used_close)
    int left = 0; // contacts left alone (ContactSet::left_open)
    // Whether contact c steps this step: not one without sub-contacts, of an excavated or a
    // deformable block, or open by more than its blocks can have closed it (counted in n_left).
    auto steps = [&](int c, int& n_left, int& n_by_margin, int& n_by_close) {
        // Most contacts between blocks apart carry no sub-contact: nothing to add.
        if (cs.sub_offset[c] == cs.sub_offset[c + 1]) return false;
        const int a = cs.block_a[c], b = cs.block_b[c];
        if ((s.flags[a] | s.flags[b]) & (kExcavated | kDeformable)) {
            // (Not stepped: an excavated block's contacts change form as they are.)
            if (held != want) shift_open_closures(m, c, want);
            return false;
        }
        if (rest_open) {
            const double reach = reach_of(a, b);
            // (Its sub-contacts' flags and the contact's glue are not read again: only a refresh or
            // a command changes them between two steps, and either makes the memory forgotten. A
            // margin not known, NaN, is not looked at further.)
            if (margin[c] == margin[c] && !strong_joint(c) && beyond_reach(c, margin[c], reach, n_by_close)) {
                ++n_left;
                ++n_by_margin;
                return false;
            }
            double largest;
            if (stays_open(c, reach, &largest, n_by_close)) {
                margin[c] = largest;
                ++n_left;
                return false;
            }
            margin[c] = std::numeric_limits<double>::quiet_NaN();
        }
        return true;
    };
    // A contact that steps takes its axes and the blocks' motion on them from a batch
    // (contact_axes.h), made for up to ContactAxesBatch::kSize contacts at a time; its inputs:
    auto put_in_batch = [&](ContactAxesBatch& B, int l, int c) {
        const NormalCode code = cs.normal_code[c];
        B.nu[l] = code.u;
        B.nv[l] = code.v;
        const int blocks[2] = {cs.block_a[c], cs.block_b[c]};
        for (int side = 0; side < 2; ++side) {
            const int x = blocks[side];
            const Vec3 &d = disp_of[x], &k = axis_of[x], &c0 = s.centroid[x];
            const double* r = rot_of[x].data();
            for (int i = 0; i < 3; ++i) {
                B.k[side][i][l] = k[i];
                B.disp[side][i][l] = d[i];
                B.centroid[side][i][l] = c0[i];
            }
            for (int i = 0; i < 9; ++i) B.rot[side][i][l] = r[i];
            B.sin[side][l] = sin_of[x];
            B.cos1[side][l] = cos1_of[x];
        }
    };
    // A contact's sums into its blocks (world axes): fb the force on b, ma its moment about a's
    // centroid (a takes the opposite of both), mb about b's own (ma - cab x fb), and scale the sum
    // of the sub-contacts' force magnitudes.
    auto put_on_blocks = [&s](int a, int b, const Vec3& fb, const Vec3& ma, const Vec3& mb, double scale) {
        s.force[a] -= fb;
        s.moment[a] -= ma;
        s.force[b] += fb;
        s.moment[b] += mb;
        s.force_scale[a] += scale;
        s.force_scale[b] += scale;
    };
    // A contact's axes from lane l of its batch.
    auto axes_of = [](const ContactAxesBatch& B, int l) {
        Mat3 ax;
        for (int i = 0; i < 3; ++i) {
            ax(0, i) = B.n[i][l];
            ax(1, i) = B.e1[i][l];
            ax(2, i) = B.e2[i][l];
        }
        return ax;
    };
    // Contact c's step, from lane l of its batch.
    auto rigid_contact = [&](int c, const ContactAxesBatch& B, int l) {
        const int a = cs.block_a[c], b = cs.block_b[c];
        const LawParams& p = law_of(c);
        const bool joined = cs.joined(c);
        const Vec3 nrm(B.n[0][l], B.n[1][l], B.n[2][l]);
        // Everything on the contact's axes (n, e1, e2), the rows of ax, a rotation: a point's lever
        // ra from a's centroid, the relative displacement there, the forces and their moments.
        const Mat3 ax = axes_of(B, l);
        const Vec3 cab(B.cab[0][l], B.cab[1][l], B.cab[2][l]);
        const double k = std::max(p.kn, p.ks);
        // A point at ra from a's centroid, rb = ra - cab from b's, moved by
        // db + T_b rb - da - T_a ra = (db - da - T_b cab) + (T_b - T_a) ra: du0 and dt_ax.
        const double du0[3] = {B.du0[0][l], B.du0[1][l], B.du0[2][l]};
        Mat3 dt_ax, to_a, to_b;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                dt_ax(i, j) = B.dt_ax[3 * i + j][l];
                // The points ride on their blocks: a's body frame to the axes, and b's (from a's centroid).
                to_a(i, j) = B.to[0][3 * i + j][l];
                to_b(i, j) = B.to[1][3 * i + j][l];
            }
        }
        const Vec3 cab_ax(B.cab_ax[0][l], B.cab_ax[1][l], B.cab_ax[2][l]);
        // How far the blocks have moved towards each other since their references at the point at
        // ra (on the axes), shift0 + shift_ra . ra (reference_shift), made once some sub-contact
        // is open: D_X(x) = (c_X - g_X) + (I - Rg_X R_X^T)(x - c_X) for each block.
        // So n . D is n . (dc_b - dc_a) - (E_b^T n) . cab + ((E_b - E_a)^T n) . ra, with
        // E_X^T n = n - R_X (Rg_X^T n).
        bool have_shift = false;
        double shift0 = 0;
        Vec3 shift_ra = Vec3::Zero();
        auto shift_at = [&](const Vec3& ra) {
            if (!have_shift) {
                have_shift = true;
                // (A block without a reference has not moved from it: E = 0, c = g.)
                auto back = [&](int x) -> Vec3 {
                    return static_cast<size_t>(x) < n_refs ? Vec3(rot_of[x] * (cs.geo_orientation[x].conjugate() * nrm)) : nrm;
                };
                auto moved = [&](int x) -> Vec3 {
                    return static_cast<size_t>(x) < n_refs ? Vec3(s.centroid[x] - cs.geo_centroid[x]) : Vec3(Vec3::Zero());
                };
                const Vec3 back_a = back(a), back_b = back(b);
                shift0 = nrm.dot(moved(b) - moved(a)) - (nrm - back_b).dot(cab);
                shift_ra = ax * Vec3(back_a - back_b);
            }
            return shift0 + shift_ra.dot(ra);
        };
        const bool tension = p.ten > 0 || p.coh > 0;
        double reach = std::numeric_limits<double>::quiet_NaN(); // made at the first open one
        // The sums over the sub-contacts as plain numbers (on the axes): the force on b and its
        // moment about a's centroid.
        double f0 = 0, f1 = 0, f2 = 0, m0 = 0, m1 = 0, m2 = 0;
        double scale = 0, kt = 0, kra = 0, krb = 0;
        constexpr int kMags = 8;
        double mag2[kMags];
        int n_mag = 0;
        for (int q = cs.sub_offset[c]; q < cs.sub_offset[c + 1]; ++q) {
            const bool of_b = cs.sub_side(q) == 1;
            const Vec3 local = cs.sub_point_local(q);
            const Mat3& to = of_b ? to_b : to_a;
            const double o0 = of_b ? cab_ax[0] : 0.0, o1 = of_b ? cab_ax[1] : 0.0, o2 = of_b ? cab_ax[2] : 0.0;
            const double l0 = local[0], l1 = local[1], l2 = local[2];
            const double r0 = o0 + (to(0, 0) * l0 + to(0, 1) * l1 + to(0, 2) * l2);
            const double r1 = o1 + (to(1, 0) * l0 + to(1, 1) * l1 + to(1, 2) * l2);
            const double r2 = o2 + (to(2, 0) * l0 + to(2, 1) * l1 + to(2, 2) * l2);
            const Vec3 ra(r0, r1, r2);
            if (stiffness) {
                const double kq = k * cs.sub_area[q];
                kt += kq;
                kra += kq * ra.squaredNorm();
                krb += kq * (ra - cab_ax).squaredNorm();
            }
            // Open by more than its blocks can have closed it: as it is, carrying nothing.
            if (rest_open && !joined && open_by_reference(q, tension)) {
                if (reach != reach) reach = reach_of(a, b);
                if (cs.sub_un[q] + cs.sub_dilation(q) + reach < 0) continue;
            }
            const double du0n = du0[0] + (dt_ax(0, 0) * r0 + dt_ax(0, 1) * r1 + dt_ax(0, 2) * r2);
            const double du1 = du0[1] + (dt_ax(1, 0) * r0 + dt_ax(1, 1) * r1 + dt_ax(1, 2) * r2);
            const double du2 = du0[2] + (dt_ax(2, 0) * r0 + dt_ax(2, 1) * r1 + dt_ax(2, 2) * r2);
            const bool was_held = held && held_open(cs.sub_flags(q));
            const double shift = was_held ? shift_at(ra) : 0.0;
            bool to_reference;
            const AxesForce f = joint_step_on_axes(cs, q, p, joined, du0n, du1, du2, dissipation ? dissipation + c : nullptr,
                                                   held ? &shift : nullptr, &to_reference);
            // Opened this step (or, as the form changes, open after it): by reference, if that
            // is the form it leaves in; held by reference and still open as the form changes: as
            // it is now.
            if (to_reference && want) cs.sub_un[q] += shift_at(ra);
            else if (was_held && !want && (cs.sub_flags(q) & kSubOpen)) cs.sub_un[q] -= shift;
            f0 += f.n;
            f1 += f.s1;
            f2 += f.s2;
            m0 += r1 * f.s2 - r2 * f.s1;
            m1 += r2 * f.n - r0 * f.s2;
            m2 += r0 * f.s1 - r1 * f.n;
            // Its force's magnitude, for the blocks' force scale: the roots are taken eight at a
            // time and after the loop, in order, so that no sub-contact's step waits on one.
            const double f2n = f.n * f.n + f.s1 * f.s1 + f.s2 * f.s2;
            if (n_mag == kMags) {
                for (int i = 0; i < kMags; ++i) scale += std::sqrt(mag2[i]);
                n_mag = 0;
            }
            mag2[n_mag++] = f2n;
        }
        for (int i = 0; i < n_mag; ++i) scale += std::sqrt(mag2[i]);
        // Back on the world axes (the sums above are on the contact's).
        const Vec3 fb = ax.transpose() * Vec3(f0, f1, f2), ma = ax.transpose() * Vec3(m0, m1, m2);
        put_on_blocks(a, b, fb, ma, Vec3(ma - cab.cross(fb)), scale);
        if (stiffness) {
            cs.joint_kt[a] += kt;
            cs.joint_kr[a] += kra;
            cs.joint_kt[b] += kt;
            cs.joint_kr[b] += krb;
        }
    };
    const int n_colors = static_cast<int>(cs.color_offset.size()) - 1;
    const int* order = cs.color_order.data();
    const int* offset = cs.color_offset.data();
    // The contacts order[i0, i1) that step, a batch at a time, each in its place in that order.
    constexpr int kBatch = ContactAxesBatch::kSize;
    // The joint law's plain case runs on the batch (step_plain_subs) in dynamic mode without the
    // energy account; a contact with a sub-contact that is not plain before its step (open, new
    // or fresh), or with more than kMaxSubs, steps by the scalar law, as does one where some
    // sub-contact opens or slips in the batch.
    const bool plain = !stiffness && !dissipation && batched_sub_contacts();
    auto put_plain = [&](ContactSubBatch& S, int l, int c) {
        const int q0 = cs.sub_offset[c], ns = cs.sub_offset[c + 1] - q0;
        S.n_subs[l] = 0;
        if (ns > ContactSubBatch::kMaxSubs) return;
        for (int j = 0; j < ns; ++j) {
            const int q = q0 + j;
            const std::uint8_t f = cs.sub_flags(q);
            if (f & (kSubOpen | kSubNew | kSubFresh)) return;
            const Vec3 local = cs.sub_point_local(q);
            for (int i = 0; i < 3; ++i) S.local[j][i][l] = local[i];
            S.of_b[j][l] = cs.sub_side(q) == 1 ? 1.0 : 0.0;
            S.un[j][l] = cs.sub_un[q];
            S.dil[j][l] = cs.sub_dilation(q);
            S.ss[j][0][l] = cs.sub_ss[q][0];
            S.ss[j][1][l] = cs.sub_ss[q][1];
            S.area[j][l] = cs.sub_area[q];
            S.failed[j][l] = (f & kSubFailed) ? 1.0 : 0.0;
        }
        // (The slots past its last hold whatever they held: left out of its sums.)
        const LawParams& p = law_of(c);
        S.kn[l] = p.kn;
        S.ks[l] = p.ks;
        S.coh[l] = p.coh;
        S.ten[l] = p.ten;
        S.tan_phi[l] = p.tan_phi;
        S.tan_res[l] = p.tan_res;
        S.joined[l] = cs.joined(c) ? 1.0 : 0.0;
        S.n_subs[l] = ns;
    };
    int batched = 0; // (ContactSet::batched)
    auto run = [&](int i0, int i1, int& n_left, int& n_batched, int& n_by_margin, int& n_by_close) {
        // (Each thread its own batch.)
        thread_local ContactAxesBatch batch;
        thread_local ContactSubBatch sub_batch;
        ContactAxesBatch& B = batch;
        ContactSubBatch& S = sub_batch;
        int listed[kBatch];
        int n = 0;
        auto flush = [&] {
            make_contact_axes(B, n);
            if (plain) {
                for (int l = 0; l < n; ++l) put_plain(S, l, listed[l]);
                step_plain_subs(B, S, n);
            }
            for (int l = 0; l < n; ++l) {
                const int c = listed[l];
                if (!plain || S.n_subs[l] == 0 || S.slow[l] != 0) {
                    rigid_contact(c, B, l);
                    continue;
                }
                // Stepped in the batch: its sub-contacts take their new state.
                ++n_batched;
                for (int j = 0, q = cs.sub_offset[c]; q < cs.sub_offset[c + 1]; ++j, ++q) {
                    cs.sub_un[q] = S.un_new[j][l];
                    Eigen::Vector2d& us = cs.sub_us[q];
                    us[0] += S.dus[j][0][l];
                    us[1] += S.dus[j][1][l];
                    cs.sub_ss[q] = Eigen::Vector2d(S.ss_new[j][0][l], S.ss_new[j][1][l]);
                    cs.set_sub_flags(q, static_cast<std::uint8_t>(cs.sub_flags(q) & ~(kSubSlip | kSubOpen)));
                }
                // Its sums, put on the world axes in the batch, into its blocks.
                put_on_blocks(cs.block_a[c], cs.block_b[c], Vec3(S.fb[0][l], S.fb[1][l], S.fb[2][l]),
                              Vec3(S.ma[0][l], S.ma[1][l], S.ma[2][l]), Vec3(S.mb[0][l], S.mb[1][l], S.mb[2][l]),
                              S.scale[l]);
            }
            n = 0;
        };
        auto take = [&](int c) {
            if (!steps(c, n_left, n_by_margin, n_by_close)) return;
            put_in_batch(B, n, c);
            listed[n++] = c;
            if (n == kBatch) flush();
        };
        if (!quiet_bits) {
            for (int i = i0; i < i1; ++i) take(order[i]);
        } else if (i0 < i1) {
            // The entries whose quiet bit is clear, in order.
            for (int w = i0 >> 6; w <= (i1 - 1) >> 6; ++w) {
                const int lo = w * 64;
                std::uint64_t live = ~quiet_bits[w];
                if (lo < i0) live &= ~std::uint64_t{0} << (i0 - lo);
                if (i1 - lo < 64) live &= (std::uint64_t{1} << (i1 - lo)) - 1;
                while (live) {
                    const int j = __builtin_ctzll(live);
                    live &= live - 1;
                    take(order[lo + j]);
                }
            }
        }
        if (n > 0) flush();
    };
    const int n_colored = n_colors >= 0 ? offset[n_colors] : 0;
    if (threads > 1 && cs.size() >= kParallelMinItems) {
#pragma omp parallel num_threads(threads) reduction(+ : left, batched, by_margin, by_close)
        for (int col = 0; col < n_colors; ++col) {
            const int n_pieces = (offset[col + 1] - offset[col] + kBatch - 1) / kBatch;
#pragma omp for schedule(static)
            for (int piece = 0; piece < n_pieces; ++piece) {
                const int i0 = offset[col] + piece * kBatch;
                run(i0, std::min(offset[col + 1], i0 + kBatch), left, batched, by_margin, by_close);
            }
        }
    } else {
        // The same order, without entering an OpenMP region (parallel.h).
        run(0, n_colored, left, batched, by_margin, by_close);
    }
    // Then, in contact order: the contacts no colour could take (a block with more contacts
    // than there are colours), and those of deformable blocks.
    run(n_colored, static_cast<int>(cs.color_order.size()), left, batched, by_margin, by_close);
    cs.rest.used_quiet = quiet ? cs.rest.n_quiet : 0;
    if (quiet) {
        left += cs.rest.n_quiet;
        by_margin += cs.rest.n_quiet;
    } else if (rest_open) {
        // The quiet contacts for the next steps: those left alone by their margin whose margin is
        // below zero by more than twice this step's reach bound (the others are looked at each
        // step), so that the list holds until the bound has doubled.
        auto& r = cs.rest;
        const int n_listed = static_cast<int>(cs.color_order.size());
        r.quiet.assign((n_listed + 63) / 64, 0);
        r.n_quiet = 0;
        r.slack = std::numeric_limits<double>::infinity();
        const double enough = reach_bound + reach_bound;
        if (enough == enough) {
            for (int i = 0; i < n_listed; ++i) {
                const int c = order[i];
                const double gap = -margin[c];
                if (!(gap > enough) || strong_joint(c)) continue;
                r.quiet[i >> 6] |= std::uint64_t{1} << (i & 63);
                ++r.n_quiet;
                r.slack = std::min(r.slack, gap);
            }
        }
        if (r.n_quiet == 0) r.quiet.clear();
    }
    cs.left_open = left;
    cs.batched = batched;
    cs.rest.used = by_margin;
    cs.rest.used_close = by_close;
    cs.open_by_reference = want;
    // Without gridpoints there are no deformable blocks.
    for (int c = 0; c < (g.size() > 0 ? cs.size() : 0); ++c) {
        const int a = cs.block_a[c], b = cs.block_b[c];
        if ((s.flags[a] | s.flags[b]) & kExcavated) continue;
        if ((s.flags[a] | s.flags[b]) & kDeformable) {
            const LawParams& p = law_of(c);
            const bool joined = cs.joined(c);
            const Vec3 nrm = cs.normal(c);
            Vec3 e1, e2;
            shear_axes(nrm, e1, e2);
            const double kj = std::max(p.kn, p.ks);
            // Gridpoints against the other block's surface (contact_gridpoint.h).
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                const bool of_a = cs.sub_side(k) == 3;
                const int gp = cs.sub_vertex(k);
                const int o = of_a ? b : a;
                const std::array<int, 3> tri = cs.sub_triangle(k);
                Vec3 dxo, lever = Vec3::Zero(), w = Vec3::Zero();
                if (tri[0] >= 0) {
                    w = cs.sub_weights(k);
                    dxo = (w[0] * gp_vel(tri[0]) + w[1] * gp_vel(tri[1]) + w[2] * gp_vel(tri[2])) * dt;
                } else {
                    lever = rot_of[o] * cs.sub_point_local(k);
                    dxo = moved(o, lever);
                }
                const Vec3 dxg = gp_vel(gp) * dt;
                const Vec3 f = joint_step(cs, k, p, joined, nrm, e1, e2, of_a ? Vec3(dxo - dxg) : Vec3(dxg - dxo),
                                          dissipation ? dissipation + c : nullptr);
                const Vec3 fg = of_a ? Vec3(-f) : f; // on the gridpoint; its partner takes -fg
                const double fn = f.norm();
                g.force[gp] += fg;
                g.force_scale[gp] += fn;
                if (tri[0] >= 0) {
                    for (int i = 0; i < 3; ++i) {
                        g.force[tri[i]] -= w[i] * fg;
                        g.force_scale[tri[i]] += w[i] * fn;
                    }
                } else {
                    s.force[o] -= fg;
                    s.moment[o] -= lever.cross(fg);
                    s.force_scale[o] += fn;
                    if (stiffness) {
                        const double kq = kj * cs.sub_area[k];
                        cs.joint_kt[o] += kq;
                        cs.joint_kr[o] += kq * lever.squaredNorm();
                    }
                }
            }
        }
    }
    if (account) {
        double sum = 0;
        for (int c = 0; c < cs.size(); ++c) sum += dissipation[c];
        m.energy.slip += sum;
    }
}

double stiffest_contact(const Model& m) {
    const ContactSet& cs = m.contacts;
    double k_max = 0;
    for (int c = 0; c < cs.size(); ++c) {
        const JointMaterial* jp = contact_joint_material(m, c);
        if (!jp) continue;
        const JointMaterial& j = *jp;
        double area = 0;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) area += cs.sub_area[k];
        k_max = std::max(k_max, std::max(j.kn, j.ks) * area);
    }
    return k_max;
}

double contact_critical_timestep(const Model& m) {
    const BlockSet& s = m.blocks;
    double m_min = 0;
    for (int b = 0; b < s.size(); ++b) {
        // A deformable block's own mass does not move as one: its gridpoints set the zones' step.
        if ((s.flags[b] & (kExcavated | kFixed | kDeformable)) || !(s.mass[b] > 0)) continue;
        if (m_min == 0 || s.mass[b] < m_min) m_min = s.mass[b];
    }
    if (!(m_min > 0)) return 0;
    double k_max = stiffest_contact(m);
    if (!(k_max > 0)) {
        double kj = 0, face = 0;
        for (const JointMaterial& j : m.joint_materials) {
            if (j.defined) kj = std::max(kj, std::max(j.kn, j.ks));
        }
        for (int b = 0; b < s.size(); ++b) {
            if (s.flags[b] & kExcavated) continue;
            for (int f = 0; f < s.shape[b].n_faces(); ++f) face = std::max(face, s.shape[b].face_area(f));
        }
        k_max = kj * face;
    }
    if (!(k_max > 0)) return 0;
    return m.settings.dtfrac * 2.0 * std::sqrt(m_min / k_max);
}

double stable_timestep_limit(const Model& m, int* block_out) {
    const BlockSet& s = m.blocks;
    const ContactSet& cs = m.contacts;
    const int n = s.size();
    if (block_out) *block_out = -1;
    const double automatic = contact_critical_timestep(m);
    std::vector<double> kt(n, 0.0), kr(n, 0.0);
    std::vector<Vec3> kx(n, Vec3::Zero()); // sum of k times the lever: moves kr to a clump's centroid
    bool any = false;
    for (int c = 0; c < cs.size(); ++c) {
        const JointMaterial* jp = contact_joint_material(m, c);
        if (!jp) continue;
        const int a = cs.block_a[c], b = cs.block_b[c];
        if ((s.flags[a] | s.flags[b]) & kExcavated) continue;
        const double k = std::max(jp->kn, jp->ks);
        for (int i = cs.sub_offset[c]; i < cs.sub_offset[c + 1]; ++i) {
            const Vec3 x = sub_point(m, c, i);
            const double ki = k * cs.sub_area[i];
            kt[a] += ki;
            kt[b] += ki;
            kr[a] += ki * (x - s.centroid[a]).squaredNorm();
            kr[b] += ki * (x - s.centroid[b]).squaredNorm();
            kx[a] += ki * (x - s.centroid[a]);
            kx[b] += ki * (x - s.centroid[b]);
            any = any || ki > 0;
        }
    }
    if (!any) return automatic > 0 ? automatic / m.settings.dtfrac : 0.0;
    double omega2 = 0;
    int worst = -1;
    // A clump (clump.h) moves as one body: its springs' stiffness over its mass, and their
    // stiffness times the squared lever about its centroid over its least principal inertia.
    const ClumpList clumps = list_clumps(s);
    for (int c = 0; c < clumps.size(); ++c) {
        const int* p = clumps.pieces.data() + clumps.offset[c];
        const int np = clumps.offset[c + 1] - clumps.offset[c];
        bool moves = true;
        for (int i = 0; i < np; ++i) moves = moves && !(s.flags[p[i]] & (kExcavated | kFixed | kDeformable));
        const ClumpBody body = clump_body(s, p, np);
        if (!moves || !(body.mass > 0)) continue;
        double t = 0, r = 0;
        for (int i = 0; i < np; ++i) {
            const Vec3 lever = s.centroid[p[i]] - body.centroid;
            t += kt[p[i]];
            r += kr[p[i]] + 2.0 * lever.dot(kx[p[i]]) + kt[p[i]] * lever.squaredNorm();
        }
        double w2 = t / body.mass;
        const double i_min =
            Eigen::SelfAdjointEigenSolver<Mat3>(body.inertia, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
        if (i_min > 0) w2 = std::max(w2, r / i_min);
        if (w2 > omega2) {
            omega2 = w2;
            worst = p[0];
        }
    }
    for (int b = 0; b < n; ++b) {
        if ((s.flags[b] & (kExcavated | kFixed | kDeformable)) || !(s.mass[b] > 0) || s.clump[b] != 0) continue;
        double w2 = kt[b] / s.mass[b];
        const double i_min = Eigen::SelfAdjointEigenSolver<Mat3>(s.inertia_body[b], Eigen::EigenvaluesOnly)
                                 .eigenvalues()
                                 .minCoeff();
        if (i_min > 0) w2 = std::max(w2, kr[b] / i_min);
        if (w2 > omega2) {
            omega2 = w2;
            worst = b;
        }
    }
    if (!(omega2 > 0)) return automatic > 0 ? automatic / m.settings.dtfrac : 0.0;
    if (block_out) *block_out = worst;
    return std::max(automatic, 2.0 / std::sqrt(omega2));
}

} // namespace odec
