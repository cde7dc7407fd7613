#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/stages.h"
#include "engine/liner.h"

namespace odec {



const CommandSpec& prop_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("property", 4, "set the properties of a block material or a joint material");
        c.keyword("material", 3, "block material number").integer("n", 1, 1000000).in_choice(1);
        c.keyword("jmat", 4, "joint material number").integer("n", 1, 1000000).in_choice(1);
        c.keyword("density", 3, "mass density, kg/m^3").real("rho", 0, kInf, Limit::Open);
        c.keyword("bulk", 2, "bulk modulus K, Pa (deformable blocks)").real("K", 0, kInf, Limit::Open);
        c.keyword("k", 1, "bulk modulus K, Pa (same as 'bulk')").real("K", 0, kInf, Limit::Open);
        c.keyword("shear", 2, "shear modulus G, Pa (deformable blocks)").real("G", 0, kInf, Limit::Open);
        c.keyword("g", 1, "shear modulus G, Pa (same as 'shear')").real("G", 0, kInf, Limit::Open);
        c.keyword("ymod", 2, "Young's modulus E, Pa (with 'prat', instead of K and G)").real("E", 0, kInf, Limit::Open);
        c.keyword("prat", 2, "Poisson's ratio (with 'ymod')").real("nu", -1, 0.5, Limit::Open, Limit::Open);
        c.keyword("cohesion", 3, "cohesion, Pa (Mohr-Coulomb zones)").real("c", 0);
        c.keyword("friction", 3, "friction angle, degrees (Mohr-Coulomb zones)").real("phi", 0, 90, Limit::Closed, Limit::Open);
        c.keyword("tension", 3, "tensile strength, Pa (Mohr-Coulomb zones)").real("t", 0);
        c.keyword("dilation", 3, "dilation angle, degrees (Mohr-Coulomb zones)").real("psi", 0, 90, Limit::Closed, Limit::Open);
        c.keyword("jkn", 3, "joint normal stiffness, Pa/m").real("kn", 0, 1e18, Limit::Open);
        c.keyword("jks", 3, "joint shear stiffness, Pa/m").real("ks", 0, 1e18, Limit::Open);
        c.keyword("jfriction", 3, "joint friction angle, degrees").real("phi", 0, 90, Limit::Closed, Limit::Open);
        c.keyword("jcohesion", 3, "joint cohesion, Pa (lost once the joint fails)").real("c", 0);
        c.keyword("jtension", 3, "joint tensile strength, Pa (lost once the joint fails)").real("t", 0);
        c.keyword("jdilation", 3, "joint dilation angle, degrees").real("psi", 0, 90, Limit::Closed, Limit::Open);
        c.keyword("jzdilation", 3, "shear displacement at which dilation stops, m (0: never)").real("u", 0);
        c.keyword("zdilation", 3, "same as 'jzdilation' (the older name)").real("u", 0);
        c.keyword("jres_friction", 4, "residual friction angle after failure, degrees (joint model 2)")
            .real("phi", 0, 90, Limit::Closed, Limit::Open);
        c.keyword("azero", 3, "joint: hydraulic aperture at zero effective normal stress, m (fluid flow)").real("a", 0, 1e3);
        c.keyword("ares", 3, "joint: residual (smallest) hydraulic aperture, m").real("a", 0, 1e3);
        c.keyword("amax", 3, "joint: largest hydraulic aperture, m (0: no cap)").real("a", 0, 1e3);
        c.keyword("cb_area", 5, "cable: cross-section area of the steel, m^2").real("A", 0, kMaxMagnitude, Limit::Open);
        c.keyword("cb_e", 4, "cable: Young's modulus of the steel, Pa").real("E", 0, kMaxMagnitude, Limit::Open);
        c.keyword("cb_yield", 4, "cable: tensile yield force, N (0: no limit)").real("F", 0, kMaxMagnitude);
        c.keyword("cb_ycomp", 4, "cable: compressive yield force, N (0: the cable carries no compression)").real("F", 0, kMaxMagnitude);
        c.keyword("cb_kbond", 4, "cable: grout shear stiffness per unit length of cable, N/m/m").real("k", 0, kMaxMagnitude);
        c.keyword("cb_sbond", 4, "cable: grout bond strength per unit length of cable, N/m (0: no limit)").real("s", 0, kMaxMagnitude);
        c.keyword("cb_dens", 4, "cable: density of the steel, kg/m^3 (the nodes' masses in dynamic mode)").real("rho", 0, kMaxMagnitude);
        c.keyword("li_e", 4, "liner: Young's modulus of the shell, Pa").real("E", 0, kMaxMagnitude, Limit::Open);
        c.keyword("li_nu", 5, "liner: Poisson's ratio of the shell").real("nu", -1, 0.5, Limit::Open, Limit::Open);
        c.keyword("li_thick", 4, "liner: thickness of the shell, m").real("t", 0, kMaxMagnitude, Limit::Open);
        c.keyword("li_dens", 4, "liner: density of the shell, kg/m^3 (its weight; the nodes' masses in dynamic mode)")
            .real("rho", 0, kMaxMagnitude);
        c.keyword("li_kn", 5, "liner: bond normal stiffness per unit area, Pa/m").real("kn", 0, kMaxMagnitude);
        c.keyword("li_ks", 5, "liner: bond shear stiffness per unit area, Pa/m (0: the liner slides freely)")
            .real("ks", 0, kMaxMagnitude);
        c.keyword("li_ncut", 5, "liner: bond tensile strength, Pa (not given: no limit)").real("t", 0, kMaxMagnitude);
        c.keyword("li_scoh", 5, "liner: bond shear cohesion, Pa (not given: no limit)").real("c", 0, kMaxMagnitude);
        c.keyword("li_sfric", 5, "liner: bond friction angle, degrees").real("phi", 0, 90, Limit::Closed, Limit::Open);
        c.require_one_of(1);
        c.describe("Properties not given keep their earlier values (0 for a new material). Block "
                   "properties go with 'mat', joint properties (those starting with j) with 'jmat'. "
                   "Changing the density of a material updates the mass of its blocks. Cable properties "
                   "(those starting with cb_) also go with 'mat': they make the cable material of that "
                   "number, which 'cable ... prop n' takes; a material number may hold block and cable "
                   "properties side by side. The hydraulic apertures of a joint (azero, ares, amax, m) also go with "
                   "'jmat': the aperture of a joint for fluid flow is azero less its closure, held between ares and "
                   "amax ('help fluid'). Liner properties (those starting with li_) make the liner "
                   "material of that number, which 'liner ... prop n' takes (see 'help liner'); li_ncut and "
                   "li_scoh not given mean a bond that never breaks.");
        c.example("prop mat=3 li_e=30e9 li_nu=0.2 li_thick=0.2 li_dens=2500 li_kn=1e10 li_ks=1e10 li_ncut=1e6 li_scoh=2e6 li_sfric=35");
        c.example("prop mat=2 cb_area=1.81e-4 cb_e=98.6e9 cb_yield=0.5e6 cb_kbond=112e6 cb_sbond=0.175e6");
        c.example("prop mat=1 dens=2700");
        c.example("prop jmat=1 jkn=1e10 jks=5e9 jfric=30 jcoh=0 jten=0");
        c.example("prop jmat=1 azero=1e-4 ares=2e-5 amax=1e-3");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const bool joint = a.chosen(1) == "jmat";
            // Check first: no joint property on a block material and no block property on a joint one.
            for (const KeywordUse& u : a.uses) {
                const std::string& n = u.spec->name;
                if (n == "material" || n == "jmat") continue;
                const bool is_joint = n[0] == 'j' || n == "zdilation" || n == "azero" || n == "ares" || n == "amax";
                if (is_joint != joint) {
                    const char* kind = is_joint ? "joint" : n.compare(0, 3, "cb_") == 0 ? "cable"
                                                          : n.compare(0, 3, "li_") == 0 ? "liner" : "block";
                    fail(u.loc, "'" + n + "' is a " + kind + " property: give it with '" +
                                    (is_joint ? "jmat" : "mat") + "=n'",
                         {}, "property");
                }
            }
            if (joint) {
                const int n = a.integer("jmat");
                {
                    // Checked first: a refused command changes nothing.
                    const JointMaterial old = n < static_cast<int>(m.joint_materials.size()) ? m.joint_materials[n] : JointMaterial();
                    const double ares = a.real_or("ares", old.ares), amax = a.real_or("amax", old.amax);
                    if (amax > 0 && amax < ares) {
                        fail((a.has("amax") ? a.find("amax") : a.find("ares"))->loc,
                             "the largest hydraulic aperture (amax " + num_text(amax) + " m) is below the residual one (ares " +
                                 num_text(ares) + " m)", {}, "property");
                    }
                }
                ensure_index(m.joint_materials, n);
                JointMaterial& j = m.joint_materials[n];
                j.defined = true;
                j.kn = a.real_or("jkn", j.kn);
                j.ks = a.real_or("jks", j.ks);
                j.friction = a.real_or("jfriction", j.friction);
                j.cohesion = a.real_or("jcohesion", j.cohesion);
                j.tension = a.real_or("jtension", j.tension);
                j.dilation = a.real_or("jdilation", j.dilation);
                j.zdilation = a.real_or("zdilation", a.real_or("jzdilation", j.zdilation));
                j.res_friction = a.real_or("jres_friction", j.res_friction);
                j.azero = a.real_or("azero", j.azero);
                j.ares = a.real_or("ares", j.ares);
                j.amax = a.real_or("amax", j.amax);
                m.geometry_changed = true; // stiffness may change the timestep
                return;
            }
            const int n = a.integer("material");
            bool block_props = false, cable_props = false, liner_props = false;
            for (const KeywordUse& u : a.uses) {
                const std::string& kw = u.spec->name;
                if (kw == "material") continue;
                (kw.compare(0, 3, "cb_") == 0 ? cable_props : kw.compare(0, 3, "li_") == 0 ? liner_props : block_props) = true;
            }
            // Liner properties, likewise computed and checked first, stored last.
            LinerMaterial liner_mat;
            if (liner_props) {
                const LinerSet& ls = m.liners;
                LinerMaterial& p = liner_mat;
                p = n < static_cast<int>(ls.materials.size()) ? ls.materials[n] : LinerMaterial();
                p.defined = true;
                p.e = a.real_or("li_e", p.e);
                p.nu = a.real_or("li_nu", p.nu);
                p.thick = a.real_or("li_thick", p.thick);
                p.density = a.real_or("li_dens", p.density);
                p.kn = a.real_or("li_kn", p.kn);
                p.ks = a.real_or("li_ks", p.ks);
                p.ncut = a.real_or("li_ncut", p.ncut);
                p.scoh = a.real_or("li_scoh", p.scoh);
                p.sfric = a.real_or("li_sfric", p.sfric);
                for (int c = 0; c < ls.size(); ++c) {
                    if (ls.material[c] == n && (!(p.e > 0) || !(p.thick > 0))) {
                        fail(a.loc, "liner " + std::to_string(ls.id[c]) + " is of material " + std::to_string(n) +
                                        ": it needs li_e and li_thick above 0", {}, "property");
                    }
                }
            }
            auto store_liner = [&] {
                if (!liner_props) return;
                LinerSet& ls = m.liners;
                ensure_index(ls.materials, n);
                ls.materials[n] = liner_mat;
                for (int c = 0; c < ls.size(); ++c) {
                    if (ls.material[c] != n) continue;
                    for (int i = ls.node_offset[c]; i < ls.node_offset[c + 1]; ++i) {
                        ls.mass[i] = liner_mat.density * liner_mat.thick * ls.area[i];
                    }
                }
                build_liner_stiffness(ls);
                m.geometry_changed = true;
            };
            // Cable properties: computed aside and checked first, stored last, so that a refused
            // command (here or in the block properties below) changes nothing.
            CableMaterial cable_mat;
            if (cable_props) {
                const CableSet& cs = m.cables;
                CableMaterial& p = cable_mat;
                p = n < static_cast<int>(cs.materials.size()) ? cs.materials[n] : CableMaterial();
                p.defined = true;
                p.area = a.real_or("cb_area", p.area);
                p.e = a.real_or("cb_e", p.e);
                p.ytens = a.real_or("cb_yield", p.ytens);
                p.ycomp = a.real_or("cb_ycomp", p.ycomp);
                p.kbond = a.real_or("cb_kbond", p.kbond);
                p.sbond = a.real_or("cb_sbond", p.sbond);
                p.density = a.real_or("cb_dens", p.density);
                // The cables already made of it keep a steel they can compute with.
                for (int c = 0; c < cs.size(); ++c) {
                    if (cs.material[c] == n && (!(p.area > 0) || !(p.e > 0))) {
                        fail(a.loc, "cable " + std::to_string(cs.id[c]) + " is of material " + std::to_string(n) +
                                        ": it needs cb_area and cb_e above 0", {}, "property");
                    }
                }
            }
            auto store_cable = [&] {
                if (!cable_props) return;
                CableSet& cs = m.cables;
                ensure_index(cs.materials, n);
                cs.materials[n] = cable_mat;
                // The nodes' real masses follow the density.
                for (int c = 0; c < cs.size(); ++c) {
                    if (cs.material[c] != n) continue;
                    for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
                        cs.mass[i] = cable_mat.density * cable_mat.area * cs.length[i];
                    }
                }
                m.geometry_changed = true; // stiffness and masses may change the timestep
            };
            if (!block_props) {
                store_cable();
                store_liner();
                return;
            }
            if (a.has("density")) {
                // Check first: every block of this material must keep a mass it can compute with.
                const double rho = a.real("density");
                const BlockSet& s = m.blocks;
                for (int b = 0; b < s.size(); ++b) {
                    if (s.material[b] != n) continue;
                    MassProperties mp;
                    mp.volume = s.volume[b];
                    mp.inertia = s.inertia_unit[b];
                    const std::string problem = block_numbers_problem(mp, rho);
                    if (!problem.empty()) {
                        fail(a.find("density")->values[0].loc, "block " + std::to_string(s.id[b]) + ": " + problem,
                             {}, "property");
                    }
                }
            }
            // Computed aside and checked, then stored: a refused command changes nothing.
            const Material mat = material_from_args(
                a, n < static_cast<int>(m.materials.size()) ? m.materials[n] : Material(), "ymod", "prat", "property");
            ensure_index(m.materials, n);
            m.materials[n] = mat;
            if (a.has("density")) update_masses(m);
            // Zone masses, stiffnesses and the timestep follow the new values.
            m.geometry_changed = true;
            store_cable();
            store_liner();
        });
        return c;
    }();
    return spec;
}

} // namespace odec
