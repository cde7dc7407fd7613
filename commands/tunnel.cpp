#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/tunnel.h"
#include "tunnel_axis.h"

#include <cmath>

namespace odec {

namespace {

// Blocks one 'tunnel' may leave in the model: a guard against a typing slip.
constexpr long kMaxBlocksAfterTunnel = 200000;

// Distance from x to the segment from p to q.
double distance_to_segment(const Vec3& x, const Vec3& p, const Vec3& q) {
    const Vec3 d = q - p;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((x - p).dot(d) / len2, 0.0, 1.0) : 0.0;
    return (x - (p + t * d)).norm();
}

} // namespace

const CommandSpec& tunnel_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("tunnel", 3, "cut blocks along a circular tunnel: its core, rings of blocks around it, joined");
        c.keyword("a", 1, "the start of the tunnel's axis").vec("x,y,z");
        c.keyword("b", 1, "the end of the tunnel's axis").vec("x,y,z");
        c.keyword("dip", 2, "with 'length': plunge of the axis, degrees below horizontal").real("d", 0, 90).defaults("0");
        c.keyword("dd", 2, "with 'length': trend of the axis, degrees clockwise from north (+y)")
            .real("a", -360, 360)
            .defaults("0");
        c.keyword("origin", 2, "with 'length': the point the lengths are measured from").vec("x,y,z").defaults("0,0,0");
        c.keyword("length", 3, "instead of 'a' and 'b': the axis runs from l1 to l2 along the direction 'dip' and "
                               "'dd' from 'origin'")
            .real("l1")
            .real("l2");
        c.keyword("radius", 3, "radius of the tunnel, m (its wall is a polygon with the circle's area)")
            .real("r", 0, kInf, Limit::Open);
        c.keyword("outer", 2, "radius of the outer edge of the last ring, m (a polygon with the circle's area)")
            .real("r", 0, kInf, Limit::Open)
            .defaults("3 radii");
        c.keyword("ntheta", 2, "sides of the tunnel's polygon, and blocks in each ring").integer("n", 3, 720).defaults("16");
        c.keyword("nrad", 2, "rings of blocks from the tunnel wall to the outermost ring").integer("m", 1, 1000).defaults("3");
        c.keyword("ratio", 3, "thickness of each ring over that of the ring inside it")
            .real("q", 0, kInf, Limit::Open)
            .defaults("ring radii growing geometrically");
        c.keyword("nseg", 2, "segments along the axis").integer("k", 1, 10000).defaults("1");
        c.keyword("group", 2, "group of the pieces inside the tunnel wall").word("name").defaults("tunnel");
        c.keyword("jmat", 2, "joint material of the contacts across the new cuts").integer("n", 1, 1000000);
        c.range("which blocks to cut: see 'help range' (hidden and excavated blocks are never cut)");
        c.describe("Deformable blocks are not cut (cut first, then zone). The pattern is that of 'poly tunnel': in the cross-section the tunnel wall is a regular polygon "
                   "of 'ntheta' sides with the area of the circle of 'radius', one corner on the horizontal plane "
                   "through the axis (on the x axis when the axis is vertical); around it lie 'nrad' rings, bounded by "
                   "larger polygons out to the one with the area of the circle of 'outer', each 'ratio' times as thick "
                   "as the one inside it. Between 'a' and 'b' (or 'length' l1 to l2 along 'dip' and 'dd' from "
                   "'origin'), every selected block that reaches into the wall or the rings is cut by planes across "
                   "the axis at the tunnel's ends (where they lie inside it) and between its 'nseg' segments, by the "
                   "planes through the axis at the polygon's corners (which run on to the block's own faces: beyond "
                   "the rings the block is left in wedges, so that every piece is convex; with an odd 'ntheta' the "
                   "plane through the first corner also runs through the opposite sector), and in each sector by "
                   "the sides of the wall and of every ring. The pieces inside the wall, one wedge per sector and "
                   "segment, join group 'tunnel' (or the 'group' given), so that 'excavate range group tunnel' opens "
                   "the hole; the other pieces keep their block's group, region and material. Every new cut is one "
                   "joined joint set, so the rock stays one mass across it; the block's own faces keep their joints. "
                   "A cut that would leave a piece thinner than a millionth of the block is not made ('print info' "
                   "counts them). Blocks the rings do not reach are left whole. A cut through a block of a clump "
                   "(a solid that is not convex, 'poly', one rigid body) ends the clump, as 'jset' does: its blocks "
                   "become blocks of their own, glued across the faces between them, and a line says so.");
        c.example("tunnel a (0,-1,0) b (0,11,0) radius 2 outer 6 nrad 3 nseg 4");
        c.example("tunnel dip 0 dd 90 origin 0,5,-20 length -50 50 radius 3 range z -40 0");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            auto loc_of = [&](const std::string& kw) { return a.has(kw) ? a.find(kw)->loc : a.loc; };
            // Sizes and coordinates within reach of doubles, as 'poly' takes them.
            constexpr double kMaxCoordinate = 1e9;
            for (const char* k : {"a", "b", "origin", "length", "radius", "outer"}) {
                for (const KeywordUse* u : a.all(k)) {
                    for (const Value& v : u->values) {
                        const double x = v.type == ValueType::Vec3 ? v.vec.cwiseAbs().maxCoeff() : std::abs(v.number);
                        if (x > kMaxCoordinate) {
                            fail(v.loc, num(x) + " is too large: 'tunnel' takes coordinates and sizes within " +
                                            num(kMaxCoordinate) + " m",
                                 {"odec works in metres; move the origin near the model"}, "tunnel");
                        }
                    }
                }
            }
            TunnelSpec s;
            read_tunnel_axis(a, a.loc, "tunnel", s);
            if (!a.has("radius")) fail(a.loc, "'tunnel' needs 'radius r'", {}, "tunnel");
            s.radius = a.real("radius");
            s.outer_radius = a.real_or("outer", 3 * s.radius);
            s.n_sides = a.has("ntheta") ? a.integer("ntheta") : 16;
            s.n_rings = a.has("nrad") ? a.integer("nrad") : 3;
            s.ratio = a.real_or("ratio", 0);
            s.n_segments = a.has("nseg") ? a.integer("nseg") : 1;
            std::string keyword;
            const std::string problem = tunnel_problem(s, false, keyword);
            if (!problem.empty()) {
                fail(loc_of(keyword == "b" && a.has("length") ? "length" : keyword), problem, {}, "tunnel");
            }

