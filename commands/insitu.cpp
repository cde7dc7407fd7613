#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/insitu.h"
#include "engine/zones.h"

namespace odec {

const CommandSpec& insitu_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("insitu", 3, "set the initial stresses of zones");
        c.keyword("stress", 3, "the stress tensor, Pa (tension positive)")
            .real("sxx").real("syy").real("szz").real("sxy").real("sxz").real("syz");
        c.keyword("xgrad", 2, "its change per metre of x, Pa/m").real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("ygrad", 2, "its change per metre of y, Pa/m").real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.keyword("zgrad", 2, "its change per metre of z, Pa/m").real("gxx").real("gyy").real("gzz").real("gxy").real("gxz").real("gyz");
        c.range("which zones, by their centroid and block: see 'help range'");
        c.describe("Every zone of a deformable block whose centroid the range selects takes the stress "
                   "s + x xgrad + y ygrad + z zgrad, x, y, z its centroid. Stresses are tension positive, so "
                   "a rock mass under its own weight has negative szz growing with depth: with the surface at "
                   "z = 0, density rho and gravity g, 'insitu stress 0 0 0 0 0 0 zgrad k rho g, k rho g, "
                   "rho g, 0 0 0' (z negative below the surface). Such a state in equilibrium with gravity and "
                   "the boundaries starts without a jolt. The contacts (with a joint material) whose centroid "
                   "the range selects take the same stress at each sub-contact: normal and shear stress, and the "
                   "joint closure that carries it, so the joints start loaded too. Gridpoint displacements and "
                   "velocities are not changed.");
        c.example("insitu stress -15e6 -15e6 -30e6 0 0 0");
        c.example("insitu stress 0 0 0 0 0 0 zgrad 1.3e4 1.3e4 2.6e4 0 0 0");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
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
