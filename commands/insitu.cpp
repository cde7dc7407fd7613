#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/flow.h"
#include "engine/insitu.h"
#include "engine/zones.h"

namespace odec {

const CommandSpec& insitu_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("insitu", 3, "set the initial stresses of zones and joints");
        c.keyword("stress", 3, "the stress tensor, Pa (tension positive)")
            .real("sxx").real("syy").real("szz").real("sxy").real("sxz").real("syz");
        c.keyword("xgrad", 2, "its change per metre of x, Pa/m").real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("ygrad", 2, "its change per metre of y, Pa/m").real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("zgrad", 2, "its change per metre of z, Pa/m").real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("pp", 2, "the initial pore pressure of the joints' flow nodes, Pa ('config flow' first)").real("p", 0, kMaxMagnitude);
        c.keyword("pgrad", 3, "with 'pp': its change per metre, Pa/m: p + g . x at node x").vec("gx,gy,gz");
        c.keyword("wtable", 2, "the hydrostatic pore pressure below a water table at this elevation, m (kept for nodes made later)")
            .real("z", -kMaxMagnitude, kMaxMagnitude);
        c.range("which zones and contacts, by their centroid and block: see 'help range'");
        c.describe("Every zone of a deformable block whose centroid the range selects takes the stress "
                   "s + x xgrad + y ygrad + z zgrad, x, y, z its centroid. Stresses are tension positive, so "
                   "a rock mass under its own weight has negative szz growing with depth: with the surface at "
                   "z = 0, density rho and gravity g, 'insitu stress 0 0 0 0 0 0 zgrad k rho g, k rho g, "
                   "rho g, 0 0 0' (z negative below the surface). "
                   "The joints take the same field: every contact with a joint material whose centroid the "
                   "range selects (contacts are found first when the model changed) carries, at each "
                   "sub-contact, the traction sigma n of the field on the joint plane (n the contact normal), "
                   "as a normal stress (compression positive) and a shear stress, and the joint closure that "
                   "carries the normal stress (sn / jkn). This is so for joints between deformable blocks, "
                   "between rigid ones and between the two kinds, and for joined joints, so a jointed model "
                   "whose field is in equilibrium with gravity and its boundaries ('bound stress' with the same "
                   "tensor on the outer faces, or velocities held there) starts at rest: rigid blocks inside the "
                   "rock are held by their joints as the zones are. Only the face-to-face part of a joint is "
                   "loaded; blocks that meet only along an edge or at a corner (where joint sets cross) start "
                   "unloaded there, and the command counts those sub-contacts. Where meshes on the two sides of a "
                   "joint do not match (blocks zoned in separate 'gen' commands, or faces that are not the same "
                   "polygon on both sides), the joint still takes the field, but the gridpoints there start with "
                   "small forces out of balance, and the model settles a little. "
                   "A joint cannot start beyond its strength: where the field's shear stress exceeds its Coulomb "
                   "strength (jcoh + sn tan jfric), the shear stress is capped there and the joint starts "
                   "slipping; where the field pulls it apart beyond its tensile strength (jten), it starts open "
                   "and unloaded; either way it fails, as the joint law would have it (cohesion and tension lost; "
                   "residual friction under jcons 2), and a warning gives the number of such sub-contacts. A "
                   "joined joint has no limits. A contact without a joint material with a normal stiffness "
                   "cannot carry stress: it is left unloaded, with a warning. "
                   "The model keeps the field (it is saved with the model): blocks zoned later by 'gen' give "
                   "their new zones, and their joints, the fields given before, each over its own range, in "
                   "order. So 'insitu' may come before 'gen', as with rigid blocks that are zoned later. "
                   "Other contacts found later (blocks that come into contact as the model moves, blocks added "
                   "or cut after 'insitu' and not zoned afterwards) start unloaded: they were not joints of the "
                   "rock when its stress was given. Gridpoint displacements and velocities are not changed; 'insitu' given again sets the "
                   "stresses again.\n\n"
                   "'pp p' (with 'pgrad g': p + g . x) or 'wtable z' (rho |g| (z - elevation) below a water table at "
                   "elevation z, 0 above it) set the pore pressure of the joints' flow nodes the range selects "
                   "('config flow', 'help fluid'); nodes with a fixed pressure ('bound pp') keep theirs. The water "
                   "table is kept: nodes made later (new contacts) start at its pressure. They go without 'stress'. "
                   "The rock's total stress stays: a joint already loaded ('insitu stress', or a settled model) "
                   "hands the change of pressure to its springs (effective stress sn - p, capped by the joint's "
                   "strength), and 'insitu stress' given with water in the joints loads the springs with the "
                   "field's normal stress less the water's pressure, so a model with water starts at rest too.");
        c.example("insitu stress -15e6 -15e6 -30e6 0 0 0");
        c.example("insitu stress 0 0 0 0 0 0 zgrad 1.3e4 1.3e4 2.6e4 0 0 0");
        c.example("insitu wtable 30");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (a.has("pp") || a.has("pgrad") || a.has("wtable")) {
                const KeywordUse* first = a.find("pp") ? a.find("pp") : a.find("wtable") ? a.find("wtable") : a.find("pgrad");
                if (!m.flow.configured) fail(first->loc, "fluid flow is not configured", {"give 'config flow' first (3DEC writes 'config fluid')"}, "insitu");
                for (const KeywordUse& u : a.uses) {
                    const std::string& n = u.spec->name;
                    if (n != "pp" && n != "pgrad" && n != "wtable" && n != "range") {
                        fail(u.loc, "'" + n + "' does not go with the pore pressure ('pp', 'wtable')", {}, "insitu");
                    }
                }
                if (a.has("pgrad") && !a.has("pp")) fail(a.find("pgrad")->loc, "'pgrad' goes with 'pp'", {}, "insitu");
                if (a.has("pp") && a.has("wtable")) fail(a.find("wtable")->loc, "'wtable' and 'pp' exclude each other", {}, "insitu");
                if (a.has("wtable") && !(m.gravity.norm() > 0)) {
                    fail(a.find("wtable")->loc, "a water table needs gravity to say which way is down", {"set grav 0 0 -9.81"}, "insitu");
                }
                if (m.blocks.size() == 0) fail(a.loc, "there are no blocks, so no joints to hold a pressure", {}, "insitu");
                flow_ready(m);
                std::vector<int> nodes;
                for (int i : flow_nodes_in_range(m, a.range)) {
                    if (!m.flow.fixed[i]) nodes.push_back(i);
                }
                if (nodes.empty() && !a.has("wtable")) {
                    fail(a.loc, m.flow.n_nodes() == 0 ? "there is no joint between rigid blocks, so no flow node to hold a pressure"
                                                      : "the range selects no free flow node (no joint there, or all fixed)",
                         {"flow nodes stand at the sub-contacts of the joints: 'print flow' lists them"}, "insitu");
                }
                const std::vector<double> old_pp = m.flow.pp;
                const int n = set_flow_pressure(m, nodes, pressure_spec(m, a), false);
                const int shifted = shift_joint_water(m, old_pp);
                if (!ctx.interp.quiet) {
                    ctx.out << n << " flow node" << (n == 1 ? "" : "s") << " set";
                    if (shifted > 0) {
                        ctx.out << "; the joints' springs carry the change at " << shifted << " sub-contact"
                                << (shifted == 1 ? "" : "s") << " (the total stress stays)";
                    }
                    ctx.out << "\n";
                }
                return;
            }
            if (!a.has("stress") && !a.has("xgrad") && !a.has("ygrad") && !a.has("zgrad")) {
                fail(a.loc, "'insitu' needs 'stress sxx syy szz sxy sxz syz'", {}, "insitu");
            }
            if (m.blocks.size() == 0) fail(a.loc, "there are no blocks to take the stress", {}, "insitu");
            auto six = [&](const char* k) {
                Sym6 s = {0, 0, 0, 0, 0, 0};
                if (const KeywordUse* u = a.find(k)) {
                    for (int i = 0; i < 6; ++i) s[i] = u->values[i].number;
                }
                return s;
            };
            const StressField f{six("stress"), six("xgrad"), six("ygrad"), six("zgrad")};
            // Rigid blocks the range selects take the field when they are zoned.
            bool rigid = false;
            for (int b : select_blocks(m, a.range)) rigid = rigid || !(m.blocks.flags[b] & kDeformable);
            const InsituCount c = apply_insitu(m, a.range, f);
            if (c.zones == 0 && c.contacts == 0 && c.no_stiffness == 0 && !rigid) {
                m.insitu.pop_back();
                fail(a.loc, "the range selects no zone, no contact and no block to zone later",
                     {"zones are selected by their centroid, contacts by theirs"}, "insitu");
            }
            report_insitu(ctx, a.loc, c, "");
            if (rigid && !ctx.interp.quiet) ctx.out << "the stress is kept for the zones 'gen' makes in the rigid blocks of the range\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
