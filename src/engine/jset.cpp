// Joint sets: cutting the rock mass into blocks.
//
// Planes are applied one after another, and each plane is tried against every block of the
// selection as it stands, including the pieces earlier planes of the same set made; so a
// set of n planes through one block gives n + 1 blocks, not two. A block is cut in world
// coordinates (it may have rotated since it was made), and both pieces are stored with the
// body frame equal to the world axes: that frame is as good as any other for a rigid
// block, and it saves carrying the parent's rotation into shapes that no longer have its
// symmetry. The displacement records carry over exactly: each piece's reference orientation
// (at the last 'reset disp') is re-expressed in its new frame and its centroid displacement is
// that of the parent's material point there, and point histories follow their material point
// into the piece that holds it (replace_by_pieces). The cut is
// made on the shape turned to world axes but still centred on the block's centroid (the
// plane shifted to match): models often sit at survey coordinates millions of metres from
// the origin, where absolute vertex positions would keep only a few digits below a metre.
//
// Each piece inherits the parent's rigid-body motion, so its velocity is the parent's
// velocity at the piece's own centroid (v + w x (c_piece - c_parent)); a spinning block cut
// in two does not jerk. An applied load is shared between the pieces by volume, so the
// total load on the rock mass is the same after the cut.
//
// Persistence draws come from a splitmix64 stream seeded by the spec, consumed once per
// crossing of a plane and a block in a fixed order (planes in order, blocks in index
// order), so the same input always makes the same blocks. No std::random distribution is
// used: their output may differ between standard libraries.
#include "engine/jset.h"

#include <algorithm>
#include <cmath>

#include "engine/blocks.h"
#include "engine/clump.h"

namespace odec {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct SplitMix64 {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1) from the top 53 bits.
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
};

} // namespace

double sin_deg(double a) {
    double r = std::fmod(a, 360.0);
    if (r < 0) r += 360.0;
    if (r == 0 || r == 180) return 0;
    if (r == 90) return 1;
    if (r == 270) return -1;
    return std::sin(r * (kPi / 180.0));
}

double cos_deg(double a) { return sin_deg(a + 90.0); }

Vec3 dip_vector(double dip, double dd) {
    const double cd = cos_deg(dip);
    return Vec3(cd * sin_deg(dd), cd * cos_deg(dd), -sin_deg(dip));
}

Vec3 plane_normal(double dip, double dd) {
    const double sd = sin_deg(dip);
    return Vec3(sd * sin_deg(dd), sd * cos_deg(dd), cos_deg(dip));
}

CutReport cut_joint_set(Model& m, const JointSetSpec& spec, const Range& r, double sliver_tol) {
    CutReport rep;
    const int set = ++m.n_joint_sets;
    const Vec3 n = plane_normal(spec.dip, spec.dd);
    const double d0 = n.dot(spec.origin);
    const int number = std::max(spec.number, 0);
    SplitMix64 rng{spec.seed};

    std::vector<int> targets, cut_clumps;
    for (int b : select_blocks(m, r)) {
        // Deformable blocks are not cut: their zones would not follow (cut first, then zone).
        if (!(m.blocks.flags[b] & (kHidden | kExcavated | kDeformable))) targets.push_back(b);
    }
    for (int k = 0; k < number; ++k) {
        const double d = d0 + (k - 0.5 * (number - 1)) * spec.spacing;
        m.joint_planes.push_back(JointPlane{set, spec.join, 0});
        const int tag = static_cast<int>(m.joint_planes.size());
        ++rep.planes;
        const size_t n_targets = targets.size();
        for (size_t t = 0; t < n_targets; ++t) {
            const int b = targets[t];
            const Vec3 c0 = m.blocks.centroid[b];
            Polyhedron turned = m.blocks.shape[b];
            const Mat3 rot = m.blocks.orientation[b].toRotationMatrix();
            for (Vec3& x : turned.vertices) x = rot * x;
            Polyhedron lo, hi;
            SplitOutcome why = SplitOutcome::Missed;
            split_by_plane(turned, n, d - n.dot(c0), sliver_tol, tag, lo, hi, &why);
            if (why == SplitOutcome::Sliver) ++rep.slivers_skipped;
            if (why != SplitOutcome::Split) continue;
            if (spec.persistence < 1.0 && !(rng.uniform() < spec.persistence)) continue;

            const std::vector<int> pieces = replace_by_pieces(m, b, {lo, hi}, c0);
            if (m.blocks.clump[b] != 0) cut_clumps.push_back(b);
            const int a = pieces[1];
            targets.push_back(a);
            ++rep.blocks_cut;
        }
    }
    // A cut through a piece of a clump ends the clump (clump.h): its pieces become blocks of
    // their own, glued across the faces between them, and the new piece is one of them.
    rep.clumps_ended = dissolve_clumps(m, cut_clumps);
    m.slivers_skipped += rep.slivers_skipped;
    if (rep.blocks_cut > 0) {
        // Contacts name vertices and faces of the old shapes.
        m.contacts.clear();
        refresh_world_vertices(m);
    }
    m.geometry_changed = true;
    return rep;
}

} // namespace odec
