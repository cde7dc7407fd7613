#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/polyhedron.h"

#include <cmath>
#include "engine/zones.h"

namespace odec {

const CommandSpec& bound_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("boundary", 3, "prescribe block velocities or apply forces");
        c.alias("apply");
        c.keyword("xvelocity", 2, "hold the x velocity at v, m/s").real("v");
        c.keyword("yvelocity", 2, "hold the y velocity at v, m/s").real("v");
        c.keyword("zvelocity", 2, "hold the z velocity at v, m/s").real("v");
        c.keyword("xload", 2, "apply a force fx, N, to each block").real("fx");
        c.keyword("yload", 2, "apply a force fy, N, to each block").real("fy");
        c.keyword("zload", 2, "apply a force fz, N, to each block").real("fz");
        c.keyword("stress", 3, "apply the traction of this stress tensor (Pa, tension positive) on the "
                               "boundary faces (of rigid blocks: as a force at the centroid)")
            .real("sxx").real("syy").real("szz").real("sxy").real("sxz").real("syz");
        c.keyword("xgrad", 2, "with 'stress': its change per metre of x, Pa/m")
            .real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("ygrad", 2, "with 'stress': its change per metre of y, Pa/m")
            .real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("zgrad", 2, "with 'stress': its change per metre of z, Pa/m")
            .real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("history", 4, "scale the velocities by table n of time: v(t) = v table(t)").integer("table", 1).labelled();
        c.keyword("free", 3, "release prescribed velocities and remove applied forces");
        c.range();
        c.describe("A prescribed velocity component is held whatever the forces; the others stay free. "
                   "Loads add to gravity and contact forces. Without a range every block is taken. Rigid "
                   "blocks are selected by their centroid; in deformable blocks, velocities and loads act on "
                   "the gridpoints the range selects by their position (a load on each), and 'stress' on the "
                   "faces of zones on the surface of a continuum whose centre the range selects: each gets the "
                   "traction sigma n (n its outward normal; a negative normal stress pushes inward), replacing "
                   "an earlier 'stress' on that face. 'free' removes all of these.");
        c.example("bound xvel 0.01 range z 9 10");
        c.example("apply xvel 2.8 hist table 1 range z -1 0");
        c.example("bound zload -1e6 range id 5");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            BlockSet& s = m.blocks;
            const char* vel[3] = {"xvelocity", "yvelocity", "zvelocity"};
            const char* load[3] = {"xload", "yload", "zload"};
            bool any_vel = false, any = a.has("free") || a.has("stress");
            for (int i = 0; i < 3; ++i) {
                any_vel = any_vel || a.has(vel[i]);
                any = any || a.has(vel[i]) || a.has(load[i]);
            }
            if (!any) {
                fail(a.loc, "'boundary' needs a velocity (xvel ...), a load (xload ...), 'stress' or 'free'", {}, "boundary");
            }
            for (const char* gk : {"xgrad", "ygrad", "zgrad"}) {
                if (a.has(gk) && !a.has("stress")) {
                    fail(a.find(gk)->loc, std::string("'") + gk + "' goes with 'stress'", {}, "boundary");
                }
            }
            if (a.has("history") && !any_vel) {
                fail(a.find("history")->loc, "'hist table n' goes with a velocity", {}, "boundary");
            }
            const int table = a.has("history") ? a.integer("history") : 0;
            if (table > 0 && !m.tables.find(table)) {
                fail(a.find("history")->values[0].loc, "there is no table " + std::to_string(table),
                     {"define it first: table " + std::to_string(table) + " x1 y1 x2 y2 ..."}, "boundary");
            }
            const std::vector<int> gps = select_gridpoints(m, a.range);
            const std::vector<int> blocks = gps.empty() ? blocks_to_change(ctx, a) : select_blocks(m, a.range);
            GridpointSet& g = m.gridpoints;
            for (int i : gps) {
                if (a.has("free")) {
                    g.vel_bc[i] = 0;
                    g.vel_bc_table[i] = 0;
                    g.applied[i].setZero();
                    g.half_kick[i] = 1;
                }
                for (int k = 0; k < 3; ++k) {
                    if (a.has(vel[k])) {
                        g.vel_bc[i] |= static_cast<std::uint8_t>(1 << k);
                        g.vel_bc_value[i][k] = a.real(vel[k]);
                        g.vel_bc_table[i] = table;
                    }
                    if (a.has(load[k])) g.applied[i][k] = a.real(load[k]);
                }
            }
            if (a.has("free") && g.size() > 0) remove_boundary_stress(m, a.range);
            if (a.has("stress")) {
                auto six = [&](const char* k) {
                    Sym6 s = {0, 0, 0, 0, 0, 0};
                    if (a.has(k)) {
                        const KeywordUse* u = a.find(k);
                        for (int i = 0; i < 6; ++i) s[i] = u->values[i].number;
                    }
                    return s;
                };
                const Sym6 st = six("stress"), gx = six("xgrad"), gy = six("ygrad"), gz = six("zgrad");
                int n = m.zones.size() > 0 ? apply_boundary_stress(m, a.range, st, gx, gy, gz) : 0;
                // Rigid blocks: the traction on each free face whose centroid the range contains,
                // summed into a force at the block's centroid (as 'bound xload'; its moment about the
                // centroid is not applied).
                refresh_world_vertices(m);
                for (int b = 0; b < s.size(); ++b) {
                    if (s.flags[b] & (kDeformable | kExcavated)) continue;
                    const Polyhedron w = world_shape(m, b);
                    for (int f = 0; f < w.n_faces(); ++f) {
                        Vec3 c = Vec3::Zero();
                        for (int k = 0; k < w.face_size(f); ++k) c += w.vertices[w.face_vertex(f, k)];
                        c /= w.face_size(f);
                        if (!a.range.contains_point(m, c, b)) continue;
                        const Vec3 nrm = w.face_normal(f);
                        // A face against another block is no boundary.
                        const Vec3 probe = c + nrm * 1e-6 * std::max(1e-3, std::cbrt(s.volume[b]));
                        bool covered = false;
                        for (int o = 0; o < s.size() && !covered; ++o) {
                            if (o == b || (s.flags[o] & kExcavated)) continue;
                            if ((s.centroid[o] - probe).norm() > 4 * std::cbrt(s.volume[o]) + 4 * std::cbrt(s.volume[b])) continue;
                            covered = contains_point(world_shape(m, o), probe, 0);
                        }
                        if (covered) continue;
                        Sym6 sg;
                        for (int i = 0; i < 6; ++i) sg[i] = st[i] + gx[i] * c.x() + gy[i] * c.y() + gz[i] * c.z();
                        Mat3 sig;
                        sig << sg[0], sg[3], sg[4], sg[3], sg[1], sg[5], sg[4], sg[5], sg[2];
                        s.applied_force[b] += sig * nrm * w.face_area(f);
                        ++n;
                    }
                }
                if (n == 0) warn(ctx, a.find("stress")->loc, "the range selects no boundary face, nothing loaded");
                if (!ctx.interp.quiet) ctx.out << n << " boundary faces loaded\n";
            }
            if (!gps.empty()) m.geometry_changed = true;
            for (int b : blocks) {
                if (s.flags[b] & kDeformable) continue;
                if (a.has("free")) {
                    s.vel_bc[b] = 0;
                    s.vel_bc_table[b] = 0;
                    s.applied_force[b].setZero();
                }
                for (int i = 0; i < 3; ++i) {
                    if (a.has(vel[i])) {
                        s.vel_bc[b] |= static_cast<std::uint8_t>(1 << i);
                        s.vel_bc_value[b][i] = a.real(vel[i]);
                        s.vel_bc_table[b] = table;
                    }
                    if (a.has(load[i])) s.applied_force[b][i] = a.real(load[i]);
                }
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
