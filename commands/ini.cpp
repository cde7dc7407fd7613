#include "commands.h"
#include "common.h"
#include <algorithm>

#include "engine/blocks.h"
#include "engine/clump.h"
#include "engine/zones.h"

namespace odec {

const CommandSpec& ini_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("initial", 3, "give blocks an initial velocity or spin");
        c.keyword("xvel", 2, "velocity x component, m/s").real("v");
        c.keyword("yvel", 2, "velocity y component, m/s").real("v");
        c.keyword("zvel", 2, "velocity z component, m/s").real("v");
        c.keyword("xrvel", 3, "spin (rotational velocity) of a rigid block about the x axis through its centroid, "
                              "rad/s, right-hand rule").real("w");
        c.keyword("yrvel", 3, "spin about the y axis through the centroid, rad/s").real("w");
        c.keyword("zrvel", 3, "spin about the z axis through the centroid, rad/s").real("w");
        c.range();
        c.describe("The velocity is that of the blocks' centroids at the present time, the spin their "
                   "angular velocity about the world axes; components not given are kept. Fixed blocks stay "
                   "still. A spin is for rigid blocks: in a deformable block each gridpoint has a velocity of "
                   "its own. A clump (the blocks of a solid that is not convex, 'poly') moves as one rigid "
                   "body: the velocity is that of its centroid, the spin about its centroid, given to the whole "
                   "clump when the range selects any of its blocks.");
        c.example("ini zvel -1 range group 'falling'");
        c.example("ini zrvel 0.5 range id 3");
        c.handle([](CommandContext& ctx, const Args& a) {
            static const char* const kWords[6] = {"xvel", "yvel", "zvel", "xrvel", "yrvel", "zrvel"};
            bool any = false;
            for (const char* w : kWords) any = any || a.has(w);
            if (!any) fail(a.loc, "'initial' needs one of: xvel, yvel, zvel, xrvel, yrvel, zrvel", {}, "initial");
            BlockSet& s = ctx.model.blocks;
            // In deformable blocks, the gridpoints the range selects by their position.
            GridpointSet& g = ctx.model.gridpoints;
            const std::vector<int> gps = select_gridpoints(ctx.model, a.range);
            for (const char* w : {"xrvel", "yrvel", "zrvel"}) {
                if (a.has(w) && !gps.empty()) {
                    fail(a.find(w)->loc, "'" + std::string(w) + "' spins rigid blocks: the range holds gridpoints of deformable blocks",
                         {"narrow the range to rigid blocks; a deformable block's gridpoints take 'xvel', 'yvel', 'zvel'"},
                         "initial");
                }
            }
            for (int i : gps) {
                for (int k = 0; k < 3; ++k) {
                    const char* w = k == 0 ? "xvel" : k == 1 ? "yvel" : "zvel";
                    if (a.has(w) && !(g.vel_bc[i] & (1 << k))) g.vel[i][k] = a.real(w);
                }
                g.half_kick[i] = 1;
            }
            std::vector<int> blocks = gps.empty() ? blocks_to_change(ctx, a) : select_blocks(ctx.model, a.range);
            take_whole_clumps(ctx, blocks, "moving");
            // A clump: the velocity of its centroid and its spin, every piece the rigid motion's
            // velocity at its own centroid.
            std::vector<int> done;
            for (int b : blocks) {
                if (s.clump[b] == 0 || std::find(done.begin(), done.end(), s.clump[b]) != done.end()) continue;
                done.push_back(s.clump[b]);
                const std::vector<int> pieces = clump_pieces(s, b);
                bool held = false;
                for (int i : pieces) held = held || (s.flags[i] & (kFixed | kDeformable));
                if (held) continue;
                // Its motion at the present time, from its pieces' at that time.
                std::vector<Vec3> vel, spin;
                for (int i : pieces) {
                    vel.push_back(velocity_at_t(ctx.model, i));
                    spin.push_back(spin_at_t(ctx.model, i));
                }
                const ClumpBody body =
                    clump_body(s, pieces.data(), static_cast<int>(pieces.size()), vel.data(), spin.data());
                Vec3 v = body.vel, w = body.spin;
                for (int k = 0; k < 3; ++k) {
                    if (a.has(kWords[k])) v[k] = a.real(kWords[k]);
                    if (a.has(kWords[3 + k])) w[k] = a.real(kWords[3 + k]);
                }
                set_clump_motion(s, pieces.data(), static_cast<int>(pieces.size()), v, w);
            }
            for (int b : blocks) {
                if ((s.flags[b] & (kFixed | kDeformable)) || s.clump[b] != 0) continue;
                // Given at the present time: the components kept are taken at it too (the
                // integration holds them half a step back).
                Vec3 v = velocity_at_t(ctx.model, b), w = spin_at_t(ctx.model, b);
                for (int k = 0; k < 3; ++k) {
                    if (a.has(kWords[k])) v[k] = a.real(kWords[k]);
                    if (a.has(kWords[3 + k])) w[k] = a.real(kWords[3 + k]);
                }
                s.vel[b] = v;
                s.ang_vel[b] = w;
                s.half_kick[b] = 1;
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
