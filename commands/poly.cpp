#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/tunnel.h"
#include "tunnel_axis.h"

#include <array>
#include <cctype>
#include <cmath>
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

// Coordinates written in a script are rounded to some decimal place: this is the finest place
// any of them uses, m, or 0 when one carries more than 9 decimals (a computed value).
double written_precision(const std::vector<Vec3>& pts) {
    int finest = 0;
    for (const Vec3& p : pts) {
        for (int i = 0; i < 3; ++i) {
            const double x = std::abs(p[i]);
            int k = 0;
            for (; k <= 9; ++k) {
                const double s = x * std::pow(10.0, k);
                if (s > 1e15 || std::abs(s - std::round(s)) <= 1e-6 + 1e-14 * s) break;
            }
            if (k > 9) return 0;
            finest = std::max(finest, k);
        }
    }
    return std::pow(10.0, -finest);
}

// The largest distance of the points from their least-squares plane, m.
double off_plane(const std::vector<Vec3>& q) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& x : q) c += x;
    c /= static_cast<double>(q.size());
    Mat3 cov = Mat3::Zero();
    for (const Vec3& x : q) cov += (x - c) * (x - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
    const Vec3 n = eig.eigenvectors().col(0);
    double worst = 0;
    for (const Vec3& x : q) worst = std::max(worst, std::abs(n.dot(x - c)));
    return worst;
}

// The blocks already made, their reach and their shapes in world axes, each found once per
// command and only when asked for.
struct NearbyFaces {
    const Model& m;
    std::vector<int> done;                 // block index -> 1 once its world shape is made
    std::vector<Polyhedron> shape;
    std::vector<double> reach;             // m, farthest vertex from the centroid (-1: not yet)
    explicit NearbyFaces(const Model& model) : m(model) {}
    double radius(int b) {
        if (reach.empty()) reach.assign(static_cast<size_t>(m.blocks.size()), -1.0);
        if (reach[b] < 0) {
            reach[b] = 0;
            for (const Vec3& x : m.blocks.shape[b].vertices) reach[b] = std::max(reach[b], x.norm());
        }
        return reach[b];
    }
    const Polyhedron& world(int b) {
        if (done.empty()) {
            done.assign(static_cast<size_t>(m.blocks.size()), 0);
            shape.resize(static_cast<size_t>(m.blocks.size()));
        }
        if (!done[b]) {
            shape[b] = world_shape(m, b);
            done[b] = 1;
        }
        return shape[b];
    }
};

// True when polygon f (face of p) lies in triangle t (within tol) and has area.
bool face_in_triangle(const Polyhedron& p, int f, const Vec3 t[3], double tol) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    if (!(p.face_area(f) > tol * tol)) return false;
    for (int k = 0; k < p.face_size(f); ++k) {
        const Vec3& x = p.vertices[p.face_vertex(f, k)];
        if (std::abs(n.dot(x - t[0])) > tol) return false;
        for (int e = 0; e < 3; ++e) {
            const Vec3 side = n.cross(t[(e + 1) % 3] - t[e]).normalized(); // points into the triangle
            if (side.dot(x - t[e]) < -tol) return false;
        }
    }
    return true;
}

// Which diagonal an existing block splits the skew quadrilateral q0 q1 q2 q3 along, judged by
// its faces on either pair of triangles: 1 for q0-q2, 2 for q1-q3, 0 when none has (or both
// have); `by` gets the id of the block.
int diagonal_in_use(NearbyFaces& near, const Vec3 q[4], double tol, int& by) {
    const Vec3 centre = 0.25 * (q[0] + q[1] + q[2] + q[3]);
    double reach = 0;
    for (int i = 0; i < 4; ++i) reach = std::max(reach, (q[i] - centre).norm());
    const Vec3 tris[2][2][3] = {{{q[0], q[1], q[2]}, {q[0], q[2], q[3]}}, {{q[0], q[1], q[3]}, {q[1], q[2], q[3]}}};
    int found = 0;
    const BlockSet& s = near.m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if ((s.centroid[b] - centre).norm() > near.radius(b) + reach + tol) continue;
        const Polyhedron& p = near.world(b);
        for (int f = 0; f < p.n_faces(); ++f) {
            for (int option = 0; option < 2; ++option) {
                for (int t = 0; t < 2; ++t) {
                    if (!face_in_triangle(p, f, tris[option][t], tol)) continue;
                    if (found != 0 && found != option + 1) return 0;
                    found = option + 1;
                    by = s.id[b];
                }
            }
        }
    }
    return found;
}

