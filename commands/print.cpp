#include "analysis_mode.h"
#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/clump.h"
#include "engine/cable.h"
#include "engine/liner.h"
#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/flow.h"
#include "engine/parallel.h"
#include "engine/verdict.h"
#include "engine/zones.h"
#include "mesh/tet_mesh.h"
#include "verdict_text.h"

#include <cmath>

namespace odec {

namespace {

// Right-aligned in w characters, always with a blank before it, so neighbours never run together.
std::string col(const std::string& s, size_t w) { return s.size() >= w ? " " + s : std::string(w - s.size(), ' ') + s; }

// Tables fit in 100 columns: numbers to 3 significant figures (at most 9 characters, so a
// column of width 10 always keeps a blank before the next); full precision is in 'hist',
// 'export vtk' and the save file.
std::string n3(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

void print_blocks(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    const BlockSet& s = m.blocks;
    const std::vector<int> sel = select_blocks(m, a.range, true);
    std::ostream& o = ctx.out;
    o << col("id", 5) << col("x", 9) << col("y", 9) << col("z", 9) << col("xdis", 10) << col("ydis", 10)
      << col("zdis", 10) << col("xvel", 10) << col("yvel", 10) << col("zvel", 10) << " state\n";
    for (int b : sel) {
        const Vec3 v = velocity_at_t(m, b);
        std::string state = (s.flags[b] & kFixed) ? "fix" : "free";
        if (s.flags[b] & kExcavated) state = "null";
        if (s.flags[b] & kHidden) state += ",h";
        o << col(std::to_string(s.id[b]), 5) << col(n3(s.centroid[b].x()), 9) << col(n3(s.centroid[b].y()), 9)
          << col(n3(s.centroid[b].z()), 9) << col(n3(s.disp[b].x()), 10) << col(n3(s.disp[b].y()), 10)
          << col(n3(s.disp[b].z()), 10) << col(n3(v.x()), 10) << col(n3(v.y()), 10) << col(n3(v.z()), 10) << " "
          << state << "\n";
    }
    // The clump column only where there are clumps (clump.h).
    bool clumps = false;
    for (int b : sel) clumps = clumps || s.clump[b] != 0;
    o << "\n" << col("id", 5) << col("volume", 11) << col("mass", 10) << col("mat", 5) << col("region", 7)
      << (clumps ? col("clump", 7) : std::string()) << "  group\n";
    for (int b : sel) {
        o << col(std::to_string(s.id[b]), 5) << col(n3(s.volume[b]), 11) << col(n3(s.mass[b]), 10)
          << col(std::to_string(s.material[b]), 5) << col(std::to_string(s.region[b]), 7)
          << (clumps ? col(s.clump[b] != 0 ? std::to_string(s.clump[b]) : "-", 7) : std::string()) << "  "
          << (s.group[b] >= 0 ? m.group_names[s.group[b]] : "-") << "\n";
    }
    o << sel.size() << " of " << s.size() << " blocks (x, y, z: centroid; m, m/s, m^3, kg; fix: fixed, null: excavated, h: hidden";
    if (clumps) o << "; clump: the solid that is not convex, one rigid body, whose piece the block is";
    o << ")\n";
}

std::string g6(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
}

void print_energy(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    if (!m.energy.on) {
        fail(a.find("energy")->loc, "the energy account is off", {"'set energy on' starts it (before the steps to account for)"},
             "print");
    }
    const EnergyReading r = energy_reading(m);
    std::ostream& o = ctx.out;
    // The account stands where the stresses stand: at the start of the last step.
    const double t = m.step > 0 ? std::max(0.0, m.time - m.dt) : m.time;
    o << "energy account, J: stored energies at the start of the last step (t = " << g6(t)
      << " s), work and dissipation since step " << m.energy.start_step << "\n";
    for (const EnergyTermInfo& t : energy_terms()) {
        const std::string name = t.name;
        if (name == "error") continue;
        double v = 0;
        energy_term(m, name, v);
        o << "  " << name << std::string(10 - name.size(), ' ') << col(g6(v), 13) << "  " << t.help << "\n";
    }
    const double in = r.initial + r.given + r.work(), out = r.stored() + r.dissipated();
    o << "balance:\n";
    o << "  stored + dissipated          " << col(g6(out), 13) << "\n";
    o << "  initial + given + work       " << col(g6(in), 13) << "\n";
    o << "  error (their difference)     " << col(g6(r.error()), 13);
    if (m.energy.peak > 0) {
        o << "  (" << n3(100.0 * r.error() / m.energy.peak) << " % of " << g6(m.energy.peak)
          << " J, the most energy the account has handled)";
    }
    o << "\n";
    const std::string caveat = energy_caveat(m);
    if (!caveat.empty()) o << "note: " << caveat << "\n";
}

std::string zone_state_text(std::uint8_t model, std::uint8_t st) {
    if (model == kZoneNull) return "null";
    if (model == kZoneElastic) return "elastic";
    std::string t;
    if (st & kShearNow) t += "shear-n,";
    if (st & kTensionNow) t += "tens-n,";
    if ((st & kShearPast) && !(st & kShearNow)) t += "shear-p,";
    if ((st & kTensionPast) && !(st & kTensionNow)) t += "tens-p,";
    if (t.empty()) return "mc";
    t.pop_back();
    return t;
}

void print_zones(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    const ZoneSet& z = m.zones;
    std::ostream& o = ctx.out;
    std::vector<int> sel;
    for (int i = 0; i < z.size(); ++i) {
        if (m.blocks.flags[z.block[i]] & kExcavated) continue;
        if (a.range.contains_point(m, zone_centroid(m, i), z.block[i])) sel.push_back(i);
    }
    o << col("zone", 7) << col("block", 6) << col("x", 9) << col("y", 9) << col("z", 9) << col("smin", 10)
      << col("smid", 10) << col("smax", 10) << "  state\n";
    for (int i : sel) {
        const Vec3 c = zone_centroid(m, i);
        Vec3 p;
        principal_stresses(z.stress[i], p);
        o << col(std::to_string(i + 1), 7) << col(std::to_string(m.blocks.id[z.block[i]]), 6) << col(n3(c.x()), 9)
          << col(n3(c.y()), 9) << col(n3(c.z()), 9) << col(n3(p[0]), 10) << col(n3(p[1]), 10) << col(n3(p[2]), 10)
          << "  " << zone_state_text(z.model[i], z.state[i]) << "\n";
    }
    o << "\n" << col("zone", 7) << col("sxx", 10) << col("syy", 10) << col("szz", 10) << col("sxy", 10)
      << col("sxz", 10) << col("syz", 10) << "\n";
    for (int i : sel) {
        const Sym6& s = z.stress[i];
        o << col(std::to_string(i + 1), 7);
        for (int k = 0; k < 6; ++k) o << col(n3(s[k]), 10);
        o << "\n";
    }
    o << sel.size() << " of " << z.size()
      << " zones (x, y, z: centroid; stresses in Pa, tension positive; smin the most compressive;\n"
         "state: elastic, mc (Mohr-Coulomb, elastic now), shear-n/tens-n yielding in shear/tension now,\n"
         "shear-p/tens-p yielded before, null)\n";
}

void print_gridpoints(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    const GridpointSet& g = m.gridpoints;
    std::ostream& o = ctx.out;
    const std::vector<int> sel = select_gridpoints(m, a.range);
    o << col("gp", 7) << col("x", 9) << col("y", 9) << col("z", 9) << col("xdis", 10) << col("ydis", 10)
      << col("zdis", 10) << col("xvel", 10) << col("yvel", 10) << col("zvel", 10) << " held\n";
    for (int i : sel) {
        const Vec3 v = gridpoint_velocity_at_t(m, i);
        std::string held;
        for (int k = 0; k < 3; ++k) {
            if (g.vel_bc[i] & (1 << k)) held += "xyz"[k];
        }
        if (held.empty()) held = "-";
        o << col(std::to_string(i + 1), 7) << col(n3(g.pos[i].x()), 9) << col(n3(g.pos[i].y()), 9)
          << col(n3(g.pos[i].z()), 9) << col(n3(g.disp[i].x()), 10) << col(n3(g.disp[i].y()), 10)
          << col(n3(g.disp[i].z()), 10) << col(n3(v.x()), 10) << col(n3(v.y()), 10) << col(n3(v.z()), 10) << " "
          << held << "\n";
    }
    o << sel.size() << " of " << g.size()
      << " gridpoints (m, m/s; held: velocity components held by 'fix' or 'bound ...vel')\n";
}

void print_cables(CommandContext& ctx) {
    const Model& m = ctx.model;
    const CableSet& cs = m.cables;
    std::ostream& o = ctx.out;
    if (cs.size() == 0) {
        o << "no cables\n";
        return;
    }
    auto seg_state = [](std::uint8_t st) -> std::string {
        if (st & kCableYieldTensionNow) return "yield-t";
        if (st & kCableYieldCompNow) return "yield-c";
        if (st & kCableYieldPast) return "yield-p";
        return "-";
    };
    auto grout_state = [](std::uint8_t st) -> std::string {
        if (st & kGroutSlipNow) return "slip";
        if (st & kGroutSlipPast) return "slip-p";
        return "-";
    };
    for (int c = 0; c < cs.size(); ++c) {
        const int first = cs.node_offset[c], last = cs.node_offset[c + 1] - 1;
        o << "cable " << cs.id[c] << " (material " << cs.material[c] << "): " << cs.segments_of(c) << " segments from "
          << vec_text(cs.pos[first]) << " to " << vec_text(cs.pos[last]) << "\n";
        o << col("seg", 5) << col("x", 9) << col("y", 9) << col("z", 9) << col("axial", 10) << " state\n";
        for (int k = 0; k < cs.segments_of(c); ++k) {
            const int i = first + k, seg = cs.first_segment(c) + k;
            const Vec3 x = 0.5 * (cs.pos[i] + cs.pos[i + 1]);
            o << col(std::to_string(k + 1), 5) << col(n3(x.x()), 9) << col(n3(x.y()), 9) << col(n3(x.z()), 9)
              << col(n3(cs.axial[seg]), 10) << " " << seg_state(cs.seg_state[seg]) << "\n";
        }
        o << col("node", 5) << col("x", 9) << col("y", 9) << col("z", 9) << col("xdis", 10) << col("ydis", 10)
          << col("zdis", 10) << col("block", 7) << col("grout", 10) << col("slip", 10) << " state\n";
        for (int i = first; i <= last; ++i) {
            std::string state = cs.host_block[i] > 0 ? grout_state(cs.state[i]) : "free";
            if (cs.vel_bc[i]) state += " driven";
            o << col(std::to_string(i - first + 1), 5) << col(n3(cs.pos[i].x()), 9) << col(n3(cs.pos[i].y()), 9)
              << col(n3(cs.pos[i].z()), 9) << col(n3(cs.disp[i].x()), 10) << col(n3(cs.disp[i].y()), 10)
              << col(n3(cs.disp[i].z()), 10) << col(cs.host_block[i] > 0 ? std::to_string(cs.host_block[i]) : "-", 7)
              << col(n3(cs.grout_force[i]), 10) << col(n3(cs.slip[i]), 10) << " " << state << "\n";
        }
    }
    o << cs.size() << " cables (m; axial force N, tension positive; grout: its force on the cable along it,\n"
         "  from the first node to the last, N; slip: the grout's plastic slip along it, m; block: the block the\n"
         "  node is grouted into; state: yield-t, yield-c yielding in tension, compression now, yield-p earlier;\n"
         "  slip now, slip-p earlier; free: in no block, no grout; driven: moved at a given velocity)\n";
}

void print_liners(CommandContext& ctx) {
    const Model& m = ctx.model;
    const LinerSet& ls = m.liners;
    std::ostream& o = ctx.out;
    if (ls.size() == 0) {
        o << "no liners\n";
        return;
    }
    for (int c = 0; c < ls.size(); ++c) {
        o << "liner " << ls.id[c] << " (material " << ls.material[c] << "): " << ls.elem_offset[c + 1] - ls.elem_offset[c]
          << " elements, " << ls.node_offset[c + 1] - ls.node_offset[c] << " nodes, axis " << vec_text(ls.axis[c]) << "\n";
        o << col("el", 6) << col("x", 9) << col("y", 9) << col("z", 9) << col("n_x", 11) << col("n_y", 11)
          << col("n_xy", 11) << col("m_x", 11) << col("m_y", 11) << col("m_xy", 11) << "\n";
        for (int e = ls.elem_offset[c]; e < ls.elem_offset[c + 1]; ++e) {
            const LinerResultants r = liner_resultants(ls, e);
            o << col(std::to_string(e - ls.elem_offset[c] + 1), 6) << col(n3(r.centroid.x()), 9)
              << col(n3(r.centroid.y()), 9) << col(n3(r.centroid.z()), 9) << col(n3(r.nx), 11) << col(n3(r.ny), 11)
              << col(n3(r.nxy), 11) << col(n3(r.mx), 11) << col(n3(r.my), 11) << col(n3(r.mxy), 11) << "\n";
        }
        o << col("node", 6) << col("x", 9) << col("y", 9) << col("z", 9) << col("xdis", 10) << col("ydis", 10)
          << col("zdis", 10) << col("block", 7) << col("bond_n", 10) << col("bond_s", 10) << " state\n";
        for (int i = ls.node_offset[c]; i < ls.node_offset[c + 1]; ++i) {
            std::string state = "-";
            if (ls.host_block[i] <= 0) state = "free";
            else if (ls.state[i] & kBondOpen) state = "open";
            else if (ls.state[i] & kBondBrokenTension) state = "broken-t";
            else if (ls.state[i] & kBondBrokenShear) state = (ls.state[i] & kBondSlipNow) ? "slip" : "broken-s";
            else if (ls.state[i] & kBondSlipNow) state = "slip";
            o << col(std::to_string(i - ls.node_offset[c] + 1), 6) << col(n3(ls.pos[i].x()), 9) << col(n3(ls.pos[i].y()), 9)
              << col(n3(ls.pos[i].z()), 9) << col(n3(ls.disp[i].x()), 10) << col(n3(ls.disp[i].y()), 10)
              << col(n3(ls.disp[i].z()), 10) << col(ls.host_block[i] > 0 ? std::to_string(ls.host_block[i]) : "-", 7)
              << col(n3(ls.bond_n[i]), 10) << col(n3(ls.bond_s[i].norm()), 10) << " " << state << "\n";
        }
    }
    o << ls.size() << " liners (m; per element at its centroid, in its frame: x in its plane across the axis, y\n"
         "  along it; n membrane forces N/m, tension positive (a lining's thrust is -n_x); m bending moments\n"
         "  N m/m, positive with the face on the void's side in tension; per node: bond_n the bond's normal force\n"
         "  on the liner, N, compression positive, bond_s its shear force, N; state: slip at the shear limit now,\n"
         "  broken-t, broken-s broken in tension, shear (friction only since), open broken and apart, free: no\n"
         "  rock under it)\n";
}

void print_properties(CommandContext& ctx) {
    const Model& m = ctx.model;
    std::ostream& o = ctx.out;
    o << "block materials (density kg/m^3; moduli, cohesion, tension Pa; angles degrees; all but density:\n"
         "zones of deformable blocks)\n";
    o << col("mat", 5) << col("density", 10) << col("bulk", 10) << col("shear", 10) << col("cohesion", 10)
      << col("friction", 10) << col("tension", 10) << col("dilation", 10) << "\n";
    int n = 0;
    for (size_t k = 1; k < m.materials.size(); ++k) {
        const Material& p = m.materials[k];
        if (!p.defined) continue;
        ++n;
        o << col(std::to_string(k), 5) << col(n3(p.density), 10) << col(n3(p.bulk), 10) << col(n3(p.shear), 10)
          << col(n3(p.cohesion), 10) << col(n3(p.friction), 10) << col(n3(p.tension), 10) << col(n3(p.dilation), 10)
          << "\n";
    }
    if (n == 0) o << "  none\n";
    o << "joint materials (jkn, jks Pa/m; jcoh, jten Pa; angles deg; jzdil m)\n";
    o << col("jmat", 5) << col("jkn", 10) << col("jks", 10) << col("jfric", 10) << col("jcoh", 10) << col("jten", 10)
      << col("jdil", 10) << col("jzdil", 10) << col("jresfric", 10) << "\n";
    n = 0;
    for (size_t k = 1; k < m.joint_materials.size(); ++k) {
        const JointMaterial& j = m.joint_materials[k];
        if (!j.defined) continue;
        ++n;
        o << col(std::to_string(k), 5) << col(n3(j.kn), 10) << col(n3(j.ks), 10) << col(n3(j.friction), 10)
          << col(n3(j.cohesion), 10) << col(n3(j.tension), 10) << col(n3(j.dilation), 10) << col(n3(j.zdilation), 10)
          << col(n3(j.res_friction), 10) << "\n";
    }
    if (n == 0) o << "  none\n";
    const CableSet& cs = m.cables;
    n = 0;
    for (size_t k = 1; k < cs.materials.size(); ++k) n += cs.materials[k].defined;
    if (n > 0) {
        o << "cable materials (area m^2; e Pa; yield, ycomp N; kbond N/m/m; sbond N/m; dens kg/m^3; 0: see 'help prop')\n";
        o << col("mat", 5) << col("area", 10) << col("e", 10) << col("yield", 10) << col("ycomp", 10) << col("kbond", 10)
          << col("sbond", 10) << col("dens", 10) << "\n";
        for (size_t k = 1; k < cs.materials.size(); ++k) {
            const CableMaterial& p = cs.materials[k];
            if (!p.defined) continue;
            o << col(std::to_string(k), 5) << col(n3(p.area), 10) << col(n3(p.e), 10) << col(n3(p.ytens), 10)
              << col(n3(p.ycomp), 10) << col(n3(p.kbond), 10) << col(n3(p.sbond), 10) << col(n3(p.density), 10) << "\n";
        }
    }
    const LinerSet& ls = m.liners;
    n = 0;
    for (size_t k = 1; k < ls.materials.size(); ++k) n += ls.materials[k].defined;
    if (n > 0) {
        o << "liner materials (e Pa; thick m; dens kg/m^3; kn, ks Pa/m; ncut, scoh Pa, none: no limit; sfric deg)\n";
        o << col("mat", 5) << col("e", 10) << col("nu", 7) << col("thick", 9) << col("dens", 9) << col("kn", 10)
          << col("ks", 10) << col("ncut", 10) << col("scoh", 10) << col("sfric", 7) << "\n";
        for (size_t k = 1; k < ls.materials.size(); ++k) {
            const LinerMaterial& p = ls.materials[k];
            if (!p.defined) continue;
            o << col(std::to_string(k), 5) << col(n3(p.e), 10) << col(n3(p.nu), 7) << col(n3(p.thick), 9)
              << col(n3(p.density), 9) << col(n3(p.kn), 10) << col(n3(p.ks), 10)
              << col(p.ncut >= 0 ? n3(p.ncut) : "none", 10) << col(p.scoh >= 0 ? n3(p.scoh) : "none", 10)
              << col(n3(p.sfric), 7) << "\n";
        }
    }
}

void print_histories(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    const HistorySet& hs = m.histories;
    std::vector<int> numbers;
    for (const Value& v : a.find("history")->values) numbers.push_back(history_number(m, v, "print"));
    std::ostream& o = ctx.out;
    std::vector<size_t> width;
    o << col("step", 10);
    for (int n : numbers) {
        const std::string title = std::to_string(n) + ": " + hs.items[n - 1].label;
        width.push_back(std::max<size_t>(14, title.size() + 2));
        o << col(title, width.back());
    }
    o << "\n";
    for (size_t k = 0; k < hs.sample_steps.size(); ++k) {
        o << col(std::to_string(hs.sample_steps[k]), 10);
        for (size_t i = 0; i < numbers.size(); ++i) {
            // Blank before the history's first sample (it was made during the run).
            const double* v = hs.items[numbers[i] - 1].at(k);
            o << col(v ? num(*v) : std::string(), width[i]);
        }
        o << "\n";
    }
}

// The flow nodes: position, pore pressure, whether fixed, hydraulic aperture (volume / area) and
// net inflow of the last sub-step.
void print_flow(CommandContext& ctx, const Args& a) {
    Model& m = ctx.model;
    std::ostream& o = ctx.out;
    FlowSet& f = m.flow;
    if (!f.configured) {
        o << "fluid flow is not configured ('config flow')\n";
        return;
    }
    if (m.contacts.detected) {
        flow_sync(m);
        flow_apertures(m);
    }
    o << "fluid flow " << (f.on ? "on" : "off") << ", " << (f.mode == FlowMode::Steady ? "steady" : "transient")
      << " (" << f.substeps << " sub-step" << (f.substeps == 1 ? "" : "s") << " per step in steady mode); density "
      << n3(f.density) << " kg/m^3, viscosity " << n3(f.viscosity) << " Pa s, bulk modulus " << n3(f.bulk) << " Pa";
    if (f.has_wtable) o << "; water table at " << n3(f.wtable) << " m";
    o << "\n" << f.n_nodes() << " nodes, " << f.n_links() << " links, " << f.steps << " flow sub-steps";
    if (f.mode == FlowMode::Transient) o << ", flow time " << n3(f.time) << " s";
    o << "; inflow at the fixed nodes " << n3(fixed_inflow(m)) << " m^3/s\n";
    o << col("node", 6) << col("x", 9) << col("y", 9) << col("z", 9) << col("pp", 10) << col("aperture", 10)
      << col("volume", 10) << col("inflow", 10) << " fixed\n";
    const std::vector<int> nodes = flow_nodes_in_range(m, a.range);
    for (int i : nodes) {
        const bool derived = i < static_cast<int>(f.volume.size());
        const double ap = derived && f.area[i] > 0 ? f.volume[i] / f.area[i] : 0.0;
        o << col(std::to_string(i + 1), 6) << col(n3(f.pos[i].x()), 9) << col(n3(f.pos[i].y()), 9)
          << col(n3(f.pos[i].z()), 9) << col(n3(f.pp[i]), 10) << col(n3(ap), 10)
          << col(n3(derived ? f.volume[i] : 0.0), 10) << col(n3(derived ? f.inflow[i] : 0.0), 10) << " "
          << (f.fixed[i] ? "yes" : "-") << "\n";
    }
    o << nodes.size() << " of " << f.n_nodes()
      << " nodes (pp: pore pressure, Pa; aperture: hydraulic, m, mean over the node's area; volume, m^3;\n"
         "inflow: net inflow of the last sub-step, m^3/s)\n";
}

void print_contacts(CommandContext& ctx, const Args& a) {
    if (ctx.model.flow.configured && ctx.model.contacts.detected) {
        // The joints' apertures as they stand (derived: the nodes and apertures are made again
        // from the contacts, nothing saved changes).
        flow_sync(ctx.model);
        flow_apertures(ctx.model);
    }
    const Model& m = ctx.model;
    std::ostream& o = ctx.out;
    const bool flow = m.flow.configured && static_cast<int>(m.flow.sub_node.size()) == m.contacts.n_subs() &&
                      m.flow.sub_aperture.size() == m.flow.sub_node.size();
    o << col("id", 5) << col("blk a", 5) << col("blk b", 5) << col("x", 9) << col("y", 9) << col("z", 9)
      << col("area", 9) << col("nstress", 10) << col("sstress", 10) << col("ndis", 10) << col("sdis", 10);
    if (flow) o << col("pp", 10) << col("aperture", 10);
    o << " state\n";
    int n = 0;
    for (int c = 0; c < m.contacts.size(); ++c) {
        const ContactInfo ci = contact_info(m, c);
        if (a.has_range && !a.range.contains_contact(m, ci.centroid, ci.block_a, ci.block_b)) continue;
        ++n;
        o << col(std::to_string(ci.id), 5) << col(std::to_string(m.blocks.id[ci.block_a]), 5)
          << col(std::to_string(m.blocks.id[ci.block_b]), 5) << col(n3(ci.centroid.x()), 9)
          << col(n3(ci.centroid.y()), 9) << col(n3(ci.centroid.z()), 9) << col(n3(ci.area), 9)
          << col(n3(ci.normal_stress), 10) << col(n3(ci.shear_stress), 10) << col(n3(ci.normal_disp), 10)
          << col(n3(ci.shear_disp), 10);
        if (flow) {
            const ContactFlow cf = contact_flow(m, c);
            o << col(n3(cf.pp), 10) << col(n3(cf.aperture), 10);
        }
        o << " " << (ci.area > 0 ? contact_state_name(ci.state) : "apart")
          << (ci.joined ? ",joined" : "") << "\n";
    }
    o << n << " of " << m.contacts.size()
      << " contacts (x, y, z: centroid; area: where the blocks touch now; nstress, sstress: mean\n"
         "over the sub-contacts' spring areas, Pa, compression +; m, closure +; apart: near, not touching"
      << (flow ? ";\npp: mean pore pressure, Pa; aperture: mean hydraulic aperture, m (effective nstress)" : "") << ")\n";
}

void print_max(CommandContext& ctx) {
    const Model& m = ctx.model;
    const BlockSet& s = m.blocks;
    std::ostream& o = ctx.out;
    struct Max {
        double value = 0;
        int where = -1;
    } disp, vel, unbal, nstress, sstress, ndis, sdis;
    auto take = [](Max& mx, double v, int i) {
        if (mx.where < 0 || v > mx.value) {
            mx.value = v;
            mx.where = i;
        }
    };
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & kExcavated) continue;
        take(disp, s.disp[b].norm(), b);
        // A deformable block moves by its gridpoints: their lines below show its velocity
        // and unbalanced force (the block's own are not integrated).
        if (s.flags[b] & kDeformable) continue;
        take(vel, velocity_at_t(m, b).norm(), b);
        // A clump's at its first piece (the forces between its pieces cancel).
        Vec3 f;
        if (rigid_body_unbalanced(m, b, f)) take(unbal, f.norm(), b);
    }
    for (int c = 0; c < m.contacts.size(); ++c) {
        const ContactInfo ci = contact_info(m, c);
        if (!(ci.area > 0)) continue; // blocks within reach of each other that touch nowhere
        take(nstress, ci.normal_stress, c);
        take(sstress, ci.shear_stress, c);
        take(ndis, ci.normal_disp, c);
        take(sdis, ci.shear_disp, c);
    }
    auto block_line = [&](const char* what, const Max& mx, const char* unit) {
        o << col(what, 26) << "  ";
        if (mx.where < 0) {
            o << "-\n";
            return;
        }
        o << num(mx.value) << " " << unit << " at block " << s.id[mx.where] << " " << vec_text(s.centroid[mx.where]) << "\n";
    };
    auto contact_line = [&](const char* what, const Max& mx, const char* unit) {
        o << col(what, 26) << "  ";
        if (mx.where < 0) {
            o << "-\n";
            return;
        }
        const ContactInfo ci = contact_info(m, mx.where);
        o << num(mx.value) << " " << unit << " at contact " << ci.id << " " << vec_text(ci.centroid) << "\n";
    };
    block_line("displacement", disp, "m");
    block_line("velocity", vel, "m/s");
    block_line("unbalanced force", unbal, "N");
    contact_line("joint normal stress", nstress, "Pa");
    contact_line("joint shear stress", sstress, "Pa");
    contact_line("joint normal closure", ndis, "m");
    contact_line("joint shear displacement", sdis, "m");
    if (m.zones.size() > 0) {
        const ZoneSet& z = m.zones;
        const GridpointSet& g = m.gridpoints;
        Max gdisp, gvel, gunbal, smin, smax;
        for (int i = 0; i < g.size(); ++i) {
            if (m.blocks.flags[g.block[i]] & kExcavated) continue;
            take(gdisp, g.disp[i].norm(), i);
            take(gvel, gridpoint_velocity_at_t(m, i).norm(), i);
            if (g.mass[i] > 0 && g.vel_bc[i] != 7) {
                Vec3 f = g.force[i];
                for (int k = 0; k < 3; ++k) {
                    if (g.vel_bc[i] & (1 << k)) f[k] = 0;
                }
                take(gunbal, f.norm(), i);
            }
        }
        for (int i = 0; i < z.size(); ++i) {
            if (z.model[i] == kZoneNull || (m.blocks.flags[z.block[i]] & kExcavated)) continue;
            Vec3 p;
            principal_stresses(z.stress[i], p);
            take(smin, -p[0], i);  // the most compressive: largest compression
            take(smax, p[2], i);
        }
        auto gp_line = [&](const char* what, const Max& mx, const char* unit) {
            o << col(what, 26) << "  ";
            if (mx.where < 0) {
                o << "-\n";
                return;
            }
            o << num(mx.value) << " " << unit << " at gridpoint " << mx.where + 1 << " " << vec_text(g.pos[mx.where]) << "\n";
        };
        auto zone_line = [&](const char* what, const Max& mx, double sign) {
            o << col(what, 26) << "  ";
            if (mx.where < 0) {
                o << "-\n";
                return;
            }
            o << num(sign * mx.value) << " Pa at zone " << mx.where + 1 << " " << vec_text(zone_centroid(m, mx.where)) << "\n";
        };
        gp_line("gridpoint displacement", gdisp, "m");
        gp_line("gridpoint velocity", gvel, "m/s");
        gp_line("gridpoint unbalanced force", gunbal, "N");
        zone_line("smin (most compressive)", smin, -1.0);
        zone_line("smax (most tensile)", smax, 1.0);
    }
    o << col("mean unbalanced ratio", 26) << "  " << num(unbalanced_ratio(m)) << "\n";
}

void print_info(CommandContext& ctx) {
    const Model& m = ctx.model;
    std::ostream& o = ctx.out;
    int n_fixed = 0, n_excavated = 0;
    for (int b = 0; b < m.blocks.size(); ++b) {
        n_fixed += (m.blocks.flags[b] & kFixed) != 0;
        n_excavated += (m.blocks.flags[b] & kExcavated) != 0;
    }
    o << "title:      " << (m.title.empty() ? "(none)" : m.title) << "\n";
    o << "blocks:     " << m.blocks.size() << " (" << n_fixed << " fixed, " << n_excavated << " excavated)\n";
    o << "contacts:   " << m.contacts.size() << "\n";
    {
        const ClumpList cl = list_clumps(m.blocks);
        if (cl.size() > 0) {
            o << "clumps:     " << cl.size() << " (solids that are not convex, each one rigid body; "
              << cl.pieces.size() << " blocks in all)\n";
        }
    }
    if (m.zones.size() > 0) {
        int models[3] = {0, 0, 0};
        for (auto c : m.zones.model) ++models[c < 3 ? c : 0];
        int deformable = 0;
        for (int b = 0; b < m.blocks.size(); ++b) deformable += (m.blocks.flags[b] & kDeformable) != 0;
        o << "zones:      " << m.zones.size() << " in " << deformable << " deformable blocks (" << models[1]
          << " elastic, " << models[2] << " Mohr-Coulomb, " << models[0] << " null)\n";
        o << "gridpoints: " << m.gridpoints.size() << "; " << (m.settings.large_strain ? "large" : "small")
          << " strain\n";
        // Zone quality: the radius ratio (3 r_in / r_out, 1 for a regular tetrahedron) of the
        // worst zone, in the geometry the zones use.
        const std::vector<Vec3>& x = m.settings.large_strain ? m.gridpoints.pos : m.gridpoints.ref;
        double worst = 2;
        int worst_zone = 0;
        for (int z = 0; z < m.zones.size(); ++z) {
            const auto& q = m.zones.gp[z];
            const double r = radius_ratio(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
            if (r < worst) {
                worst = r;
                worst_zone = z;
            }
        }
        o << "zone quality: worst radius ratio " << num(worst) << " (a zone of block "
          << m.blocks.id[m.zones.block[worst_zone]] << "; 1 for a regular tetrahedron)\n";
    }
    o << "joint sets: " << m.n_joint_sets << " (" << m.joint_planes.size() << " planes, " << m.slivers_skipped
      << " cuts skipped as slivers)\n";
    o << "materials: ";
    int n_mat = 0;
    for (size_t k = 1; k < m.materials.size(); ++k) {
        if (m.materials[k].defined) {
            o << " " << k << " (dens " << num(m.materials[k].density) << ")";
            ++n_mat;
        }
    }
    o << (n_mat ? "" : " none") << "\n";
    o << "joint materials:";
    int n_jmat = 0;
    for (size_t k = 1; k < m.joint_materials.size(); ++k) {
        const JointMaterial& j = m.joint_materials[k];
        if (j.defined) {
            o << " " << k << " (kn " << num(j.kn) << " ks " << num(j.ks) << " fric " << num(j.friction) << ")";
            ++n_jmat;
        }
    }
    o << (n_jmat ? "" : " none") << "\n";
    o << "gravity:    " << vec_text(m.gravity) << " m/s^2\n";
    const Damping& d = m.damping;
    o << "damping:    ";
    switch (d.mode) {
    case DampingMode::Local: o << "local " << num(d.local); break;
    case DampingMode::Auto:
        // The coefficient is 2 kAutoDampingFraction omega of the motion the model showed at its
        // last step (integrate.cpp).
        o << "auto (adaptive: " << num(kAutoDampingFraction) << " of critical for the motion the model shows";
        if (d.auto_coefficient > 0) {
            o << "; now " << num(d.auto_coefficient) << " 1/s, for "
              << num(d.auto_coefficient / (2 * kAutoDampingFraction) / (2 * M_PI)) << " Hz";
        }
        o << ")";
        break;
    case DampingMode::Rayleigh: o << "Rayleigh, fraction " << num(d.rayleigh_fraction) << " at " << num(d.rayleigh_frequency) << " Hz (mass)"; break;
    case DampingMode::Off: o << "off"; break;
    }
    o << "\n";
    o << "timestep:   " << (m.settings.dt_fixed > 0 ? num(m.settings.dt_fixed) + " s (set dt)"
                                                    : "automatic, dtfrac " + num(m.settings.dtfrac))
      << (m.dt > 0 ? ", in use " + num(m.dt) + " s" : "") << "\n";
    // What 'set ovtol' allows: blocks that carry no stress yet may overlap this much when cycling starts.
    o << "overlap:    at most " << (m.settings.ovtol > 0 ? num(m.settings.ovtol) + " m (set ovtol)"
                                                       : std::string("0.5 % of the smaller block's size (automatic)"))
      << " where unstressed\n";
    o << "analysis:   " << analysis_mode_text(m) << "\n";
    o << "threads:    " << thread_count()
      << (threads_available() ? " ('set threads n' or ODEC_THREADS; the same results with any number)"
                              : " (built without OpenMP)")
      << "\n";
    o << "step:       " << m.step << "  time " << num(m.time) << " s" << (m.settings.dynamic ? "" : " (static: not real time)")
      << "\n";
    o << "histories:  " << m.histories.items.size() << " (every " << m.histories.ncyc << " steps, "
      << m.histories.sample_steps.size() << " samples)\n";
    // The last solve: the criteria it was given, and how it ended.
    if (const auto& v = ctx.interp.last_solve) {
        o << "last solve: " << criteria_text(*v) << "; ended at step " << v->end_step << "\n";
        o << "verdict:    " << verdict_text(*v) << "\n";
        if (v->stop == StopReason::Time && v->outcome == SolveOutcome::Mechanism) {
            o << "            mechanism: " << mechanism_text(*v) << "\n";
        }
    } else {
        o << "last solve: none finished since 'new' or 'restore'\n";
    }
    const Profile& p = m.profile;
    double total = 0;
    for (double s : p.seconds) total += s;
    if (p.steps > 0 && total > 0) {
        o << "cycle profile over " << p.steps << " steps (" << num(total) << " s, " << num(p.steps / total)
          << " steps/s):\n";
        for (int k = 0; k < static_cast<int>(Stage::Count); ++k) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "  %-16s %6.1f %%\n", stage_name(static_cast<Stage>(k)), 100.0 * p.seconds[k] / total);
            o << buf;
        }
    }
}

} // namespace

