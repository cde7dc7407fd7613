#include "commands.h"
#include "common.h"
#include "engine/jset.h"

#include <cmath>
#include <limits>

namespace odec {

namespace {

// A session with a block limit (Interpreter::Limits) refuses, before cutting, a joint set
// that could leave more blocks than the limit, or take more than 20 times that many
// plane-block trials: every plane that crosses a block's extent counts as a cut.
void check_block_limit(CommandContext& ctx, const Args& a, const JointSetSpec& s) {
    const Model& m = ctx.model;
    const long limit = ctx.interp.limits.max_blocks;
    const Vec3 n = plane_normal(s.dip, s.dd);
    const double d0 = n.dot(s.origin);
    const double planes = std::max(s.number, 1);
    double blocks = m.blocks.size();
    for (int b : select_blocks(m, a.range)) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        const Mat3 rot = m.blocks.orientation[b].toRotationMatrix();
        for (const Vec3& v : m.blocks.shape[b].vertices) {
            const double t = n.dot(m.blocks.centroid[b] + rot * v);
            lo = std::min(lo, t);
            hi = std::max(hi, t);
        }
        // Planes k = 0 .. planes-1 at d0 + (k - (planes-1)/2) spacing.
        double crossing = planes;
        if (s.spacing > 0 && std::isfinite(lo) && std::isfinite(hi)) {
            const double first = std::max(0.0, std::ceil((lo - d0) / s.spacing + 0.5 * (planes - 1)));
            const double last = std::min(planes - 1, std::floor((hi - d0) / s.spacing + 0.5 * (planes - 1)));
            crossing = last >= first ? last - first + 1 : 0;
            if (!std::isfinite(crossing)) crossing = planes;
        }
        blocks += crossing;
    }
    if (blocks > limit || planes * blocks > 20.0 * limit) {
        fail(a.loc, "this session allows at most " + std::to_string(limit) + " blocks: the joint set could make " +
                        num(blocks) + " blocks with " + num(planes) + " planes",
             {}, "jset");
    }
}

} // namespace

