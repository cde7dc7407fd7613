#include <algorithm>

#include "analysis_mode.h"
#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/flow.h"
#include "engine/polyhedron.h"

#include <cmath>
#include "engine/zones.h"

namespace odec {

namespace {

// A stress field s + x gx + y gy + z gz, Pa (tension positive), as matrices.
struct StressField3 {
    Mat3 s, g[3];
};

Mat3 tensor(const Sym6& v) {
    Mat3 t;
    t << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
    return t;
}

// The traction of the field on face f of a block's world shape, whose centroid is c: its force,
// N, and its moment about c, N m (both world axes), and the face's area centroid. The face is
// fanned into triangles; over each, the traction is linear in the position, and its force and
// moment are integrated exactly from the triangle's area, first and second moments.
struct FaceTraction {
    Vec3 force = Vec3::Zero();
    Vec3 moment = Vec3::Zero();
    Vec3 centroid = Vec3::Zero();
};

FaceTraction face_traction(const Polyhedron& w, int f, const Vec3& c, const StressField3& field) {
    // Positions y are taken from the block's centroid: sigma(y) = s0 + sum_k y_k g_k.
    const Mat3 s0 = field.s + c.x() * field.g[0] + c.y() * field.g[1] + c.z() * field.g[2];
    FaceTraction r;
    double area = 0;
    const Vec3 p0 = w.vertices[w.face_vertex(f, 0)] - c;
    for (int k = 1; k + 1 < w.face_size(f); ++k) {
        const Vec3 p1 = w.vertices[w.face_vertex(f, k)] - c;
        const Vec3 p2 = w.vertices[w.face_vertex(f, k + 1)] - c;
        const Vec3 a = 0.5 * (p1 - p0).cross(p2 - p0); // area times outward normal
        const double at = a.norm();
        if (!(at > 0)) continue;
        const Vec3 mean = (p0 + p1 + p2) / 3.0;
        const Vec3 sum = p0 + p1 + p2;
        // The second moment of the triangle: integral of y y^T over it.
        const Mat3 second = (at / 12.0) * (p0 * p0.transpose() + p1 * p1.transpose() + p2 * p2.transpose() +
                                           sum * sum.transpose());
        const Vec3 t0 = s0 * a;                  // the traction of s0 times the area
        r.force += t0;
        r.moment += mean.cross(t0);
        for (int k2 = 0; k2 < 3; ++k2) {
            const Vec3 gk = field.g[k2] * a;     // the traction of g_k times the area
            r.force += mean[k2] * gk;
            r.moment += (second.col(k2) / at).cross(gk);
        }
        r.centroid += at * mean;
        area += at;
    }
    r.centroid = area > 0 ? Vec3(c + r.centroid / area) : Vec3(c + p0);
    return r;
}

// Set the given components of the load of this kind at this point (within tol, m) with this
// table on a block (a new load when it has none there); loads left with no force and no couple go.
void set_block_load(std::vector<BlockLoad>& loads, LoadKind kind, int table, const Vec3& lever, double tol,
                    const bool given[6], const double value[6]) {
    BlockLoad* l = nullptr;
    for (BlockLoad& x : loads) {
        if (x.kind == kind && x.table == table && (x.lever - lever).stableNorm() <= tol) l = &x;
    }
    if (l) l->lever = lever;
    if (!l) {
        BlockLoad fresh;
        fresh.kind = kind;
        fresh.table = table;
        fresh.lever = lever;
        loads.push_back(fresh);
        l = &loads.back();
    }
    for (int i = 0; i < 3; ++i) {
        if (given[i]) l->force[i] = value[i];
        if (given[3 + i]) l->couple[i] = value[3 + i];
    }
    loads.erase(std::remove_if(loads.begin(), loads.end(),
                               [](const BlockLoad& x) { return x.force.isZero(0) && x.couple.isZero(0); }),
                loads.end());
}

// Rigid blocks whose shape holds the point x (within a thousandth of their size).
std::vector<int> rigid_blocks_at(const Model& m, const Vec3& x) {
    const BlockSet& s = m.blocks;
    std::vector<int> found;
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & (kExcavated | kDeformable)) continue;
        const Vec3 local = s.orientation[b].conjugate() * (x - s.centroid[b]);
        if (contains_point(s.shape[b], local, 1e-3 * std::cbrt(s.volume[b]))) found.push_back(b);
    }
    return found;
}

