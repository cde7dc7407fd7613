// What the contact update makes once per contact between rigid blocks before its sub-contacts
// step: the contact's axes (its normal n and the shear axes e1, e2 of shear_axes), and on them
// the relative motion of the blocks over the last step and the maps from each block's body frame.
// Made for many contacts at once, lane by lane in fixed-size batches, so that the compiler runs
// several contacts in one vector instruction (the same operations in the same order in every
// lane: a contact's numbers do not depend on its neighbours in the batch, nor on the machine's
// vector width). Every number is the bits Eigen's expressions of contact.h and joint_law.cpp
// give for the same quantity (three-term sums as Eigen adds them, a0 + (a1 + a2)); a test
// compares them.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace odec {

struct ContactAxesBatch {
    static constexpr int kSize = 16; // contacts per batch
    // ---- in, per contact ----
    std::int32_t nu[kSize], nv[kSize];   // its normal's code (NormalCode)
    // Block a's, then block b's: the axis of its turn over the last step, the sine and 1 - cosine
    // of the angle (joint_law.cpp, update_contacts), its centroid's displacement over the step,
    // its rotation matrix (column-major, as Eigen keeps it) and its centroid.
    double k[2][3][kSize], sin[2][kSize], cos1[2][kSize], disp[2][3][kSize], rot[2][9][kSize], centroid[2][3][kSize];
    // ---- out, per contact ----
    double n[3][kSize], e1[3][kSize], e2[3][kSize]; // the axes, rows of ax
    double cab[3][kSize];        // b's centroid from a's (world)
    double cab_ax[3][kSize];     // the same on the axes
    double du0[3][kSize];        // ax (d_b - d_a - T_b cab)
    double dt_ax[9][kSize];      // ax (T_b - T_a) ax^T, row-major
    double to[2][9][kSize];      // ax R_a and ax R_b, row-major
};

// Fills the outputs of the first `count` contacts of the batch from their inputs.
void make_contact_axes(ContactAxesBatch& batch, int count);

// The step of the joint law (joint_law.cpp, joint_step_on_axes) at the sub-contacts of a batch's
// contacts in its plain case, the one of almost every sub-contact at almost every step: touching
// before the step (not open, new or fresh), in dynamic mode without the energy account. Lane by
// lane over the contacts, sub-contact by sub-contact within each (kMaxSubs at most), with the
// scalar law's operations in its order, so that a contact gets the very bits the scalar law
// would give it. A contact where any sub-contact opens or slips is marked `slow`: its results
// are dropped and the scalar law steps it (nothing here writes the contact set).
struct ContactSubBatch {
    static constexpr int kSize = ContactAxesBatch::kSize;
    static constexpr int kMaxSubs = 8;
    // ---- in, per contact ----
    double n_subs[kSize];                       // how many (1 .. kMaxSubs), 0: not in the batch
    double kn[kSize], ks[kSize], coh[kSize], ten[kSize], tan_phi[kSize], tan_res[kSize];
    double joined[kSize];                       // 1: glued, 0: not
    // ---- in, per sub-contact (slot j of contact l at [j][l]) ----
    double local[kMaxSubs][3][kSize];           // its point in its block's body frame
    double of_b[kMaxSubs][kSize];               // 1: a point of block b, 0: of block a
    double un[kMaxSubs][kSize], dil[kMaxSubs][kSize], ss[kMaxSubs][2][kSize], area[kMaxSubs][kSize];
    double failed[kMaxSubs][kSize];             // 1: kSubFailed
    // ---- out, per sub-contact ----
    double un_new[kMaxSubs][kSize], dus[kMaxSubs][2][kSize], ss_new[kMaxSubs][2][kSize];
    // ---- out, per contact ----
    // The sums on the world axes (put_on_blocks in joint_law.cpp): the force on b, its moment
    // about a's centroid (a takes the opposite of both), and about b's own (that less cab x fb).
    double fb[3][kSize], ma[3][kSize], mb[3][kSize];
    double scale[kSize];                        // the sum of the sub-contacts' force magnitudes
    double slow[kSize];                         // 1: some sub-contact opens or slips
};

// Steps the plain sub-contacts of the first `count` contacts of `subs`, on the axes of `axes`.
void step_plain_subs(const ContactAxesBatch& axes, ContactSubBatch& subs, int count);

// Each block's turn over the last step (update_contacts), for blocks [b0, b1), four at a time:
// w its angular velocity (zero for a block that has not moved: still[b] != 0), the axis
// w / |w| (zero where |w| dt is not above zero), and with the angle t = |w| dt, dynamic: the
// sine and 1 - cosine of t from the half-angle's (half_turn), 2 sin(t/2) cos(t/2) and
// 2 sin(t/2)^2; static: t and 0.
void make_block_turns(const Eigen::Vector3d* ang_vel, const std::uint8_t* still, int b0, int b1, double dt, bool dynamic,
                      Eigen::Vector3d* axis, double* sin, double* cos1);

} // namespace odec