const CommandSpec& jset_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("jset", 3, "cut blocks by a set of parallel joint planes");
        c.keyword("dip", 2, "dip of the planes, degrees below horizontal").real("d", 0, 90);
        c.keyword("dd", 2, "dip direction, degrees clockwise from north (+y)").real("a", -360, 360);
        c.keyword("origin", 2, "a point on the middle plane").vec("x,y,z").defaults("0,0,0");
        c.keyword("spacing", 2, "distance between neighbouring planes, m").real("s", 0, kInf, Limit::Open);
        c.keyword("number", 2, "number of planes, placed symmetrically about the origin").integer("n", 1, 100000).defaults("1");
        c.keyword("persistence", 2, "chance that a plane cuts a block it crosses").real("p", 0, 1, Limit::Open).defaults("1");
        c.keyword("seed", 2, "seed of the persistence draws (same seed, same cuts)").integer("n", 0).defaults("1");
        c.keyword("join", 2, "glue the two sides of every new cut (no slip, no opening)");
        c.keyword("jmat", 4, "joint material of the contacts across these planes").integer("n", 1, 1000000);
        c.range("which blocks to cut: see 'help range' (hidden blocks are never cut)");
        c.describe("Each plane cuts every selected block it crosses into two. A cut that would leave a "
                   "piece thinner than a millionth of the block is not made (it is counted; 'print info' "
                   "shows how many). The orientation convention: the planes' upward normal is "
                   "(sin dip sin dd, sin dip cos dd, cos dip), x east, y north, z up. Deformable blocks are "
                   "not cut (their zones would not follow): cut the rock first, then zone it. A plane through "
                   "a block of a clump (a solid that is not convex, 'poly', one rigid body) ends the clump, "
                   "as a cut through a joined group of rigid blocks parts it in 3DEC: its blocks become "
                   "blocks of their own, glued across the faces between them (their joined joint set), "
                   "and a line says so.");
        c.example("jset dip 60 dd 90 origin 0,0,0 spacing 2 number 5");
        c.example("jset dip 0 dd 0 origin 0,0,5 join");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (!a.has("dip")) fail(a.loc, "'jset' needs 'dip d' (and 'dd a')", {}, "jset");
            JointSetSpec s;
            s.dip = a.real("dip");
            s.dd = a.real_or("dd", 0);
            if (a.has("origin")) s.origin = a.vec("origin");
            s.number = a.has("number") ? a.integer("number") : 1;
            s.spacing = a.real_or("spacing", 0);
            if (s.number > 1 && !a.has("spacing")) {
                fail(a.find("number")->loc, "more than one plane needs 'spacing s'", {}, "jset");
            }
            s.persistence = a.real_or("persistence", 1.0);
            s.seed = static_cast<std::uint64_t>(a.real_or("seed", 1));
            s.join = a.has("join");
            // Size of the model, for the sliver tolerance.
            double size = 0;
            for (int b = 0; b < m.blocks.size(); ++b) size = std::max(size, std::cbrt(m.blocks.volume[b]));
            const double sliver_tol = 1e-6 * std::max(size, 1e-3);
            if (s.number > 1 && s.spacing < sliver_tol) {
                fail(a.find("spacing")->values[0].loc,
                     "planes " + num(s.spacing) + " m apart would cut only slivers: the spacing must be at least " +
                         num(sliver_tol) + " m here",
                     {}, "jset");
            }
            // Planes that cross the blocks (the others cut nothing): each may cut every block in
            // its way, and the cost grows with planes times blocks, so a few thousand is the most.
            {
                const Vec3 nrm = plane_normal(s.dip, s.dd);
                double lo = kInf, hi = -kInf;
                for (int b : select_blocks(m, a.range)) {
                    for (const Vec3& v : m.blocks.shape[b].vertices) {
                        const double h = nrm.dot(m.blocks.centroid[b] + m.blocks.orientation[b] * v);
                        lo = std::min(lo, h);
                        hi = std::max(hi, h);
                    }
                }
                const double d0 = nrm.dot(s.origin);
                long crossing = 0;
                if (lo <= hi) {
                    const double half = 0.5 * (s.number - 1);
                    // Planes k with lo <= d0 + (k - half) spacing <= hi.
                    const double k_lo = s.spacing > 0 ? std::ceil((lo - d0) / s.spacing + half) : 0;
                    const double k_hi = s.spacing > 0 ? std::floor((hi - d0) / s.spacing + half) : s.number - 1;
                    const double from = std::max(0.0, k_lo), to = std::min<double>(s.number - 1, k_hi);
                    if (to >= from) crossing = static_cast<long>(to - from + 1);
                }
                constexpr long kMaxCrossing = 5000;
                if (crossing > kMaxCrossing) {
                    fail(a.find("number")->values[0].loc,
                         std::to_string(crossing) + " of these planes cross the blocks; one 'jset' may cut with at most " +
                             std::to_string(kMaxCrossing),
                         {"use a larger spacing, or cut part of the model at a time with 'range'"}, "jset");
                }
            }
            if (ctx.interp.limits.max_blocks > 0) check_block_limit(ctx, a, s);
            const size_t first_plane = m.joint_planes.size();
            const CutReport r = cut_joint_set(m, s, a.range, sliver_tol);
            if (a.has("jmat")) {
                for (size_t k = first_plane; k < m.joint_planes.size(); ++k) m.joint_planes[k].jmat = a.integer("jmat");
            }
            if (!ctx.interp.quiet) {
                ctx.out << "joint set " << m.n_joint_sets << ": " << r.planes << " planes, " << r.blocks_cut
                        << " cuts, " << r.slivers_skipped << " skipped as slivers; " << m.blocks.size()
                        << " blocks\n";
                if (r.clumps_ended > 0) {
                    ctx.out << "jset: the planes cut " << r.clumps_ended << " clump" << (r.clumps_ended == 1 ? "" : "s")
                            << " (a solid that is not convex, one rigid body): "
                            << (r.clumps_ended == 1 ? "its" : "their")
                            << " blocks are blocks of their own now, glued across the faces between them\n";
                }
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
