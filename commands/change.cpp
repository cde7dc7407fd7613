#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/zones.h"

namespace odec {

const CommandSpec& change_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("change", 4, "give blocks another material");
        c.keyword("material", 3, "block material number").integer("n", 1, 1000000);
        c.keyword("cons", 3, "zone model for deformable blocks (0 null, 1 elastic, 2 Mohr-Coulomb)").integer("c", 0, 2);
        c.keyword("jmat", 4, "joint material number of the contacts in the range").integer("n", 1, 1000000);
        c.keyword("jcons", 4, "joint model of the contacts in the range (1 Coulomb slip, 2 with residual strength)")
            .integer("j", 1, 2);
        c.range();
        c.describe("Blocks in the range (every block when no range is given) take the material; their "
                   "mass and inertia follow its density. Contacts whose centroid is in the range take the "
                   "joint material and joint model, except those of hidden blocks ('hide'); contacts made later take those of the joint plane they "
                   "lie on, or the defaults of 'set jmat' and 'set jcons'. 'cons' sets the zone model of the "
                   "zones whose centroid is in the range (0 null: the zone carries nothing, its stress and "
                   "plastic state are set to 0, so that a model given to it again starts it unstressed; 1 elastic; 2 "
                   "Mohr-Coulomb, with 'prop coh fric ten dil'), and of the rigid blocks of the range for "
                   "when they are zoned.");
        c.example("change mat=2 range z -10 0");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (!a.has("material") && !a.has("jmat") && !a.has("jcons") && !a.has("cons")) {
                fail(a.loc, "'change' needs 'mat=n', 'cons=c', 'jmat=n' or 'jcons=j'", {}, "change");
            }
            if (a.has("jmat") || a.has("jcons")) {
                // As in 3DEC, a joint material may be assigned before its properties are given
                // (they are read when the model cycles); say so, the command goes on.
                const int jmat = a.has("jmat") ? a.integer("jmat") : 0;
                if (a.has("jmat") && !(jmat < static_cast<int>(m.joint_materials.size()) && m.joint_materials[jmat].defined)) {
                    warn(ctx, a.find("jmat")->loc, "joint material " + std::to_string(jmat) +
                                                       " has no properties yet: give them ('prop jmat=" + std::to_string(jmat) +
                                                       " jkn ... jks ...') before the model cycles");
                }
                const int jcons = a.has("jcons") ? a.integer("jcons") : 0;
                // Contacts are brought up to date first: after cycling, by the incremental
                // update; when the model changed, assign_joint_material finds them all, once.
                if (!m.geometry_changed) {
                    refresh_world_vertices(m);
                    detect_contacts(m);
                }
                const int n = assign_joint_material(m, a.range, jmat, jcons);
                if (!ctx.interp.quiet) ctx.out << n << " contacts changed\n";
            }
            if (a.has("material")) {
                const int n = a.integer("material");
                const std::vector<int> blocks = blocks_to_change(ctx, a);
                // Check first: the density of material n must give each block a mass it can compute with.
                const double rho = n < static_cast<int>(m.materials.size()) ? m.materials[n].density : 0.0;
                for (int b : blocks) {
                    MassProperties mp;
                    mp.volume = m.blocks.volume[b];
                    mp.inertia = m.blocks.inertia_unit[b];
                    const std::string problem = block_numbers_problem(mp, rho);
                    if (!problem.empty()) {
                        fail(a.find("material")->values[0].loc, "block " + std::to_string(m.blocks.id[b]) + ": " + problem,
                             {}, "change");
                    }
                }
                for (int b : blocks) m.blocks.material[b] = n;
                update_masses(m);
            }
            if (a.has("cons")) {
                const int c = a.integer("cons");
                int zones = 0, blocks = 0;
                for (int b : select_blocks(m, a.range)) {
                    if (m.blocks.flags[b] & kDeformable) continue;
                    m.blocks.cons[b] = static_cast<std::uint8_t>(c);
                    ++blocks;
                }
                for (int z = 0; z < m.zones.size(); ++z) {
                    if (m.blocks.flags[m.zones.block[z]] & kExcavated) continue;
                    if (!a.range.contains_point(m, zone_centroid(m, z), m.zones.block[z])) continue;
                    m.zones.model[z] = static_cast<std::uint8_t>(c);
                    if (c == kZoneNull) {
                        m.zones.stress[z] = Sym6{0, 0, 0, 0, 0, 0};
                        m.zones.state[z] = 0;
                    }
                    ++zones;
                }
                m.geometry_changed = true;
                if (zones + blocks == 0) warn(ctx, a.find("cons")->loc, "the range selects no zone or block, nothing changed");
                if (!ctx.interp.quiet) ctx.out << zones << " zones and " << blocks << " rigid blocks take zone model " << c << "\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
