#include "commands.h"
#include "common.h"
#include "engine/cable.h"

namespace odec {

const CommandSpec& cable_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("cable", 3, "create a fully grouted cable or rock bolt; drive, release or delete one");
        c.positional.vec("x1,y1,z1").optional().vec("x2,y2,z2").optional();
        c.keyword("segments", 3, "with the two ends: the number of segments the cable is cut into").integer("n", 1, 10000);
        c.keyword("property", 4, "with the two ends: its cable material ('prop mat=n cb_...')").integer("n", 1, 1000000);
        c.keyword("pretension", 3, "with the two ends: the axial force every segment starts with, N (tension positive)")
            .real("t", 0, kMaxMagnitude);
        c.keyword("id", 2, "the cable that 'node', 'velocity', 'free' and 'delete' act on").integer("n", 1);
        c.keyword("node", 2, "with 'id': the node, from 1 at the cable's first end").integer("k", 1);
        c.keyword("velocity", 3, "with 'id' and 'node': drive the node at this velocity, m/s (all three components)")
            .vec("vx,vy,vz")
            .in_choice(1);
        c.keyword("free", 3, "with 'id' and 'node': release the node's prescribed velocity").in_choice(1);
        c.keyword("delete", 3, "with 'id': delete the cable").in_choice(1);
        c.describe("A cable from (x1,y1,z1) to (x2,y2,z2) is cut into n equal segments, its nodes at their ends. Each "
                   "segment is an axial bar of the steel (cb_area, cb_e) that yields at cb_yield in tension and "
                   "cb_ycomp in compression (forces, N; cb_ycomp 0: it carries no compression, as a cable). Each node "
                   "is tied to the block holding it, rigid or deformable, through the grout: along the cable a shear "
                   "spring of stiffness cb_kbond (N/m per m of cable) times the node's share of the cable's length, "
                   "which slips at cb_sbond (N/m) times that length; across the cable it moves with the rock. A node "
                   "in no block has no grout. So a cable crossing a joint carries the joint's opening and shearing as "
                   "axial force. Cables are numbered from 1 in the order they are made. 'print cable' lists their "
                   "forces (axial force tension positive; grout force on the cable along it, from its first node to "
                   "its last), 'hist cable_force' and 'hist cable_grout' record them. A node driven with 'velocity' "
                   "moves at that velocity until 'free'. The timestep and the nodes' masses follow the cables' "
                   "stiffness (in static mode every node gets the mass that makes the model's timestep its own "
                   "stable one; in dynamic mode the steel's mass, cb_dens); under gravity the steel weighs its real mass. "
                   "A node is tied to the first block (in the order blocks were made) that holds it, so a node "
                   "exactly on a joint goes with the block made first: cut the cable so that its nodes fall "
                   "either side of the joints it crosses. A node keeps its tie while the rock holding it stands; "
                   "when that block is deleted, excavated, cut away or zoned anew, the node is tied afresh to "
                   "whatever holds it then (or to nothing: no grout). Cables are not in the energy account.");
        c.example("prop mat=2 cb_area=1.81e-4 cb_e=98.6e9 cb_yield=0.5e6 cb_kbond=112e6 cb_sbond=0.175e6 cb_dens=7800");
        c.example("cable 0,0,0 0,0,-3 seg 10 prop 2");
        c.example("cable 0,0,0 0,0,-3 seg 10 prop 2 pretension 5e4");
        c.example("cable id 1 node 1 velocity 0,0,1e-5");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            CableSet& cs = m.cables;
            const bool create = !a.positional.empty();
            const std::string act = a.chosen(1);
            if (create) {
                if (a.positional.size() < 2) fail(a.positional[0].loc, "a cable needs both ends: x1,y1,z1 x2,y2,z2", {}, "cable");
                for (const char* k : {"id", "node", "velocity", "free", "delete"}) {
                    if (a.has(k)) fail(a.find(k)->loc, std::string("'") + k + "' does not go with the two ends of a new cable", {}, "cable");
                }
                if (!a.has("segments")) fail(a.loc, "a new cable needs its number of segments: 'seg n'", {}, "cable");
                if (!a.has("property")) fail(a.loc, "a new cable needs its cable material: 'prop n'", {}, "cable");
                std::string why;
                const int c = add_cable(m, a.positional[0].vec, a.positional[1].vec, a.integer("segments"),
                                        a.integer("property"), a.real_or("pretension", 0.0), why);
                if (c < 0) fail(a.loc, why, {}, "cable");
                if (!ctx.interp.quiet) {
                    int tied = 0;
                    for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) tied += cs.host_block[i] > 0;
                    ctx.out << "cable " << cs.id[c] << ": " << cs.segments_of(c) << " segments, "
                            << cs.segments_of(c) + 1 << " nodes, " << tied << " grouted into blocks\n";
                }
                return;
            }
            for (const char* k : {"segments", "property", "pretension"}) {
                if (a.has(k)) fail(a.find(k)->loc, std::string("'") + k + "' goes with the two ends of a new cable", {}, "cable");
            }
            if (!a.has("id")) fail(a.loc, "give the two ends of a new cable, or 'id n' with 'node k velocity ...', 'free' or 'delete'", {}, "cable");
            const int c = cs.index(a.integer("id"));
            if (c < 0) fail(a.find("id")->values[0].loc, "there is no cable " + std::to_string(a.integer("id")), {}, "cable");
            if (act.empty()) fail(a.loc, "say what to do with the cable: 'node k velocity vx,vy,vz', 'node k free' or 'delete'", {}, "cable");
            if (act == "delete") {
                if (a.has("node")) fail(a.find("node")->loc, "'node' does not go with 'delete'", {}, "cable");
                const int id = cs.id[c];
                remove_cables(m, {c});
                if (!ctx.interp.quiet) ctx.out << "cable " << id << " deleted\n";
                return;
            }
            if (!a.has("node")) fail(a.find(act)->loc, "'" + act + "' needs the node: 'node k'", {}, "cable");
            const int k = a.integer("node");
            if (k > cs.segments_of(c) + 1) {
                fail(a.find("node")->values[0].loc, "cable " + std::to_string(cs.id[c]) + " has " +
                                                        std::to_string(cs.segments_of(c) + 1) + " nodes", {}, "cable");
            }
            const int i = cs.node_offset[c] + k - 1;
            if (act == "velocity") {
                cs.vel_bc[i] = 1;
                cs.vel_bc_value[i] = a.vec("velocity");
                cs.vel[i] = cs.vel_bc_value[i];
            } else {
                cs.vel_bc[i] = 0;
            }
            m.geometry_changed = true; // the node's mass and the timestep follow
        });
        return c;
    }();
    return spec;
}

} // namespace odec