std::string ids_text(const Model& m, const std::vector<int>& blocks) {
    std::string t;
    for (size_t k = 0; k < blocks.size() && k < 8; ++k) t += (k ? ", " : "") + std::to_string(m.blocks.id[blocks[k]]);
    if (blocks.size() > 8) t += ", ...";
    return t;
}

// 'bound pp', 'bound wtable', 'bound pfree': the pore pressures of the joints' flow nodes.
void bound_pore_pressure(CommandContext& ctx, const Args& a) {
    Model& m = ctx.model;
    const KeywordUse* first = a.find("pp") ? a.find("pp") : a.find("wtable") ? a.find("wtable") : a.find("pgrad") ? a.find("pgrad") : a.find("pfree");
    if (!m.flow.configured) fail(first->loc, "fluid flow is not configured", {"give 'config flow' first (3DEC writes 'config fluid')"}, "boundary");
    for (const KeywordUse& u : a.uses) {
        const std::string& n = u.spec->name;
        if (n != "pp" && n != "pgrad" && n != "wtable" && n != "pfree" && n != "range") {
            fail(u.loc, "'" + n + "' does not go with the pore pressure ('pp', 'wtable', 'pfree')", {}, "boundary");
        }
    }
    if (a.has("pgrad") && !a.has("pp")) fail(a.find("pgrad")->loc, "'pgrad' goes with 'pp'", {}, "boundary");
    if (a.has("pp") && a.has("wtable")) fail(a.find("wtable")->loc, "'wtable' and 'pp' exclude each other", {}, "boundary");
    if (a.has("pfree") && (a.has("pp") || a.has("wtable"))) {
        fail(a.find("pfree")->loc, "'pfree' releases pressures: it takes no 'pp' or 'wtable'", {}, "boundary");
    }
    if (a.has("wtable") && !(m.gravity.norm() > 0)) {
        fail(a.find("wtable")->loc, "a water table needs gravity to say which way is down", {"set grav 0 0 -9.81"}, "boundary");
    }
    if (m.blocks.size() == 0) fail(a.loc, "there are no blocks, so no joints to hold a pressure", {}, "boundary");
    flow_ready(m);
    const std::vector<int> nodes = flow_nodes_in_range(m, a.range);
    if (nodes.empty()) {
        fail(a.loc, m.flow.n_nodes() == 0 ? "there is no joint between rigid blocks, so no flow node to hold a pressure"
                                          : "the range selects no flow node (no joint there)",
             {"flow nodes stand at the sub-contacts of the joints: 'print flow' lists them"}, "boundary");
    }
    if (a.has("pfree")) {
        for (int i : nodes) m.flow.fixed[i] = 0;
        if (!ctx.interp.quiet) ctx.out << nodes.size() << " flow node" << (nodes.size() == 1 ? "" : "s") << " released\n";
        return;
    }
    const int n = set_flow_pressure(m, nodes, pressure_spec(m, a), true);
    if (!ctx.interp.quiet) ctx.out << n << " flow node" << (n == 1 ? "" : "s") << " with a fixed pore pressure\n";
}

} // namespace