            // The blocks to cut, and a bound on the work before doing it: a block near the
            // tunnel may become (ends + segments x sectors x (rings + 2)) pieces.
            std::vector<int> targets;
            const double reach = equal_area_circumradius(s.outer_radius, s.n_sides);
            long near = 0;
            for (int b : select_blocks(m, a.range)) {
                if (m.blocks.flags[b] & (kHidden | kExcavated | kDeformable)) continue; // zones are made after cutting
                double radius = 0;
                for (const Vec3& v : m.blocks.shape[b].vertices) radius = std::max(radius, v.norm());
                if (distance_to_segment(m.blocks.centroid[b], s.a, s.b) > reach + radius) continue;
                targets.push_back(b);
                ++near;
            }
            const double per_block = 2.0 + static_cast<double>(s.n_segments) * s.n_sides * (s.n_rings + 2);
            const long limit = ctx.interp.limits.max_blocks;
            const double most = limit > 0 ? 20.0 * limit : 4.0 * kMaxBlocksAfterTunnel;
            if (per_block > kMaxBlocksAfterTunnel || near * per_block > most) {
                const std::string could = "could cut " + std::to_string(near) + " blocks into up to " +
                                          num(per_block) + " pieces each";
                fail(a.loc,
                     limit > 0 ? "this session allows at most " + std::to_string(limit) + " blocks: the tunnel " + could
                               : "this tunnel " + could + "; one 'tunnel' leaves at most " +
                                     std::to_string(kMaxBlocksAfterTunnel) + " blocks",
                     {"use fewer sides ('ntheta'), rings ('nrad') or segments ('nseg'), or cut part of the model "
                      "with 'range'"},
                     "tunnel");
            }
            double size = 0;
            for (int b = 0; b < m.blocks.size(); ++b) size = std::max(size, std::cbrt(m.blocks.volume[b]));
            const double sliver_tol = 1e-6 * std::max(size, 1e-3);
            const int tag = static_cast<int>(m.joint_planes.size()) + 1;
            const TunnelCutPlan plan = plan_tunnel_cut(m, s, targets, tag, sliver_tol);
            const long after = m.blocks.size() + plan.n_pieces() - static_cast<long>(plan.blocks.size());
            if (after > kMaxBlocksAfterTunnel) {
                fail(a.loc, "this tunnel would leave " + std::to_string(after) + " blocks; one 'tunnel' leaves at most " +
                                std::to_string(kMaxBlocksAfterTunnel),
                     {}, "tunnel");
            }
            if (limit > 0 && after > limit) {
                fail(a.loc, "this session allows at most " + std::to_string(limit) + " blocks: the tunnel would leave " +
                                std::to_string(after),
                     {}, "tunnel");
            }
            for (size_t k = 0; k < plan.blocks.size(); ++k) {
                const int b = plan.blocks[k];
                const int mat = m.blocks.material[b];
                const double rho = mat < static_cast<int>(m.materials.size()) ? m.materials[mat].density : 0.0;
                for (const Polyhedron& p : plan.pieces[k]) {
                    const std::string numbers = block_numbers_problem(mass_properties(p), rho);
                    if (!numbers.empty()) {
                        fail(a.loc, "a piece of block " + std::to_string(m.blocks.id[b]) + ": " + numbers,
                             {"odec works in metres, kilograms and seconds"}, "tunnel");
                    }
                }
            }
            if (plan.blocks.empty()) {
                warn(ctx, a.loc, "the tunnel reaches no block" + std::string(a.has_range ? " of the range" : "") +
                                     ", nothing changed");
                return;
            }

            // Everything is checked: cut.
            ++m.n_joint_sets;
            m.joint_planes.push_back(JointPlane{m.n_joint_sets, true, a.has("jmat") ? a.integer("jmat") : 0});
            const std::string core = a.has("group") ? a.text("group") : "tunnel";
            const int clumps_ended = apply_tunnel_cut(m, plan, m.group_index(core, true));
            if (!ctx.interp.quiet) {
                long in_core = 0;
                for (const auto& layers : plan.layers) {
                    for (int l : layers) in_core += l == 0;
                }
                ctx.out << "tunnel: cut " << plan.blocks.size() << " blocks into " << plan.n_pieces() << " ("
                        << in_core << " inside the wall, group '" << core << "'), joined; " << plan.slivers_skipped
                        << " cuts skipped as slivers; " << m.blocks.size() << " blocks\n";
                if (clumps_ended > 0) {
                    ctx.out << "tunnel: the cut went through " << clumps_ended << " clump"
                            << (clumps_ended == 1 ? "" : "s") << " (a solid that is not convex, one rigid body): "
                            << (clumps_ended == 1 ? "its" : "their")
                            << " blocks are blocks of their own now, glued across the faces between them\n";
                }
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
