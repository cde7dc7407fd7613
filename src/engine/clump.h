// Clumps: a rigid solid that is not convex, moving as one rigid body.
//
// Every block is convex (contact detection, cutting and the joint law rely on it), so 'poly'
// makes a solid that is not convex (an L-shaped block, a voussoir whose intrados is bent
// inward) of convex pieces that fill it. When the solid is rigid its pieces form a clump
// (BlockSet::clump, named by the id of its first piece): one rigid body with one mass (the sum
// of the pieces'), one centroid (their mass centroid), one inertia tensor (the sum of the
// pieces' about that centroid), one velocity and one spin. There is no contact between two
// pieces of one clump. Each step the integration stage sums the forces on every piece (their
// weights, applied loads and contact forces) into one force and one moment about the clump's
// centroid, moves the clump once, and places each piece where the clump's rigid motion takes it:
// its centroid turned about the clump's centroid, its orientation turned by the same rotation,
// its velocity the clump's at its centroid. Every piece thus keeps its own id, shape, contacts,
// loads and histories, and each reads as the part of the rigid body it is.
//
// Nothing of the clump is stored but the membership: its mass, centroid, velocity and spin are
// read from its pieces when needed (their momentum and angular momentum), which are always
// consistent with one rigid motion.
//
// What acts on one piece acts on the whole: 'fix', 'free', 'ini' and the velocity boundary
// conditions are given to every piece of a clump a range touches; a load at a point of a piece
// acts at that material point. 'delete', 'excavate' and 'fill' take whole clumps. A cut through
// a piece ('jset') or zoning ('gen edge') ends the clump: its pieces become blocks of their own,
// glued across the faces between them by their joined joint set, as before they were a clump.
#pragma once

#include <string>
#include <vector>

#include "engine/model.h"

namespace odec {

struct EnergyStep;

// The clumps of a model: for each, its pieces (block indices, ascending); clumps in the order
// of their names.
struct ClumpList {
    std::vector<int> key;      // (n_clumps) the clump's name (BlockSet::clump)
    std::vector<int> offset;   // (n_clumps + 1) first piece of each clump in `pieces`
    std::vector<int> pieces;   // block indices
    int size() const { return static_cast<int>(key.size()); }
};
ClumpList list_clumps(const BlockSet& s);
// The same into `out`, reusing its memory (the cycle allocates nothing once it runs).
void list_clumps(const BlockSet& s, ClumpList& out);

// The pieces of block b's clump (ascending), or {b} when b is alone.
std::vector<int> clump_pieces(const BlockSet& s, int b);

// Add to a sorted list of block indices every other piece of the clumps it touches. Returns
// how many were added; `clumps` (may be null) receives how many clumps were completed so.
int complete_clumps(const BlockSet& s, std::vector<int>& blocks, int* clumps = nullptr);

// End the clumps of these blocks: their pieces become blocks of their own (glued to each other
// by the joined joint set between them when contacts are next detected). Returns how many
// clumps ended.
int dissolve_clumps(Model& m, const std::vector<int>& blocks);

// The rigid body a clump is, read from its pieces.
struct ClumpBody {
    double mass = 0;                      // kg, real
    Vec3 centroid = Vec3::Zero();         // m, of the real masses (of the volumes when massless)
    Vec3 vel = Vec3::Zero();              // m/s, of the centroid, from the momentum
    Vec3 spin = Vec3::Zero();             // rad/s
    Mat3 inertia = Mat3::Zero();          // kg m^2, real, about the centroid, world axes
};
// `vel` and `spin` (may be null): the pieces' velocities and spins to read instead of the ones
// stored (vel[i] for pieces[i]).
ClumpBody clump_body(const BlockSet& s, const int* pieces, int n, const Vec3* vel = nullptr,
                     const Vec3* spin = nullptr);

// Give a clump the velocity `vel` at its centroid and the spin `spin`: every piece the velocity
// of the rigid motion at its own centroid (as 'ini' gives one, at t).
void set_clump_motion(BlockSet& s, const int* pieces, int n, const Vec3& vel, const Vec3& spin);

// Set component k of the velocity at t of piece b's centroid (spin false) or of the spin (spin
// true), the clump of b following as one rigid body: the other components, b's centroid velocity
// when the spin changes (as for a block alone, it turns about its own centroid) and the half
// step the integration holds the velocities back by are kept (FISH's b_xvel, b_xrvel ...).
void set_clump_component_at_t(Model& m, int b, int k, double value, bool spin);

// The integration of the clumps (part of the integration stage): each moves as one rigid body
// under the sum of its pieces' forces and their moments about its centroid, damped as a block
// is. Adds the step's energy increments and adaptive damping's sums when given.
// Returns the index of a piece whose motion became non-finite, or -1.
int integrate_clumps(Model& m, const ClumpList& clumps, double dt, EnergyStep* energy, AutoDampingSums* sums);

// Why the clumps of a model are not consistent (for restore's checks), or "".
std::string clumps_problem(const BlockSet& s);

} // namespace odec