const CommandSpec& bound_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("boundary", 3, "prescribe block velocities or apply forces, moments and stresses");
        c.alias("apply");
        c.keyword("xvelocity", 2, "hold the x velocity at v, m/s").real("v");
        c.keyword("yvelocity", 2, "hold the y velocity at v, m/s").real("v");
        c.keyword("zvelocity", 2, "hold the z velocity at v, m/s").real("v");
        c.keyword("xload", 2, "apply a force fx, N, to each block (at its centroid, or at 'point') or gridpoint").real("fx");
        c.keyword("yload", 2, "apply a force fy, N, to each block (at its centroid, or at 'point') or gridpoint").real("fy");
        c.keyword("zload", 2, "apply a force fz, N, to each block (at its centroid, or at 'point') or gridpoint").real("fz");
        c.keyword("xmoment", 4, "apply a couple mx, N m (about the x axis, right hand), to each rigid block").real("mx");
        c.keyword("ymoment", 4, "apply a couple my, N m (about the y axis, right hand), to each rigid block").real("my");
        c.keyword("zmoment", 4, "apply a couple mz, N m (about the z axis, right hand), to each rigid block").real("mz");
        c.keyword("point", 3, "with a load: where it acts on a rigid block, a point of the block that moves and "
                              "turns with it (without a range: the block there)")
            .vec("x,y,z");
        c.keyword("stress", 3, "apply the traction of this stress tensor (Pa, tension positive) on the "
                               "boundary faces, each at the face")
            .real("sxx").real("syy").real("szz").real("sxy").real("sxz").real("syz");
        c.keyword("xgrad", 2, "with 'stress': its change per metre of x, Pa/m")
            .real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("ygrad", 2, "with 'stress': its change per metre of y, Pa/m")
            .real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("zgrad", 2, "with 'stress': its change per metre of z, Pa/m")
            .real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("history", 4, "scale the velocities, loads, moments and stress of this command by table n, "
                                "whose x is the model time (s): v(t) = v table(t)")
            .integer("table", 1)
            .labelled();
        c.keyword("free", 3, "release prescribed velocities and remove applied forces, moments and stresses");
        c.keyword("pp", 2, "fix the pore pressure of the joints' flow nodes in the range at p, Pa ('config flow' first)").real("p", 0, kMaxMagnitude);
        c.keyword("pgrad", 3, "with 'pp': its change per metre, Pa/m: p + g . x at node x").vec("gx,gy,gz");
        c.keyword("wtable", 2, "fix the pore pressure at the hydrostatic one below a water table at this elevation, m")
            .real("z", -kMaxMagnitude, kMaxMagnitude);
        c.keyword("pfree", 3, "release the fixed pore pressures of the flow nodes in the range");
        c.range();
        c.describe("A prescribed velocity component is held whatever the forces; the others stay free. "
                   "Loads add to gravity and contact forces. Without a range every block is taken. Rigid "
                   "blocks are selected by their centroid; in deformable blocks, velocities and loads act on "
                   "the gridpoints the range selects by their position (a load on each), and 'stress' on the "
                   "faces of zones on the surface of a continuum that no other block covers (a joint's faces "
                   "are no boundary) and whose centre the range selects: each gets the "
                   "traction sigma n (n its outward normal; a negative normal stress pushes inward), replacing "
                   "an earlier 'stress' on that face. 'free' removes all of these.\n\n"
                   "On a rigid block a load acts at its centroid, or at 'point' x,y,z: a material point of the "
                   "block, which moves and turns with it, so that the load's moment about the centroid, "
                   "r x F, follows the block as it rocks. Without a range, 'point' loads the one rigid block "
                   "holding the point. A force and a couple ('xmoment' ...) keep their directions in world "
                   "axes. A load replaces the components given of an earlier load at the same point (within a "
                   "thousandth of the block's size of where that load's point is now) with the same table; loads "
                   "at other points, or with other tables, add to it. 'stress' on a rigid "
                   "block loads each of its faces that no other block covers and whose centroid the range "
                   "selects with the resultant of the traction over the face, at the face, computed for the "
                   "block where it is when the command is given (the force keeps its direction as the block "
                   "turns, its point turns with the block); a new 'stress' on a face replaces the old.\n\n"
                   "'hist table n' multiplies the velocities, loads, couples and stresses of the command by "
                   "table n at the model time (the table's x, in seconds, as 'hist time' records it; held "
                   "beyond its ends). In a static analysis the masses are scaled and model time is not real "
                   "time: a table then sets the order and the pace of loading, not a real duration.\n\n"
                   "A clump (the blocks of a solid that is not convex, 'poly') is one rigid body: a velocity "
                   "holds the velocity of its centroid and goes to all its blocks when the range selects any; "
                   "a load on one of its blocks acts on the whole at its point, its moment taken about the "
                   "clump's centroid.\n\n"
                   "Pore pressures ('config flow', 'help fluid'): 'pp p' fixes the pressure of the flow nodes of the "
                   "joints the range selects (by the node's position, or the blocks of its joint), p + g . x with "
                   "'pgrad g'; 'wtable z' fixes them at the hydrostatic pressure rho |g| (z - elevation) below a water "
                   "table at elevation z (0 above it), and nodes made later start at it; 'pfree' releases them. "
                   "Elsewhere the joints' ends are closed (no flow). A range with no flow node in it (no joint there) "
                   "is an error. To load a face of a rigid block with a reservoir's water, use 'stress' with a "
                   "gradient: a head of water to z = H with density rho on a face normal to x is 'stress -rho g H 0 0 "
                   "0 0 0 zgrad rho g 0 0 0 0 0' (tension positive).");
        c.example("bound xvel 0.01 range z 9 10");
        c.example("apply xvel 2.8 hist table 1 range z -1 0");
        c.example("bound zload -1e6 range id 5");
        c.example("bound xload 5e4 point 0,0.5,1.8 range id 2");
        c.example("bound ymoment 1e3 hist table 2 range id 3");
        c.example("bound pp 1e5 range x -0.1 0.1");
        c.example("bound wtable 30 range x -0.1 0.1");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (a.has("pp") || a.has("pgrad") || a.has("wtable") || a.has("pfree")) {
                bound_pore_pressure(ctx, a);
                return;
            }
            BlockSet& s = m.blocks;
            GridpointSet& g = m.gridpoints;
            const char* vel[3] = {"xvelocity", "yvelocity", "zvelocity"};
            const char* load[3] = {"xload", "yload", "zload"};
            const char* mom[3] = {"xmoment", "ymoment", "zmoment"};
            bool any_vel = false, any_load = false, any_moment = false;
            for (int i = 0; i < 3; ++i) {
                any_vel = any_vel || a.has(vel[i]);
                any_load = any_load || a.has(load[i]);
                any_moment = any_moment || a.has(mom[i]);
            }
            const bool stress = a.has("stress");
            if (!any_vel && !any_load && !any_moment && !stress && !a.has("free")) {
                fail(a.loc, "'boundary' needs a velocity (xvel ...), a load (xload ...), a moment (xmoment ...), "
                            "'stress' or 'free'", {}, "boundary");
            }
            for (const char* gk : {"xgrad", "ygrad", "zgrad"}) {
                if (a.has(gk) && !stress) {
                    fail(a.find(gk)->loc, std::string("'") + gk + "' goes with 'stress'", {}, "boundary");
                }
            }
            if (a.has("history") && !any_vel && !any_load && !any_moment && !stress) {
                fail(a.find("history")->loc, "'hist table n' goes with a velocity, a load, a moment or 'stress'", {},
                     "boundary");
            }
            if (a.has("point") && !any_load) {
                fail(a.find("point")->loc, "'point' goes with a load (xload, yload, zload)",
                     {any_moment ? "a couple ('xmoment' ...) has the same moment about every point: it takes no point"
                                 : "e.g. 'bound xload 1e3 point 0,0,1 range id 1'"},
                     "boundary");
            }
            const int table = a.has("history") ? a.integer("history") : 0;
            if (table > 0 && !m.tables.find(table)) {
                fail(a.find("history")->values[0].loc, "there is no table " + std::to_string(table),
                     {"define it first: table " + std::to_string(table) + " x1 y1 x2 y2 ..."}, "boundary");
            }
            const bool at_point = a.has("point");
            const Vec3 point = at_point ? Vec3(a.vec("point")) : Vec3::Zero();

            // What is loaded: the gridpoints of deformable blocks and the rigid blocks of the range;
            // with 'point' and no range, the rigid block holding the point.
            std::vector<int> gps, blocks;
            if (at_point && !a.has_range) {
                blocks = rigid_blocks_at(m, point);
                if (blocks.empty()) {
                    for (int b = 0; b < s.size(); ++b) {
                        if ((s.flags[b] & kDeformable) && !(s.flags[b] & kExcavated) &&
                            contains_point(world_shape(m, b), point, 1e-3 * std::cbrt(s.volume[b]))) {
                            fail(a.find("point")->loc,
                                 "the point " + vec_text(point) + " lies in deformable block " + std::to_string(s.id[b]) +
                                     ": 'point' goes with rigid blocks",
                                 {"deformable blocks take loads on the gridpoints a range selects, e.g. 'bound xload 1e3 "
                                  "range sphere x,y,z r'"},
                                 "boundary");
                        }
                    }
                    fail(a.find("point")->values[0].loc, "no rigid block holds the point " + vec_text(point),
                         {"give a range to load the blocks of the range at this point"}, "boundary");
                }
                // Where the pieces of one clump meet, the point is on the one rigid body.
                bool one_clump = s.clump[blocks[0]] != 0;
                for (int b : blocks) one_clump = one_clump && s.clump[b] == s.clump[blocks[0]];
                if (one_clump) blocks.resize(1);
                if (blocks.size() > 1) {
                    fail(a.find("point")->values[0].loc,
                         "the point " + vec_text(point) + " lies on blocks " + ids_text(m, blocks) +
                             ", where they meet",
                         {"give a range to say which block it loads, e.g. 'range id " +
                          std::to_string(s.id[blocks[0]]) + "'"},
                         "boundary");
                }
            } else {
                gps = select_gridpoints(m, a.range);
                // 'stress' alone selects faces, not blocks by their centroid: it says itself when
                // it loads none.
                const bool by_centroid = any_vel || any_load || any_moment || a.has("free");
                blocks = gps.empty() && by_centroid ? blocks_to_change(ctx, a) : select_blocks(m, a.range);
            }
            std::vector<int> rigid;
            for (int b : blocks) {
                if (!(s.flags[b] & kDeformable)) rigid.push_back(b);
            }
            if (!gps.empty() && (any_moment || at_point)) {
                const KeywordUse* u = at_point ? a.find("point") : nullptr;
                for (int i = 0; i < 3 && !u; ++i) u = a.find(mom[i]);
                fail(u->loc,
                     std::string(at_point ? "'point'" : "a moment") + " goes with rigid blocks: the range selects " +
                         std::to_string(gps.size()) + " gridpoint" + (gps.size() == 1 ? "" : "s") +
                         " of deformable blocks",
                     {at_point ? "deformable blocks take loads on the gridpoints the range selects ('bound xload ... "
                                 "range ...')"
                               : "deformable blocks take loads on the gridpoints the range selects ('bound xload ...'): "
                                 "a moment as forces on several of them"},
                     "boundary");
            }

            // Gridpoint loads: one table for all the components of a gridpoint's load.
            if (any_load) {
                for (int i : gps) {
                    if (a.has("free") || g.applied_table[i] == table) continue;
                    for (int k = 0; k < 3; ++k) {
                        if (!a.has(load[k]) && g.applied[i][k] != 0) {
                            fail(a.find(a.has(load[0]) ? load[0] : a.has(load[1]) ? load[1] : load[2])->loc,
                                 "the gridpoint at " + vec_text(g.pos[i]) + " carries a load in " +
                                     std::string(1, "xyz"[k]) + " " + (g.applied_table[i] > 0 ? "times table " + std::to_string(g.applied_table[i])
                                                                        : std::string("without a table")) +
                                     ": a gridpoint's load follows one table",
                                 {"give all its components in one command, or 'bound free' it first"}, "boundary");
                        }
                    }
                }
            }

            // The loads each rigid block gets, worked out before anything changes.
            bool given[6] = {};
            double value[6] = {};
            for (int i = 0; i < 3; ++i) {
                given[i] = a.has(load[i]);
                value[i] = given[i] ? a.real(load[i]) : 0.0;
                given[3 + i] = a.has(mom[i]);
                value[3 + i] = given[3 + i] ? a.real(mom[i]) : 0.0;
            }
            std::vector<Vec3> levers(rigid.size(), Vec3::Zero());
            std::vector<int> outside;
            if (any_load || any_moment) {
                const Vec3 f(value[0], value[1], value[2]);
                for (size_t k = 0; k < rigid.size(); ++k) {
                    const int b = rigid[k];
                    if (!at_point) continue;
                    levers[k] = s.orientation[b].conjugate() * (point - s.centroid[b]);
                    const Vec3 r = point - s.centroid[b];
                    if (!r.allFinite() || !r.cross(f).allFinite() || !std::isfinite(r.stableNorm() * f.stableNorm())) {
                        fail(a.find("point")->values[0].loc,
                             "the point " + vec_text(point) + " is so far from block " + std::to_string(s.id[b]) +
                                 " that the load's moment is not a finite number",
                             {}, "boundary");
                    }
                    const Vec3 local = levers[k];
                    if (!contains_point(s.shape[b], local, 1e-3 * std::cbrt(s.volume[b]))) outside.push_back(b);
                }
            }

            // 'stress' on rigid blocks: the traction on each free face whose centroid the range
            // selects, a load at the face.
            struct FaceLoadOf {
                int block;
                Vec3 lever, force, couple;
            };
            std::vector<FaceLoadOf> face_loads;
            Sym6 st{}, gx{}, gy{}, gz{};
            if (stress) {
                auto six = [&](const char* k) {
                    Sym6 v = {0, 0, 0, 0, 0, 0};
                    if (a.has(k)) {
                        const KeywordUse* u = a.find(k);
                        for (int i = 0; i < 6; ++i) v[i] = u->values[i].number;
                    }
                    return v;
                };
                st = six("stress");
                gx = six("xgrad");
                gy = six("ygrad");
                gz = six("zgrad");
                const StressField3 field{tensor(st), {tensor(gx), tensor(gy), tensor(gz)}};
                const FaceCover cover(m);
                for (int b = 0; b < s.size(); ++b) {
                    if (s.flags[b] & (kDeformable | kExcavated)) continue;
                    const Polyhedron w = world_shape(m, b);
                    const Mat3 rt = s.orientation[b].conjugate().toRotationMatrix();
                    for (int f = 0; f < w.n_faces(); ++f) {
                        const FaceTraction t = face_traction(w, f, s.centroid[b], field);
                        if (!a.range.contains_point(m, t.centroid, b)) continue;
                        const Vec3 nrm = w.face_normal(f);
                        // A face against another block is no boundary.
                        if (cover.covered(b, t.centroid, nrm)) continue;
                        const Vec3 r = t.centroid - s.centroid[b];
                        const Vec3 couple = t.moment - r.cross(t.force);
                        if (!t.force.allFinite() || !t.moment.allFinite() || !couple.allFinite()) {
                            fail(a.find("stress")->loc,
                                 "the traction on a face of block " + std::to_string(s.id[b]) +
                                     " is not a finite number: give smaller stresses or gradients",
                                 {}, "boundary");
                        }
                        face_loads.push_back({b, rt * r, t.force, couple});
                    }
                }
            }

            // Everything checked: the model changes from here on.
            if (a.has("history") && !m.settings.dynamic) note_static_time(ctx, "a boundary condition following a table of time");
            for (int i : gps) {
                if (a.has("free")) {
                    g.vel_bc[i] = 0;
                    g.vel_bc_table[i] = 0;
                    g.applied[i].setZero();
                    g.applied_table[i] = 0;
                    g.half_kick[i] = 1;
                }
                for (int k = 0; k < 3; ++k) {
                    if (a.has(vel[k])) {
                        g.vel_bc[i] |= static_cast<std::uint8_t>(1 << k);
                        g.vel_bc_value[i][k] = a.real(vel[k]);
                        g.vel_bc_table[i] = table;
                    }
                    if (a.has(load[k])) {
                        g.applied[i][k] = a.real(load[k]);
                        g.applied_table[i] = table;
                    }
                }
                if (g.applied[i].isZero(0)) g.applied_table[i] = 0;
            }
            if (a.has("free") && g.size() > 0) remove_boundary_stress(m, a.range);
            if (!gps.empty()) m.geometry_changed = true;
            // Velocities hold a clump's centroid: they go to every piece of a clump the range
            // touches (loads stay on the pieces they are given to, at their points).
            std::vector<int> held = blocks;
            std::sort(held.begin(), held.end());
            if (any_vel || a.has("free")) take_whole_clumps(ctx, held, any_vel ? "holding" : "releasing");
            std::vector<int> chosen = blocks;
            std::sort(chosen.begin(), chosen.end());
            for (int b : held) {
                if (s.flags[b] & kDeformable) continue;
                if (a.has("free")) {
                    s.vel_bc[b] = 0;
                    s.vel_bc_table[b] = 0;
                    if (std::binary_search(chosen.begin(), chosen.end(), b)) s.loads[b].clear();
                }
                for (int i = 0; i < 3; ++i) {
                    if (a.has(vel[i])) {
                        s.vel_bc[b] |= static_cast<std::uint8_t>(1 << i);
                        s.vel_bc_value[b][i] = a.real(vel[i]);
                        s.vel_bc_table[b] = table;
                    }
                }
            }
            if (any_load || any_moment) {
                for (size_t k = 0; k < rigid.size(); ++k) {
                    const int b = rigid[k];
                    // The same point as an earlier load, though the block has moved a little since.
                    const double tol = levers[k].isZero(0) ? 0.0 : 1e-3 * std::cbrt(s.volume[b]);
                    set_block_load(s.loads[b], LoadKind::Point, table, levers[k], tol, given, value);
                }
            }
            if (stress) {
                int n = m.zones.size() > 0 ? apply_boundary_stress(m, a.range, st, gx, gy, gz, table) : 0;
                const bool all[6] = {true, true, true, true, true, true};
                for (const FaceLoadOf& fl : face_loads) {
                    const double v[6] = {fl.force.x(), fl.force.y(), fl.force.z(),
                                         fl.couple.x(), fl.couple.y(), fl.couple.z()};
                    set_block_load(s.loads[fl.block], LoadKind::Face, table, fl.lever,
                                   1e-3 * std::cbrt(s.volume[fl.block]), all, v);
                }
                n += static_cast<int>(face_loads.size());
                if (n == 0) warn(ctx, a.find("stress")->loc, "the range selects no boundary face, nothing loaded");
                if (!ctx.interp.quiet) {
                    ctx.out << n << " boundary faces loaded";
                    // On one rigid block: the resultant, for checking.
                    bool one = !face_loads.empty();
                    for (const FaceLoadOf& fl : face_loads) one = one && fl.block == face_loads[0].block;
                    if (one) {
                        const int b = face_loads[0].block;
                        const Mat3 r = s.orientation[b].toRotationMatrix();
                        Vec3 f = Vec3::Zero(), mo = Vec3::Zero();
                        for (const FaceLoadOf& fl : face_loads) {
                            f += fl.force;
                            mo += fl.couple + (r * fl.lever).cross(fl.force);
                        }
                        ctx.out << "; on block " << s.id[b] << ": force " << vec_text(f) << " N, moment about its centroid "
                                << vec_text(mo) << " N m";
                    }
                    ctx.out << "\n";
                }
            }
            if ((any_load || any_moment) && (at_point || any_moment) && !ctx.interp.quiet && !rigid.empty()) {
                const Vec3 f(value[0], value[1], value[2]), cpl(value[3], value[4], value[5]);
                if (rigid.size() == 1) {
                    const int b = rigid[0];
                    ctx.out << "block " << s.id[b] << ": ";
                    if (any_load) ctx.out << "force " << vec_text(f) << " N" << (at_point ? " at " + vec_text(point) : std::string());
                    if (any_load && any_moment) ctx.out << ", ";
                    if (any_moment) ctx.out << "couple " << vec_text(cpl) << " N m";
                    if (at_point) ctx.out << "; moment about its centroid " << vec_text((point - s.centroid[b]).cross(f) + cpl) << " N m";
                } else {
                    ctx.out << rigid.size() << " blocks loaded" << (at_point ? " at " + vec_text(point) : std::string());
                }
                if (table > 0) ctx.out << ", times table " << table << " of time";
                ctx.out << "\n";
            }
            if (!outside.empty()) {
                warn(ctx, a.find("point")->loc,
                     "the point " + vec_text(point) + " lies outside block" + (outside.size() == 1 ? " " : "s ") +
                         ids_text(m, outside) + ": the load acts there as through a rigid arm");
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
