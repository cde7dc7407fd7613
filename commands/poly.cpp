#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/tunnel.h"
#include "tunnel_axis.h"

#include <cstdio>
#include <limits>

namespace odec {

namespace {

std::vector<Vec3> points_of(const KeywordUse& u) {
    std::vector<Vec3> pts;
    for (const Value& v : u.values) {
        if (v.type == ValueType::Vec3) pts.push_back(v.vec);
    }
    return pts;
}

// Geometric tolerance for merging vertices and checking planarity: relative to the size.
double tolerance_for(const std::vector<Vec3>& pts) {
    Vec3 lo = pts.front(), hi = pts.front();
    for (const Vec3& p : pts) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return 1e-6 * std::max(1e-3, (hi - lo).norm());
}

// A looser tolerance for coordinates written with few digits: scripts exported by other
// programs round each coordinate to 5 to 7 significant digits, so a vertex may be off its
// face's plane by a few units of the last digit of the largest coordinate.
double rounding_tolerance_for(const std::vector<Vec3>& pts) {
    double big = 0;
    for (const Vec3& p : pts) big = std::max(big, p.cwiseAbs().maxCoeff());
    return std::max(tolerance_for(pts), 2e-5 * big);
}

// Input that is convex only nearly (a voussoir whose curved face was given as a polygon,
// coordinates rounded to a few digits) is taken as the convex hull of its vertices when no
// vertex lies deeper inside that hull than this fraction of the block's size.
constexpr double kHullDepthFraction = 0.02;

// The volume a solid given by its faces encloses (m^3): each face, turned to face away from
// `centre`, adds the cone from the origin to it (the divergence theorem). Exact for a closed
// solid that is star-shaped about `centre`, as nearly convex input is.
double enclosed_volume(const std::vector<std::vector<Vec3>>& faces, const Vec3& centre) {
    double v = 0;
    for (const auto& f : faces) {
        Vec3 area = Vec3::Zero(), mid = Vec3::Zero();
        for (size_t k = 0; k < f.size(); ++k) {
            area += 0.5 * f[k].cross(f[(k + 1) % f.size()]);
            mid += f[k];
        }
        mid /= static_cast<double>(f.size());
        const double sign = area.dot(mid - centre) >= 0 ? 1.0 : -1.0;
        v += sign * mid.dot(area) / 3.0;
    }
    return v;
}

// Replace a build that failed on convexity by the convex hull of the vertices when the hull
// adds little: at most this fraction of its volume (a voussoir whose curved face was given
// as a polygon adds about 1 %). Says how much it added. False (the original error stands)
// when the input is further from convex.
constexpr double kHullAddedFraction = 0.05;

bool accept_hull(CommandContext& ctx, const std::vector<std::vector<Vec3>>& faces, const std::vector<Vec3>& all,
                 const std::string& what, Polyhedron& p) {
    Polyhedron hull;
    std::string error;
    if (!make_convex_hull(all, tolerance_for(all), hull, error)) return false;
    const MassProperties mp = mass_properties(hull);
    const double given = enclosed_volume(faces, mp.centroid);
    const double added = mp.volume - given;
    if (!(given > 0) || added > kHullAddedFraction * mp.volume) return false;
    p = std::move(hull);
    {
        char buf[240];
        std::snprintf(buf, sizeof buf, "%.3g m^3 (%.2g %% of its volume)", std::max(added, 0.0),
                      100.0 * std::max(added, 0.0) / mp.volume);
        ctx.interp.err << "warning: " << what << ": the block is taken as the convex hull of its vertices, which adds "
                       << buf << "\n";
    }
    return true;
}

// Blocks one 'poly tunnel' may make: a guard against a typing slip (nseg 10000 ntheta 720).
constexpr long kMaxTunnelBlocks = 100000;

// `poly tunnel`: check everything, build every block, then change the model.
void make_tunnel(CommandContext& ctx, const Args& a) {
    Model& m = ctx.model;
    const SourceLoc where = a.find("tunnel")->loc;
    auto loc_of = [&](const std::string& kw) { return a.has(kw) ? a.find(kw)->loc : where; };
    TunnelSpec s;
    read_tunnel_axis(a, where, "poly", s);
    if (!a.has("radius")) fail(where, "'tunnel' needs 'radius r'", {}, "poly");
    s.radius = a.real("radius");
    s.n_sides = a.has("ntheta") ? a.integer("ntheta") : 16;
    s.n_rings = a.has("nrad") ? a.integer("nrad") : 4;
    s.ratio = a.real_or("ratio", 0);
    s.n_segments = a.has("nseg") ? a.integer("nseg") : 1;
    if (a.has("box")) {
        s.half_u = a.real("box", 0);
        s.half_v = a.find("box")->values.size() > 1 ? a.real("box", 1) : s.half_u;
    } else {
        s.half_u = s.half_v = 5 * s.radius;
    }
    std::string keyword;
    const std::string problem = tunnel_problem(s, true, keyword);
    if (!problem.empty()) fail(loc_of(keyword == "b" && a.has("length") ? "length" : keyword), problem, {}, "poly");

    const long count = static_cast<long>(s.n_segments) * (1 + static_cast<long>(s.n_sides) * s.n_rings);
    if (count > kMaxTunnelBlocks) {
        fail(where, "this tunnel would make " + std::to_string(count) + " blocks; one 'poly tunnel' makes at most " +
                        std::to_string(kMaxTunnelBlocks),
             {"use fewer sides ('ntheta'), rings ('nrad') or segments ('nseg')"}, "poly");
    }
    const long limit = ctx.interp.limits.max_blocks;
    if (limit > 0 && m.blocks.size() + count > limit) {
        fail(where, "this session allows at most " + std::to_string(limit) + " blocks: the tunnel would make " +
                        std::to_string(count) + " more",
             {}, "poly");
    }
    // Region n + k for ring k: the parser keeps integers within 2e9, rings within 1000.
    const int region = a.has("region") ? a.integer("region") : 0;
    const int material = a.has("material") ? a.integer("material") : 1;
    const std::string core_group = a.has("group") ? a.text("group") : "tunnel";

    std::vector<TunnelBlock> blocks;
    std::string error;
    const int tag = static_cast<int>(m.joint_planes.size()) + 1;
    if (!make_tunnel_blocks(s, tag, blocks, error)) fail(where, error, {}, "poly");
    const double rho = material < static_cast<int>(m.materials.size()) ? m.materials[material].density : 0.0;
    for (const TunnelBlock& blk : blocks) {
        const std::string numbers = block_numbers_problem(mass_properties(blk.shape), rho);
        if (!numbers.empty()) fail(where, numbers, {"odec works in metres, kilograms and seconds"}, "poly");
    }

    // Everything is checked: change the model. The faces between the blocks belong to one
    // joined joint set of their own, so that the blocks act as one mass.
    ++m.n_joint_sets;
    m.joint_planes.push_back(JointPlane{m.n_joint_sets, true, a.has("jmat") ? a.integer("jmat") : 0});
    std::vector<int> group(s.n_rings + 1);
    group[0] = m.group_index(core_group, true);
    for (int k = 1; k <= s.n_rings; ++k) group[k] = m.group_index(core_group + "_ring" + std::to_string(k), true);
    for (const TunnelBlock& blk : blocks) {
        const int b = add_block(m, blk.shape, region + blk.layer, group[blk.layer], material);
        if (a.has("cons")) m.blocks.cons[b] = static_cast<std::uint8_t>(a.integer("cons"));
    }
    if (!ctx.interp.quiet) {
        const std::string last = std::to_string(s.n_rings);
        const bool many = s.n_rings > 1;
        ctx.out << "tunnel: " << blocks.size() << " blocks, joined: in each of " << s.n_segments << " segment"
                << (s.n_segments == 1 ? "" : "s") << " the core (group '" << core_group << "', region " << region
                << ") and " << s.n_rings << (many ? " rings" : " ring") << " of " << s.n_sides << " (group"
                << (many ? "s '" : " '") << core_group << "_ring1'" << (many ? " to '" + core_group + "_ring" + last + "'" : "")
                << (many ? ", regions " : ", region ") << region + 1
                << (many ? " to " + std::to_string(region + s.n_rings) : "") << ")\n";
    }
}

} // namespace

const CommandSpec& poly_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("poly", 4, "create a rigid convex polyhedral block");
        c.keyword("brick", 2, "axis-aligned box from x1 to x2, y1 to y2, z1 to z2")
            .real("x1").real("x2").real("y1").real("y2").real("z1").real("z2")
            .in_choice(1);
        c.keyword("prism", 2, "prism between polygon 'a' and its translated copy 'b'").in_choice(1);
        c.keyword("a", 1, "with 'prism': the vertices of one end, in order; with 'tunnel': the start of the axis")
            .vec("v").repeat();
        c.keyword("b", 1, "with 'prism': the vertices of the other end, in order; with 'tunnel': the end of the axis")
            .vec("v").repeat();
        c.keyword("face", 2, "one face of a general convex polyhedron: its vertices in order (repeat 'face' "
                             "for every face)")
            .integer("id", 1).labelled().optional()
            .vec("v").repeat()
            .many()
            .in_choice(1);
        c.keyword("tetra", 2, "tetrahedron with these four corners").vec("v1").vec("v2").vec("v3").vec("v4").in_choice(1);
        c.keyword("tunnel", 2, "a box of rock around a straight tunnel, as joined convex blocks, the tunnel's core "
                               "included (see below)")
            .in_choice(1);
        c.keyword("radius", 3, "with 'tunnel': radius of the tunnel, m (its wall is a polygon with the circle's area)")
            .real("r", 0, kInf, Limit::Open);
        c.keyword("box", 2, "with 'tunnel': half-width w of the box across the axis and its half-height h, m")
            .real("w", 0, kInf, Limit::Open)
            .real("h", 0, kInf, Limit::Open)
            .optional("w")
            .defaults("5 radii");
        c.keyword("ntheta", 2, "with 'tunnel': sides of the tunnel's polygon, and blocks in each ring")
            .integer("n", 3, 720)
            .defaults("16");
        c.keyword("nrad", 2, "with 'tunnel': rings of blocks from the tunnel wall to the box").integer("m", 1, 1000).defaults("4");
        c.keyword("ratio", 3, "with 'tunnel': thickness of each ring over that of the ring inside it")
            .real("q", 0, kInf, Limit::Open)
            .defaults("ring radii growing geometrically");
        c.keyword("nseg", 2, "with 'tunnel': segments along the axis").integer("k", 1, 10000).defaults("1");
        c.keyword("dip", 2, "with 'tunnel' and 'length': plunge of the axis, degrees below horizontal")
            .real("d", 0, 90)
            .defaults("0");
        c.keyword("dd", 2, "with 'tunnel' and 'length': trend of the axis, degrees clockwise from north (+y)")
            .real("a", -360, 360)
            .defaults("0");
        c.keyword("origin", 2, "with 'tunnel' and 'length': the point the lengths are measured from")
            .vec("x,y,z")
            .defaults("0,0,0");
        c.keyword("length", 3, "with 'tunnel', instead of 'a' and 'b': the axis runs from l1 to l2 along the "
                               "direction 'dip' and 'dd' from 'origin'")
            .real("l1")
            .real("l2");
        c.keyword("jmat", 2, "with 'tunnel': joint material of the contacts between its blocks").integer("n", 1, 1000000);
        c.keyword("region", 3, "region number of the new block, for 'range region' (with 'tunnel': of the core; "
                               "ring k gets n + k)")
            .integer("n", 0)
            .defaults("0");
        c.keyword("group", 2, "group name of the new block (with 'tunnel': of the core, default 'tunnel'; ring k "
                              "gets name_ring<k>)")
            .word("name");
        c.keyword("material", 3, "material number of the new block").integer("n", 1, 1000000).defaults("1");
        c.keyword("cons", 3, "zone model its zones get when it is divided into zones (0 null, 1 elastic, 2 Mohr-Coulomb)")
            .integer("c", 0, 2);
        c.require_one_of(1);
        c.describe("The block is rigid: it moves as a whole, with three translations and three rotations "
                   "about its centroid. Its mass and inertia come from its faces and the density of its "
                   "material ('prop mat=n dens=...'). Faces must be planar and the solid convex; an error "
                   "names the face that is not.\n\n"
                   "'tunnel' makes a box of rock around a straight tunnel in one command. In the cross-section "
                   "the tunnel wall is a regular polygon of 'ntheta' sides with the area of the circle of "
                   "'radius' (its corners a little outside the circle), one corner on the box's horizontal "
                   "mid-plane: a multiple of 4 makes the model symmetric about both mid-planes, so that a "
                   "quarter of it can be kept. Inside the wall, the core is one block per segment, in group "
                   "'tunnel' (or the 'group' given): 'excavate range group tunnel' opens the hole. Around it lie "
                   "'nrad' rings of 'ntheta' blocks each, bounded by planes through the axis at the polygon's "
                   "corners and by larger polygons; each ring is 'ratio' times as thick as the one inside it, and "
                   "the last reaches the box (half-width w across the axis, horizontally unless the axis is "
                   "vertical, and half-height h). Every block is a convex prism; neighbours share whole faces "
                   "with the same corners, and the faces between the blocks are one joint set, joined, so the "
                   "blocks act as one mass. The axis runs from 'a' to 'b', or from 'length' l1 to l2 along the "
                   "line of plunge 'dip' and trend 'dd' through 'origin'.");
        c.example("poly brick 0 10 0 10 -5 0 region 1 group 'base'");
        c.example("poly prism a (0,0,0) (1,0,0) (0,1,0) b (0,0,2) (1,0,2) (0,1,2)");
        c.example("poly tetra (0,0,0) (1,0,0) (0,1,0) (0,0,1)");
        c.example("poly tunnel a (0,0,0) b (0,2,0) radius 1 box 10 ntheta 16 nrad 6 nseg 2");
        c.example("poly tunnel dip 0 dd 0 length 0 1 radius 1 box 10 nrad 10 ratio 1.4");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const std::string kind = a.chosen(1);
            if (kind != "prism" && kind != "tunnel" && (a.has("a") || a.has("b"))) {
                const KeywordUse* u = a.has("a") ? a.find("a") : a.find("b");
                fail(u->loc, "'" + u->spec->name + "' goes with 'prism' or 'tunnel'", {}, "poly");
            }
            if (kind != "tunnel") {
                for (const char* k : {"radius", "box", "ntheta", "nrad", "ratio", "nseg", "dip", "dd", "origin", "length", "jmat"}) {
                    if (a.has(k)) fail(a.find(k)->loc, std::string("'") + k + "' goes with 'tunnel'", {}, "poly");
                }
            }
            // Coordinates within reach of doubles: their squares and cubes (areas, volumes,
            // inertias) must not overflow, and round-off must leave the block its shape.
            constexpr double kMaxCoordinate = 1e9;
            for (const char* k : {"brick", "a", "b", "face", "tetra", "origin", "length"}) {
                for (const KeywordUse* u : a.all(k)) {
                    for (const Value& v : u->values) {
                        const double x = v.type == ValueType::Vec3 ? v.vec.cwiseAbs().maxCoeff() : std::abs(v.number);
                        if ((v.type == ValueType::Vec3 || v.type == ValueType::Real) && x > kMaxCoordinate) {
                            fail(v.loc, "coordinate " + num(x) + " is too far from the origin: poly takes coordinates within " +
                                            num(kMaxCoordinate) + " m",
                                 {"odec works in metres; move the origin near the model"}, "poly");
                        }
                    }
                }
            }
            for (const char* k : {"radius", "box"}) {
                for (const KeywordUse* u : a.all(k)) {
                    for (const Value& v : u->values) {
                        if (v.number > kMaxCoordinate) {
                            fail(v.loc, "size " + num(v.number) + " is too large: poly takes sizes within " +
                                            num(kMaxCoordinate) + " m",
                                 {"odec works in metres"}, "poly");
                        }
                    }
                }
            }
            if (kind == "tunnel") {
                make_tunnel(ctx, a);
                return;
            }
            Polyhedron p;
            std::string error;
            SourceLoc where = a.find(kind)->loc;
            if (kind == "brick") {
                const KeywordUse* b = a.find("brick");
                const char* axes[3] = {"x", "y", "z"};
                for (int i = 0; i < 3; ++i) {
                    const Value& lo = b->values[2 * i];
                    const Value& hi = b->values[2 * i + 1];
                    if (!(hi.number > lo.number)) {
                        fail(hi.loc, std::string("'brick' ") + axes[i] + "2 must be greater than " + axes[i] +
                                         "1 (got " + num(hi.number) + " after " + num(lo.number) + ")",
                             {}, "poly");
                    }
                }
                p = make_brick(b->values[0].number, b->values[1].number, b->values[2].number, b->values[3].number,
                               b->values[4].number, b->values[5].number);
            } else if (kind == "prism") {
                if (!a.has("a") || !a.has("b")) fail(where, "'prism' needs both ends: 'a' v ... 'b' v ...", {}, "poly");
                const std::vector<Vec3> pa = points_of(*a.find("a")), pb = points_of(*a.find("b"));
                std::vector<Vec3> all = pa;
                all.insert(all.end(), pb.begin(), pb.end());
                // Ends that are not translated copies (a tapered or skewed prism) make the convex
                // hull of the two polygons, as 3DEC does, when that hull has the two as faces.
                if (!make_prism(pa, pb, tolerance_for(all), p, error) &&
                    !make_prism(pa, pb, rounding_tolerance_for(all), p, error)) {
                    Polyhedron hull;
                    std::string hull_error;
                    if (!make_convex_hull(all, tolerance_for(all), hull, hull_error)) fail(a.find("a")->loc, error, {}, "poly");
                    // Every vertex of both polygons must lie on the hull's surface (a vertex inside
                    // it means the two polygons do not bound one convex solid).
                    const double tol = rounding_tolerance_for(all);
                    for (const Vec3& x : all) {
                        double inside = std::numeric_limits<double>::infinity();
                        for (int f = 0; f < hull.n_faces(); ++f) {
                            inside = std::min(inside, hull.face_normal(f).dot(hull.vertices[hull.face_vertex(f, 0)] - x));
                        }
                        if (inside > tol) {
                            fail(a.find("a")->loc, "prism: polygons a and b are not the two ends of a convex solid: "
                                                   "the vertex " + vec_text(x) + " lies " + num(inside) +
                                                   " m inside the hull of the others",
                                 {"list each end's vertices in order around it; the two ends may differ in shape"}, "poly");
                        }
                    }
                    p = std::move(hull);
                }
            } else if (kind == "face") {
                std::vector<std::vector<Vec3>> faces;
                std::vector<Vec3> all;
                for (const KeywordUse* u : a.all("face")) {
                    faces.push_back(points_of(*u));
                    all.insert(all.end(), faces.back().begin(), faces.back().end());
                    if (faces.back().size() < 3) {
                        fail(u->loc, "face " + std::to_string(faces.size()) + " has " +
                                         std::to_string(faces.back().size()) + " vertices: a face needs at least 3",
                             {}, "poly");
                    }
                }
                if (!make_from_faces(faces, tolerance_for(all), p, error) &&
                    !make_from_faces(faces, rounding_tolerance_for(all), p, error) &&
                    !(error.find("convex") != std::string::npos && accept_hull(ctx, faces, all, "the faces given are not convex", p))) {
                    // The message names the face by its number; point at that 'face' keyword.
                    const auto uses = a.all("face");
                    SourceLoc loc = uses.front()->loc;
                    const size_t at = error.find("face ");
                    if (at != std::string::npos) {
                        const int n = std::atoi(error.c_str() + at + 5);
                        if (n >= 1 && n <= static_cast<int>(uses.size())) loc = uses[n - 1]->loc;
                    }
                    fail(loc, error, {}, "poly");
                }
            } else {
                const KeywordUse* t = a.find("tetra");
                std::vector<Vec3> v = points_of(*t);
                if (!make_tetra(v[0], v[1], v[2], v[3], tolerance_for(v), p, error)) fail(t->loc, error, {}, "poly");
            }
            const int region = a.has("region") ? a.integer("region") : 0;
            const int material = a.has("material") ? a.integer("material") : 1;
            {
                const double rho = material < static_cast<int>(m.materials.size()) ? m.materials[material].density : 0.0;
                const std::string problem = block_numbers_problem(mass_properties(p), rho);
                if (!problem.empty()) fail(where, problem, {"odec works in metres, kilograms and seconds"}, "poly");
            }
            if (ctx.interp.limits.max_blocks > 0 && m.blocks.size() >= ctx.interp.limits.max_blocks) {
                fail(where, "this session allows at most " + std::to_string(ctx.interp.limits.max_blocks) + " blocks",
                     {}, "poly");
            }
            const int group = a.has("group") ? m.group_index(a.text("group"), true) : -1;
            const int b = add_block(m, p, region, group, material);
            if (a.has("cons")) m.blocks.cons[b] = static_cast<std::uint8_t>(a.integer("cons"));
        });
        return c;
    }();
    return spec;
}

} // namespace odec