const CommandSpec& print_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("print", 3, "print a table of model quantities");
        c.keyword("block", 2, "blocks: centroid, displacement, velocity, mass, material, state").in_choice(1);
        c.keyword("history", 2, "the samples of histories n ...").integer("n", 1).repeat().in_choice(1);
        c.keyword("info", 2, "a summary of the model, its settings and where cycling time goes").in_choice(1);
        c.keyword("contact", 2, "contacts: blocks, centroid, area, stresses, displacements, state").in_choice(1);
        c.keyword("max", 2, "the largest displacement, velocity, unbalanced force and joint quantities, and where").in_choice(1);
        c.keyword("property", 3, "every block and joint material and its properties").in_choice(1);
        c.keyword("zone", 2, "zones of deformable blocks: centroid, principal stresses, state, stress tensor").in_choice(1);
        c.keyword("gridpoint", 2, "gridpoints of deformable blocks: position, displacement, velocity, what holds them").in_choice(1);
        c.keyword("gp", 2, "same as 'gridpoint'").in_choice(1);
        c.keyword("energy", 2, "the energy account ('set energy on'): each term in J, the balance and its error")
            .in_choice(1);
        c.keyword("cable", 3, "cables: axial force and state of each segment; position, displacement, grout force, "
                              "slip and state of each node").in_choice(1);
        c.keyword("flow", 2, "fluid flow in the joints: the fluid and each flow node's pore pressure, aperture, "
                             "volume and inflow").in_choice(1);
        c.keyword("liner", 3, "liners: membrane forces and bending moments of each element; position, displacement, "
                              "bond forces and state of each node").in_choice(1);
        c.range();
        c.require_one_of(1);
        c.example("print block range z 0 10");
        c.example("print hist 1 2");
        c.handle([](CommandContext& ctx, const Args& a) {
            const std::string what = a.chosen(1);
            if (a.has_range && what != "block" && what != "contact" && what != "zone" && what != "gridpoint" && what != "gp" &&
                what != "flow") {
                fail(a.range_loc, "'range' goes with 'print block', 'contact', 'zone', 'gridpoint' and 'flow'", {}, "print");
            }
            if (what == "block") print_blocks(ctx, a);
            else if (what == "zone") print_zones(ctx, a);
            else if (what == "gridpoint" || what == "gp") print_gridpoints(ctx, a);
            else if (what == "contact") print_contacts(ctx, a);
            else if (what == "max") print_max(ctx);
            else if (what == "history") print_histories(ctx, a);
            else if (what == "property") print_properties(ctx);
            else if (what == "energy") print_energy(ctx, a);
            else if (what == "cable") print_cables(ctx);
            else if (what == "flow") print_flow(ctx, a);
            else if (what == "liner") print_liners(ctx);
            else print_info(ctx);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
