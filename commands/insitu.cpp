#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/contact.h"
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
            auto six = [&](const char* k) {
                Sym6 s = {0, 0, 0, 0, 0, 0};
                if (const KeywordUse* u = a.find(k)) {
                    for (int i = 0; i < 6; ++i) s[i] = u->values[i].number;
                }
                return s;
            };
            // Zones first: a range that selects no zone leaves the contacts alone too. A model of
            // rigid blocks only takes the stress on its joints (3DEC does the same).
            if (m.zones.size() == 0) {
                refresh_world_vertices(m);
                detect_contacts(m);
                const int nc = set_insitu_contact_stress(m, a.range, six("stress"), six("xgrad"), six("ygrad"), six("zgrad"));
                if (nc == 0) {
                    fail(a.loc, "there are no zones and the range selects no contact: nothing would take the stress",
                         {"rigid blocks carry stress only on their joints; divide blocks into zones with 'gen edge e'"},
                         "insitu");
                }
                if (!ctx.interp.quiet) ctx.out << "0 zones (rigid blocks) and " << nc << " contacts set\n";
                return;
            }
            const int n = set_insitu_stress(m, a.range, six("stress"), six("xgrad"), six("ygrad"), six("zgrad"));
            if (n == 0) {
                fail(a.loc, "the range selects no zone", {"zones are selected by their centroid; rigid blocks have none"},
                     "insitu");
            }
            const int nc = set_insitu_contact_stress(m, a.range, six("stress"), six("xgrad"), six("ygrad"), six("zgrad"));
            if (!ctx.interp.quiet) ctx.out << n << " zones and " << nc << " contacts set\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
