#include "commands.h"
#include "common.h"
#include "engine/flow.h"

namespace odec {

const CommandSpec& fluid_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("fluid", 3, "set the density, viscosity and bulk modulus of the fluid in the joints");
        c.keyword("density", 3, "fluid density, kg/m^3 (default 1000)").real("rho", 0, kMaxMagnitude, Limit::Open);
        c.keyword("viscosity", 3, "dynamic viscosity, Pa s (default 1e-3)").real("mu", 0, kMaxMagnitude, Limit::Open);
        c.keyword("bulk", 2, "fluid bulk modulus, Pa (default 2e9)").real("Kw", 0, kMaxMagnitude, Limit::Open);
        c.describe("Fluid flows along the joints between blocks, rigid or zoned, once 'config flow' is given (3DEC's 'config fluid'). "
                   "Flow nodes stand at the sub-contacts of the joints; nodes of different joints at one place are "
                   "one node, so water passes from joint to joint across block edges. Between two nodes of a joint "
                   "the flow follows the cubic law of a parallel-plate channel: per unit width q = a^3 / (12 mu) "
                   "times the drop of p - rho g . x per unit length (x the position, g gravity), m^2/s, a the "
                   "hydraulic aperture, azero - un held between ares and amax (joint material properties, m; un the "
                   "joint's closure, so a joint carrying an effective normal stress sn' has azero - sn'/jkn and an "
                   "open joint azero plus its gap). Each joint polygon is fanned into triangles over which the "
                   "pressure is linear (exact for a pressure varying linearly across the joint). A node's pressure "
                   "(Pa, never below 0) changes by Kw dt / V times its net inflow, V the sum of aperture x area of "
                   "its sub-contacts. 'set flow steady' (the default): each mechanical step the flow takes 'set "
                   "substeps' sub-steps, each node at its own stable step, so the pressures head for the steady "
                   "field (not along a real path in time). 'solve' waits for the flow to settle as well: "
                   "the sum of |net inflow| of the free nodes over the sum of |flow| of the links falls below its "
                   "ratio. 'set flow transient': the flow follows the model's time, "
                   "in sub-steps no larger than 0.8 of the smallest stable step V / (Kw sum c), and a joint closing "
                   "on its water raises the pressure (dp = -Kw dV / V). Boundaries are closed (no flow) unless a "
                   "pressure is fixed there ('bound pp'); 'insitu pp' sets initial pressures; with 'wtable z' both "
                   "give the hydrostatic pressure rho |g| (z - elevation) below the water table, and nodes made later "
                   "(new contacts) start at it. The pressure pushes both faces of the joint apart (p times the "
                   "sub-contact's area, along the normal) and the joint law works on the effective normal stress: "
                   "the joint springs carry sn' = jkn x closure, Coulomb's limit is c + sn' tan(phi). 'print flow' "
                   "lists the nodes, 'print contact' the mean pressure and aperture of each joint; 'hist pp x,y,z', "
                   "'hist aperture x,y,z', 'hist flowrate' record them; FISH has fl_pp, fl_aperture, fl_flow, fl_nnode; 'plot contact pp' "
                   "and 'plot contact aperture' colour the joints; 'export vtk' writes pore_pressure and aperture with the contacts. In zoned blocks the "
                   "flow nodes are the gridpoints on the joints, linked through the surface triangles that lie along "
                   "them, and the pressure pushes on those gridpoints over their faces flat to the joint; of two "
                   "zoned faces the larger follows the smaller's network (manual/fluid-flow.md). Joined cuts carry no "
                   "water. Not in the energy "
                   "account. A fluid property given without 'config flow' is an error.");
        c.example("config flow");
        c.example("fluid density 1000 viscosity 1e-3 bulk 2e9");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (!m.flow.configured) {
                fail(a.loc, "fluid flow is not configured", {"give 'config flow' first (3DEC writes 'config fluid')"}, "fluid");
            }
            if (a.uses.empty()) fail(a.loc, "'fluid' needs a property: density, viscosity or bulk", {}, "fluid");
            m.flow.density = a.real_or("density", m.flow.density);
            m.flow.viscosity = a.real_or("viscosity", m.flow.viscosity);
            m.flow.bulk = a.real_or("bulk", m.flow.bulk);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
