// Cutting blocks by a joint set: a family of parallel planes.
#pragma once

#include <cstdint>

#include "engine/model.h"
#include "engine/range.h"

namespace odec {

struct JointSetSpec {
    double dip = 0;                 // deg below horizontal, 0..90
    double dd = 0;                  // deg, dip direction clockwise from north (+y) toward east (+x)
    Vec3 origin = Vec3::Zero();     // m, a point on the middle plane
    double spacing = 0;             // m between neighbouring planes (used when number > 1)
    int number = 1;                 // planes, placed symmetrically about origin
    double persistence = 1.0;       // in (0, 1]: chance that a plane cuts a block it crosses
    bool join = false;              // the two sides of each cut are glued
    std::uint64_t seed = 1;         // drives persistence; same seed, same cuts
};

struct CutReport {
    int planes = 0;           // planes placed (each appended to Model::joint_planes)
    int blocks_cut = 0;       // cuts made (each adds one block)
    int slivers_skipped = 0;  // cuts not made because a piece would be thinner than sliver_tol
    int clumps_ended = 0;     // clumps a cut went through: their pieces are blocks of their own now
};

// Sine and cosine of an angle in degrees, exact at multiples of 90 degrees.
double sin_deg(double degrees);
double cos_deg(double degrees);

// Unit vector pointing down the dip of a plane of this dip and dip direction (degrees), or
// along a line of this plunge (dip) and trend (dd): (sin dd cos dip, cos dd cos dip, -sin dip).
// Exact at multiples of 90 degrees, so that dip 0 dd 0 gives exactly (0, 1, 0).
Vec3 dip_vector(double dip, double dd);

// Upward unit normal of a plane of this dip and dip direction (degrees); exact at multiples
// of 90 degrees, so that dip 90 dd 90 gives exactly (1, 0, 0).
Vec3 plane_normal(double dip, double dd);

// Cut the blocks that r selects (hidden and excavated ones excepted) by the planes of
// spec. Pieces made by one plane are cut again by the later planes of the same set.
// The part below a plane keeps the block's index and id, the part above becomes a new
// block; both keep the block's attributes and motion. Both faces of each cut carry the
// plane's joint tag. Cuts that would leave a piece thinner than sliver_tol are skipped.
CutReport cut_joint_set(Model& m, const JointSetSpec& spec, const Range& r, double sliver_tol);

} // namespace odec