// A prism whose ends are not translated copies (a tapered or skewed prism), and any prism
// that is not convex: its end polygons a and b and, for each k, the side a_k a_k+1 b_k+1 b_k.
// A side whose corners lie in one plane within the rounding of the coordinates as written is
// one face, made exactly planar (each corner moved onto the planes of its faces, by no more
// than that rounding); a side that does not cannot be one face of a block: it is taken as two
// triangles, split along the diagonal that an existing block sharing those corners already
// uses (so that neighbours meet without gap or overlap), else along the one that keeps the
// block convex. Returns the solid's faces, with a name for each for messages.
struct PrismFaces {
    std::vector<std::vector<Vec3>> faces;
    std::vector<std::string> names;
    double tol = 0;            // m, planarity and corner merging
    double precision = 0;      // m, as written (0: not rounded)
    int skew = 0;              // sides taken as two triangles
    double worst = 0;          // m, farthest a skew side's corners are off one plane
    std::vector<std::string> matched; // "side k as block n": the diagonal taken from that block
};

PrismFaces prism_faces(NearbyFaces& near, const std::vector<Vec3>& pa, const std::vector<Vec3>& pb_given) {
    PrismFaces out;
    const size_t n = pa.size();
    std::vector<Vec3> all = pa;
    all.insert(all.end(), pb_given.begin(), pb_given.end());
    // A rounding as coarse as a thousandth of the block's size (integers for a block of a few
    // metres) is no rounding: such coordinates are taken as exact.
    Vec3 lo = all.front(), hi = all.front();
    for (const Vec3& x : all) {
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
    out.precision = written_precision(all);
    if (std::sqrt(3.0) * out.precision > 1e-3 * (hi - lo).norm()) out.precision = 0;
    out.tol = std::max(tolerance_for(all), std::sqrt(3.0) * out.precision);
    // b may start at any vertex and run either way: vertex k of a is joined to the vertex of b
    // that makes the sides shortest (the sum of their squared lengths least; as listed when tied).
    std::vector<Vec3> pb = pb_given;
    double best = std::numeric_limits<double>::infinity();
    for (int dir = 1; dir >= -1; dir -= 2) {
        for (size_t shift = 0; shift < n; ++shift) {
            std::vector<Vec3> cand(n);
            double sum = 0;
            for (size_t i = 0; i < n; ++i) {
                const long j = (static_cast<long>(shift) + dir * static_cast<long>(i) + 2 * static_cast<long>(n)) %
                               static_cast<long>(n);
                cand[i] = pb_given[static_cast<size_t>(j)];
                sum += (cand[i] - pa[i]).squaredNorm();
            }
            if (sum < best * (1 - 1e-12)) {
                best = sum;
                pb = std::move(cand);
            }
        }
    }
    out.faces = {pa, pb};
    out.names = {"polygon a", "polygon b"};
    // Windings that agree around the solid: a as listed, b backwards, side k as a_k+1 a_k b_k b_k+1;
    // the sign of the volume they enclose says whether that is outward.
    std::vector<std::array<Vec3, 4>> sides(n);
    double volume6 = 0;
    const Vec3 o = pa[0];
    for (size_t k = 0; k < n; ++k) {
        const size_t j = (k + 1) % n;
        sides[k] = {pa[j], pa[k], pb[k], pb[j]};
        for (const auto& tri : {std::array<Vec3, 3>{pa[j], pa[k], pb[k]}, std::array<Vec3, 3>{pa[j], pb[k], pb[j]}}) {
            volume6 += (tri[0] - o).dot((tri[1] - o).cross(tri[2] - o));
        }
    }
    // Polygon a's fan from o adds nothing; polygon b backwards, fanned from its last vertex.
    for (size_t k = n - 2; k >= 1; --k) volume6 += (pb[n - 1] - o).dot((pb[k] - o).cross(pb[k - 1] - o));
    const double outward = volume6 >= 0 ? 1.0 : -1.0;
    for (size_t k = 0; k < n; ++k) {
        const auto& s = sides[k]; // s0 = a_k+1, s1 = a_k, s2 = b_k, s3 = b_k+1
        const std::string name = "side " + std::to_string(k + 1);
        const double off = off_plane({s[0], s[1], s[2], s[3]});
        if (off <= out.tol) {
            out.faces.push_back({s[0], s[1], s[2], s[3]});
            out.names.push_back(name);
            continue;
        }
        ++out.skew;
        out.worst = std::max(out.worst, off);
        // The quadrilateral as q0 q1 q2 q3 = a_k a_k+1 b_k+1 b_k; diagonal 1 is a_k-b_k+1.
        const Vec3 q[4] = {s[1], s[0], s[3], s[2]};
        int by = 0;
        int diagonal = diagonal_in_use(near, q, out.tol, by);
        if (diagonal != 0) {
            out.matched.push_back(name + " as block " + std::to_string(by));
        } else {
            // Diagonal a_k-b_k+1 splits it into (a_k+1, a_k, b_k+1) and (a_k, b_k, b_k+1): convex
            // when b_k lies behind the first, seen from outside.
            const Vec3 nrm = outward * (s[1] - s[0]).cross(s[3] - s[0]);
            diagonal = nrm.dot(s[2] - s[0]) < 0 ? 1 : 2;
        }
        if (diagonal == 1) {
            out.faces.push_back({s[0], s[1], s[3]});
            out.faces.push_back({s[1], s[2], s[3]});
        } else {
            out.faces.push_back({s[0], s[1], s[2]});
            out.faces.push_back({s[0], s[2], s[3]});
        }
        out.names.push_back(name);
        out.names.push_back(name);
    }
    return out;
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
        CommandSpec c("poly", 4, "create a rigid polyhedral block");
        c.keyword("brick", 2, "axis-aligned box from x1 to x2, y1 to y2, z1 to z2")
            .real("x1").real("x2").real("y1").real("y2").real("z1").real("z2")
            .in_choice(1);
        c.keyword("prism", 2, "prism between polygon 'a' and polygon 'b', vertex k of one joined to vertex k of the "
                              "other (a translated copy, or a tapered or skewed end: see below)")
            .in_choice(1);
        c.keyword("a", 1, "with 'prism': the vertices of one end, in order; with 'tunnel': the start of the axis")
            .vec("v").repeat();
        c.keyword("b", 1, "with 'prism': the vertices of the other end, in order; with 'tunnel': the end of the axis")
            .vec("v").repeat();
        c.keyword("face", 2, "one face of a general polyhedron: its vertices in order (repeat 'face' for every "
                             "face)")
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
                   "material ('prop mat=n dens=...'). Faces must be planar, within the rounding of the "
                   "coordinates as written; an error names the face that is not.\n\n"
                   "A solid that is not convex (an L-shaped block, a voussoir whose intrados is a polygon "
                   "bent inward) is made of convex blocks that fill it exactly, as a concave block is made "
                   "in 3DEC of convex blocks joined into one rigid block: each has an id of its own (a "
                   "line says which), with the region, group and material given. Their volumes, centroids "
                   "and inertias add up to the solid's own. Each block is cut at the edges where the "
                   "surface folds inward, by planes through those edges. The blocks are one clump: one "
                   "rigid body, with one mass (the sum of theirs), one centroid, one inertia tensor (the "
                   "sum of theirs about that centroid), one velocity and one spin; there is no contact "
                   "between them, and the forces and loads on each act on the whole, with their moments "
                   "about its centroid. Each block keeps its own id, contacts, loads and histories and "
                   "moves exactly as the part of the body it is ('print block' names its clump). What "
                   "acts on one acts on all: 'fix', 'free', 'ini' and 'bound' velocities are given to every "
                   "block of a clump a range touches, and 'delete', 'excavate' and 'fill' take whole "
                   "clumps (a line says so). The faces between the blocks are a joint set of their own, "
                   "joined: a cut through a block of the clump ('jset', 'tunnel') or zoning one ('gen edge') ends "
                   "the clump, and its blocks are then glued across those faces, with the joint material "
                   "of new contacts ('set jmat'). A model saved before clumps existed (save format 11 or "
                   "older) restores as it was saved, its blocks glued.\n\n"
                   "'prism' joins vertex k of 'a' to vertex k of 'b' ('b' may start at another vertex or "
                   "run the other way: the pairing that makes the sides shortest is taken). When 'b' is "
                   "a translated copy of 'a', the sides are parallelograms. Otherwise (a tapered column "
                   "drum) a side whose four corners lie in one plane within the rounding of the "
                   "coordinates (the finest decimal place they are written to, times the square root "
                   "of 3, when that is less than a thousandth of the block's size; else, as for computed "
                   "coordinates, a millionth of its size) is one face, made "
                   "exactly planar: each corner is moved onto the planes of its faces, by no more than "
                   "that rounding. A side whose corners do not lie in one plane "
                   "cannot be one face of a block: it is taken as two triangles, split along one of its "
                   "diagonals, and a warning says how far its corners are off one plane. The diagonal is "
                   "the one a block already made has there, when one shares those corners (so that "
                   "neighbours meet without gap or overlap), else the one that keeps the block convex. "
                   "This rule is odec's own. A prism that comes out not convex is made of convex blocks, "
                   "as above.\n\n"
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
                   "blocks act as one mass (glued, not a clump: they are a rock mass meant to part). The axis runs from 'a' to 'b', or from 'length' l1 to l2 along the "
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
            SolidPieces solid;     // a solid that is not convex: its convex pieces
            std::string error;
            SourceLoc where = a.find(kind)->loc;
            // The faces' tag between the pieces of a solid that is not convex: a joined joint set
            // of its own, added only when pieces are made.
            const int inner_tag = static_cast<int>(m.joint_planes.size()) + 1;
            // A message that names a face by its number, with the face's name and where it was typed.
            auto name_face = [](std::string text, const std::vector<std::string>& names) {
                const size_t at = text.find("face ");
                if (at == std::string::npos) return text;
                const int k = std::atoi(text.c_str() + at + 5);
                if (k < 1 || k > static_cast<int>(names.size())) return text;
                size_t end = at + 5;
                while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
                return text.substr(0, at) + names[k - 1] + text.substr(end);
            };
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
                if (!make_prism(pa, pb, tolerance_for(all), p, error) &&
                    !make_prism(pa, pb, rounding_tolerance_for(all), p, error)) {
                    if (pa.size() < 3 || pb.size() != pa.size()) fail(a.find("a")->loc, error, {}, "poly");
                    // Not a translated copy, or not convex: its faces, sides that are not planar
                    // split in two (see prism_faces).
                    NearbyFaces near(m);
                    const PrismFaces pf = prism_faces(near, pa, pb);
                    if (!make_convex_pieces(pf.faces, pf.tol, inner_tag, solid, error)) {
                        const std::string text = name_face(error, pf.names);
                        const bool planar = text.find("not planar") != std::string::npos;
                        fail(text.find("polygon b") != std::string::npos ? a.find("b")->loc : a.find("a")->loc,
                             "prism: " + text,
                             planar ? std::vector<std::string>{}
                                    : std::vector<std::string>{"list each end's vertices in order around it, vertex k "
                                                               "of 'a' joined to vertex k of 'b'"},
                             "poly");
                    }
                    if (pf.skew > 0) {
                        std::string text = "prism: " + std::to_string(pf.skew) + " of its " + std::to_string(pa.size()) +
                                           " sides are not planar (their corners up to " + num(pf.worst) +
                                           " m off one plane";
                        if (pf.precision > 0) text += ", with the coordinates written to " + num(pf.precision) + " m";
                        text += "): each is taken as two triangles, split along the diagonal that keeps the block convex";
                        if (!pf.matched.empty()) {
                            text += ", or along the one the neighbouring block already has (";
                            for (size_t i = 0; i < pf.matched.size(); ++i) text += (i ? ", " : "") + pf.matched[i];
                            text += ")";
                        }
                        warn(ctx, a.find("a")->loc, text);
                    }
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
                    !(error.find("convex") != std::string::npos &&
                      make_convex_pieces(faces, rounding_tolerance_for(all), inner_tag, solid, error))) {
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
            // The blocks to add: p, or the pieces of a solid that is not convex.
            std::vector<Polyhedron> shapes;
            if (!solid.pieces.empty()) {
                shapes = std::move(solid.pieces);
                if (shapes.size() == 1) shapes[0].face_joint.clear();
            } else {
                shapes.push_back(std::move(p));
            }
            const int region = a.has("region") ? a.integer("region") : 0;
            const int material = a.has("material") ? a.integer("material") : 1;
            {
                const double rho = material < static_cast<int>(m.materials.size()) ? m.materials[material].density : 0.0;
                for (const Polyhedron& shape : shapes) {
                    const std::string problem = block_numbers_problem(mass_properties(shape), rho);
                    if (!problem.empty()) fail(where, problem, {"odec works in metres, kilograms and seconds"}, "poly");
                }
            }
            const long limit = ctx.interp.limits.max_blocks;
            if (limit > 0 && m.blocks.size() + static_cast<long>(shapes.size()) > limit) {
                fail(where, "this session allows at most " + std::to_string(limit) + " blocks" +
                                (shapes.size() > 1 ? ": the " + std::to_string(shapes.size()) + " pieces of this one would pass it"
                                                   : std::string()),
                     {}, "poly");
            }
            // Everything is checked: change the model. The faces between the pieces of a solid
            // that is not convex are a joined joint set of their own, so that they act as one.
            if (shapes.size() > 1) {
                ++m.n_joint_sets;
                m.joint_planes.push_back(JointPlane{m.n_joint_sets, true, 0});
            }
            const int group = a.has("group") ? m.group_index(a.text("group"), true) : -1;
            const int first_id = m.next_block_id;
            for (const Polyhedron& shape : shapes) {
                const int b = add_block(m, shape, region, group, material);
                if (a.has("cons")) m.blocks.cons[b] = static_cast<std::uint8_t>(a.integer("cons"));
                // The pieces of a solid that is not convex move as one rigid body (clump.h).
                if (shapes.size() > 1) m.blocks.clump[b] = first_id;
            }
            if (shapes.size() > 1 && !ctx.interp.quiet) {
                ctx.out << "poly: the solid is not convex: made of " << shapes.size() << " convex blocks, ids " << first_id
                        << " to " << m.next_block_id - 1 << ", one rigid body (clump " << first_id
                        << "); the faces between them are joint set " << m.n_joint_sets
                        << ", joined, should the clump end ('jset', 'gen edge')\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
