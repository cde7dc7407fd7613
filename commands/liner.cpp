#include "commands.h"
#include "common.h"
#include "engine/liner.h"

namespace odec {

const CommandSpec& liner_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("liner", 3, "lay a liner (shotcrete, a lining) on the free faces of zoned blocks; delete one");
        c.range("the faces to line: those whose three corners it all contains (location filters test the corners, "
                "region, group and id filters the face's block)");
        c.keyword("property", 4, "with a range: its liner material ('prop mat=n li_...')").integer("n", 1, 1000000);
        c.keyword("axis", 2, "with a range: the axis of the liner's report frame (default: the range's cylinder axis, else z)")
            .vec("ax,ay,az");
        c.keyword("id", 2, "the liner that 'delete' acts on").integer("n", 1);
        c.keyword("delete", 3, "with 'id': delete the liner");
        c.describe(
            "A liner is a thin elastic shell of flat triangles laid on the zone faces of deformable blocks "
            "('gen edge') that face a void (no other standing block just outside them) and whose three corners "
            "all lie in the range: a thin annulus around a tunnel's wall, 'range cyl a b R+d not cyl a b R-d', "
            "picks its wall and not the faces across it. Its nodes are the corners of those faces, each with "
            "three translations and three rotations; each triangle is a flat shell (constant-strain membrane and "
            "discrete Kirchhoff plate bending) of the liner material's modulus li_e, Poisson's ratio li_nu and "
            "thickness li_thick, linear (small strains and rotations), unstressed when laid. Each node is bonded "
            "to the rock under it by a normal and a shear spring, li_kn and li_ks (Pa/m) times its share of the "
            "liner's area; the bond breaks in tension past li_ncut (Pa) and in shear past li_scoh (Pa) plus the "
            "normal pressure times tan(li_sfric); once broken it carries no tension and only friction in shear, "
            "so the liner may come off the rock. li_ks 0 is a liner that slides freely (full slip). "
            "'print liner' lists each element's forces and moments per unit width in its report frame: x in "
            "the element's plane across the axis (around a tunnel of that axis), y along it. n_x, n_y, n_xy: "
            "membrane forces, N/m, tension positive (a lining's thrust, compression positive, is -n_x); m_x, m_y, "
            "m_xy: bending moments, N m/m, positive when the face on the void's side (inside the tunnel) is in "
            "tension. 'hist liner_nx' and 'hist liner_mx' record them, 'plot liner' draws the liner coloured by "
            "n_x, 'export vtk' writes it, and FISH reads it (li_num, li_nx, li_mx ...). The liner's nodes "
            "have, in static mode, the masses that make the model's timestep their own stable one; in dynamic "
            "mode the shell's mass (li_dens) and a rotational inertia chosen from its stiffness. Liners are not "
            "in the energy account.");
        c.example("prop mat=2 li_e=30e9 li_nu=0.2 li_thick=0.2 li_dens=2500 li_kn=1e10 li_ks=1e10 li_ncut=1e6 li_scoh=2e6 li_sfric=35");
        c.example("liner range cyl 0,0,0 0,1,0 1.01 not cyl 0,0,0 0,1,0 0.99 prop 2");
        c.example("liner id 1 delete");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            LinerSet& ls = m.liners;
            if (a.has("delete")) {
                for (const char* k : {"property", "axis"}) {
                    if (a.has(k)) fail(a.find(k)->loc, std::string("'") + k + "' does not go with 'delete'", {}, "liner");
                }
                if (a.has_range) fail(a.loc, "'delete' takes the liner's 'id n', not a range", {}, "liner");
                if (!a.has("id")) fail(a.find("delete")->loc, "'delete' needs the liner: 'id n'", {}, "liner");
                const int c = ls.index(a.integer("id"));
                if (c < 0) fail(a.find("id")->values[0].loc, "there is no liner " + std::to_string(a.integer("id")), {"'print liner' lists them"}, "liner");
                remove_liners(m, {c});
                if (!ctx.interp.quiet) ctx.out << "liner " << a.integer("id") << " deleted\n";
                return;
            }
            if (a.has("id")) fail(a.find("id")->loc, "'id' goes with 'delete'", {}, "liner");
            if (!a.has_range) fail(a.loc, "a new liner needs a range: the faces it is laid on", {}, "liner");
            if (!a.has("property")) fail(a.loc, "a new liner needs its liner material: 'prop n'", {}, "liner");
            Vec3 axis = Vec3::Zero();
            if (a.has("axis")) {
                axis = a.vec("axis");
                if (!(axis.norm() > 0)) fail(a.find("axis")->values[0].loc, "the axis must not be zero", {}, "liner");
            }
            std::string why;
            const int c = add_liner(m, a.range, a.integer("property"), axis, why);
            if (c < 0) fail(a.loc, why, {}, "liner");
            if (!ctx.interp.quiet) {
                int bonded = 0;
                double area = 0;
                for (int i = ls.node_offset[c]; i < ls.node_offset[c + 1]; ++i) {
                    bonded += ls.host_block[i] > 0;
                    area += ls.area[i];
                }
                ctx.out << "liner " << ls.id[c] << ": " << ls.elem_offset[c + 1] - ls.elem_offset[c] << " elements, "
                        << ls.node_offset[c + 1] - ls.node_offset[c] << " nodes (" << bonded << " bonded), area "
                        << area << " m^2\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
