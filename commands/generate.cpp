#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/insitu.h"
#include "engine/polyhedron.h"
#include "engine/zones.h"
#include "mesh/tet_mesh.h"

namespace odec {

namespace {

// Zones of a radius ratio below this are reported: the mesher reaches it in blocks of ordinary
// shape at any edge length (tests/unit/lang/mesh_quality_test.cpp), so a block whose zones
// fall short is too thin or too sharp for the edge asked.
constexpr double kPoorZone = 0.1;

// Most zones one command makes (a regular tetrahedron of edge e has volume e^3 / (6 sqrt 2)):
// beyond it the memory of the model and its cycle time are out of any session's reach.
constexpr double kMaxZones = 5e7;
// Zones of a bounded session's budget (Interpreter::Limits::zone_budget) that one `gen` costs at
// least.
constexpr long long kGenZoneCharge = 250;
// A block is zoned only where its coordinates resolve it, and the zones' edge, to a millionth
// (up to 4.5e9 times that size from the origin).
constexpr double kResolvedFraction = 1e-6;
// A zoned block is zoned again from where its corner gridpoints are, while they still make a
// convex solid to this fraction of its size (far more than any deformation it can carry).
constexpr double kDistortedFraction = 0.01;

int find_root(std::vector<int>& parent, int i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

// `zone model elastic|mohr|null density ... bulk ... shear ... [range]` (UDEC).
void zone_model_form(CommandContext& ctx, const Args& a) {
    Model& m = ctx.model;
    const std::string word = a.find("model")->values[0].text;
    const std::uint8_t cons = word == "elastic" ? kZoneElastic : word == "mohr" ? kZoneMohrCoulomb : kZoneNull;
    const std::vector<int> blocks = blocks_to_change(ctx, a);
    if (blocks.empty()) return;
    const int first = m.blocks.material[blocks[0]];
    const Material mat = material_from_args(
        a, first > 0 && first < static_cast<int>(m.materials.size()) ? m.materials[first] : Material(), "young",
        "poisson", "zone");
    for (int b : blocks) {
        MassProperties mp;
        mp.volume = m.blocks.volume[b];
        mp.inertia = m.blocks.inertia_unit[b];
        const std::string problem = block_numbers_problem(mp, mat.density);
        if (!problem.empty()) {
            const KeywordUse* u = a.has("density") ? a.find("density") : a.find("model");
            fail(u->values[0].loc, "block " + std::to_string(m.blocks.id[b]) + ": " + problem, {}, "zone");
        }
    }
    // The first material with these very values, else a new number.
    int n = -1;
    for (int k = 1; k < static_cast<int>(m.materials.size()) && n < 0; ++k) {
        const Material& o = m.materials[k];
        if (o.defined && o.density == mat.density && o.bulk == mat.bulk && o.shear == mat.shear &&
            o.cohesion == mat.cohesion && o.friction == mat.friction && o.tension == mat.tension &&
            o.dilation == mat.dilation) {
            n = k;
        }
    }
    if (n < 0) {
        n = std::max<int>(1, static_cast<int>(m.materials.size()));
        if (n > 1000000) fail(a.loc, "there are already a million materials: no number is left for a new one", {}, "zone");
        m.materials.resize(n + 1);
        m.materials[n] = mat;
    }
    std::vector<char> chosen(m.blocks.size(), 0);
    for (int b : blocks) {
        chosen[b] = 1;
        m.blocks.material[b] = n;
        m.blocks.cons[b] = cons;
    }
    int zones = 0;
    for (int z = 0; z < m.zones.size(); ++z) {
        if (!chosen[m.zones.block[z]]) continue;
        m.zones.model[z] = cons;
        ++zones;
    }
    update_masses(m);
    m.geometry_changed = true;
    if (!ctx.interp.quiet) {
        ctx.out << blocks.size() << " blocks (" << zones << " zones) take zone model " << word << " and material " << n
                << "\n";
    }
}

// The timestep zone z sets: the least over its free gridpoints of the engine's estimate
// 2 sqrt(mass / stiffness) (zone_critical_timestep), from the masses and stiffnesses
// update_gridpoint_masses gave them. -1 when a gridpoint has none (no material yet); 0 when
// all four are fixed (they set no timestep).
double zone_timestep(const Model& m, int z) {
    const GridpointSet& g = m.gridpoints;
    double dt = 0;
    for (int i : m.zones.gp[z]) {
        if (!(g.mass[i] > 0) || !(g.stiffness[i] > 0)) return -1;
        if (g.vel_bc[i] == 7) continue;
        const double d = 2.0 * std::sqrt(g.mass[i] / g.stiffness[i]);
        if (dt == 0 || d < dt) dt = d;
    }
    return dt;
}

// Thickness of a convex solid: its least width across the normals of its faces.
double thickness(const Polyhedron& p) {
    double least = std::numeric_limits<double>::infinity();
    for (int f = 0; f < p.n_faces(); ++f) {
        const Vec3 n = p.face_normal(f);
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const Vec3& v : p.vertices) {
            lo = std::min(lo, v.dot(n));
            hi = std::max(hi, v.dot(n));
        }
        least = std::min(least, hi - lo);
    }
    return least;
}

// Warns of the blocks just zoned (blocks[k], meshed as solids[k]) whose worst zone is poor:
// the block, the zone's radius ratio, and what it costs: the timestep it sets against the
// median zone's of the model.
void warn_of_poor_zones(CommandContext& ctx, const std::vector<int>& blocks, const std::vector<double>& edges,
                        const std::vector<Polyhedron>& solids, const std::vector<double>& solid_worst) {
    const Model& m = ctx.model;
    std::vector<int> poor;  // positions in blocks
    for (size_t k = 0; k < blocks.size() && k < solid_worst.size(); ++k) {
        if (solid_worst[k] < kPoorZone) poor.push_back(static_cast<int>(k));
    }
    if (poor.empty()) return;
    std::sort(poor.begin(), poor.end(), [&](int a, int b) {
        return solid_worst[a] != solid_worst[b] ? solid_worst[a] < solid_worst[b] : a < b;
    });
    // The worst zone of each poor block, and the median zone timestep of the model.
    std::vector<int> slot(m.blocks.size(), -1);
    for (size_t i = 0; i < poor.size(); ++i) slot[blocks[poor[i]]] = static_cast<int>(i);
    std::vector<int> worst_zone(poor.size(), -1);
    std::vector<double> worst_q(poor.size(), 2.0);
    const std::vector<Vec3>& x = m.settings.large_strain ? m.gridpoints.pos : m.gridpoints.ref;
    std::vector<double> steps;
    steps.reserve(m.zones.size());
    for (int z = 0; z < m.zones.size(); ++z) {
        const double dt = zone_timestep(m, z);
        if (dt > 0) steps.push_back(dt);
        const int i = slot[m.zones.block[z]];
        if (i < 0) continue;
        const auto& q = m.zones.gp[z];
        const double r = radius_ratio(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
        if (r < worst_q[i]) {
            worst_q[i] = r;
            worst_zone[i] = z;
        }
    }
    double median = 0;
    if (!steps.empty()) {
        std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
        median = steps[steps.size() / 2];
    }
    constexpr size_t kShown = 5;
    for (size_t i = 0; i < poor.size() && i < kShown; ++i) {
        const int k = poor[i];
        const int b = blocks[k];
        auto g3 = [](double v) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.3g", v);
            return std::string(buf);
        };
        const double dt = worst_zone[i] >= 0 ? zone_timestep(m, worst_zone[i]) : -1.0;
        std::string cost;
        if (dt > 0 && median > 0) {
            cost = "its timestep is " + (dt < median ? g3(median / dt) + " times smaller than" : std::string("no smaller than")) +
                   " the model's median zone timestep (" + g3(dt) + " s against " + g3(median) + " s)";
        } else if (dt == 0) {
            cost = "its gridpoints are fixed (it costs no timestep while they are)";
        } else {
            cost = "it will shorten the timestep once the block has a material (its zones have no mass yet)";
        }
        ctx.interp.err << "warning: block " << m.blocks.id[b] << " is too thin or too sharp for zones of " << num(edges[k])
                       << " m: its worst zone has a radius ratio of " << g3(worst_q[i] < 2 ? worst_q[i] : solid_worst[k])
                       << " (good zones: " << num(kPoorZone) << " or more), and " << cost << "; zones of "
                       << g3(thickness(solids[k])) << " m or less (the block's thickness) would be better\n";
    }
    if (poor.size() > kShown) {
        ctx.interp.err << "warning: and " << poor.size() - kShown << " more blocks with zones of radius ratio under "
                       << num(kPoorZone) << "\n";
    }
}

} // namespace

const CommandSpec& generate_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("generate", 3, "make blocks deformable: divide them into tetrahedral zones");
        c.alias("zone");
        c.keyword("edge", 2, "mean edge length of the zones, m").real("e", 0, kInf, Limit::Open).in_choice(1);
        c.keyword("model", 3, "the UDEC form: zone model and material of the blocks of the range")
            .one_of("model", {"elastic", "mohr", "null"})
            .in_choice(1);
        c.keyword("density", 3, "with 'model': mass density, kg/m^3").real("rho", 0, kInf, Limit::Open);
        c.keyword("bulk", 2, "with 'model': bulk modulus K, Pa").real("K", 0, kInf, Limit::Open);
        c.keyword("shear", 2, "with 'model': shear modulus G, Pa").real("G", 0, kInf, Limit::Open);
        c.keyword("young", 2, "with 'model': Young's modulus E, Pa (with 'poisson', instead of K and G)")
            .real("E", 0, kInf, Limit::Open);
        c.keyword("poisson", 2, "with 'model': Poisson's ratio (with 'young')").real("nu", -1, 0.5, Limit::Open, Limit::Open);
        c.keyword("cohesion", 3, "with 'model mohr': cohesion, Pa").real("c", 0);
        c.keyword("friction", 3, "with 'model mohr': friction angle, degrees").real("phi", 0, 90, Limit::Closed, Limit::Open);
        c.keyword("tension", 3, "with 'model mohr': tensile strength, Pa").real("t", 0);
        c.keyword("dilation", 3, "with 'model mohr': dilation angle, degrees").real("psi", 0, 90, Limit::Closed, Limit::Open);
        c.require_one_of(1);
        c.range();
        c.describe("Each block of the range (every block when no range is given) is divided into "
                   "tetrahedral zones of mean edge length about e: its degrees of freedom become the "
                   "zones' corners (gridpoints), and its material gives the zones their density, elastic "
                   "moduli ('prop mat=n dens=... k=... g=...' or 'ymod=... prat=...') and strength. Zones "
                   "take the zone model of their block ('poly ... cons c' or 'change cons=c': 1 elastic, the "
                   "default, 2 Mohr-Coulomb, 0 null). Blocks zoned in one command that are joined ('join', "
                   "'jset ... join') and share a whole face get the same gridpoints on it: they deform as "
                   "one continuum. Zoning a deformable block again replaces its zones (their stresses are "
                   "lost) and zones the rest of its continuum again with it at their own size, so that a "
                   "continuum can be zoned finer where it matters: 'gen edge 1' then 'gen edge 0.2 range ...' "
                   "grades from 0.2 m to 1 m, conforming. The command reports the zones and gridpoints made and the "
                   "worst zone's radius ratio (3 r_in / r_out: 1 for a regular tetrahedron); blocks of ordinary shape "
                   "(convex, aspect ratio under 20) get none under 0.1 with edges up to half their size. A block too "
                   "thin or too sharp for the edge may: a warning names it, with its worst zone's radius ratio, the "
                   "timestep that zone sets against the model's median zone timestep, and the block's thickness, an "
                   "edge that would zone it well. "
                   "The UDEC form 'zone model elastic|mohr|null density ... bulk ... shear ... [friction ... "
                   "cohesion ... tension ... dilation ...] [range ...]' gives the blocks of the range (and "
                   "their zones) that zone model (1, 2 or 0) and a material of these properties: the first "
                   "material number with exactly these values, or a new one (properties not given are those "
                   "of the first block's material). Odec keeps materials per block, so a block the range "
                   "selects takes the material whole.");
        c.example("gen edge 0.5");
        c.example("zone edge 0.2 range z -5 0");
        c.example("zone model mohr density 2700 bulk 3.6e10 shear 2.7e10 friction 51 cohesion 5.5e7 tension 1.2e7");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (a.has("model")) {
                zone_model_form(ctx, a);
                return;
            }
            const KeywordUse* eu = a.find("edge");
            const double edge = a.real("edge");
            std::vector<int> blocks = blocks_to_change(ctx, a);
            if (blocks.empty()) return;
            // A clump (a solid that is not convex) is zoned whole, and ends: its blocks become
            // one continuum, glued across the faces between them.
            take_whole_clumps(ctx, blocks, "zoning");
            // The other blocks of a continuum being zoned again are zoned with it, at their own
            // size, so that its zones still conform (and grade from fine to coarse).
            std::vector<double> edges(blocks.size(), edge);
            {
                std::vector<char> chosen(m.blocks.size(), 0);
                std::vector<char> bodies;
                for (int b : blocks) {
                    chosen[b] = 1;
                    const int body = m.blocks.body[b];
                    if (body > 0) {
                        if (static_cast<int>(bodies.size()) <= body) bodies.resize(body + 1, 0);
                        bodies[body] = 1;
                    }
                }
                for (int b = 0; b < m.blocks.size(); ++b) {
                    const int body = m.blocks.body[b];
                    if (chosen[b] || body <= 0 || body >= static_cast<int>(bodies.size()) || !bodies[body]) continue;
                    blocks.push_back(b);
                    edges.push_back(m.blocks.zone_edge[b] > 0 ? m.blocks.zone_edge[b] : edge);
                }
            }
            // The count of zones before meshing: refuse what no session could hold.
            double volume = 0, estimate = 0;
            for (size_t k = 0; k < blocks.size(); ++k) {
                volume += m.blocks.volume[blocks[k]];
                estimate += m.blocks.volume[blocks[k]] / (edges[k] * edges[k] * edges[k] / (6.0 * std::sqrt(2.0)));
            }
            const double limit = ctx.interp.limits.max_zones > 0 ? static_cast<double>(ctx.interp.limits.max_zones) : kMaxZones;
            if (!(estimate <= limit)) {
                fail(eu->values[0].loc,
                     "an edge of " + num(edge) + " m would make about " + num(std::round(estimate)) + " zones in " +
                         std::to_string(blocks.size()) + " blocks (" + num(volume) + " m^3), more than the " +
                         num(limit) + " one command may make",
                     {"give a larger edge: " + num(edge * std::cbrt(estimate / limit)) + " m or more"}, "generate");
            }
            long long& budget = ctx.interp.limits.zone_budget;
            if (budget >= 0 && !(estimate <= static_cast<double>(budget))) {
                fail(eu->values[0].loc,
                     "this session may make " + std::to_string(budget) + " more zones in all; an edge of " + num(edge) +
                         " m would make about " + num(std::round(estimate)),
                     {}, "generate");
            }
            // Each `gen` forks the mesher: in a bounded session it costs at least kGenZoneCharge
            // zones of the budget, zoned or not, so that a FISH loop of small or failing ones
            // ends as well (2,000 of a few zones each forked a process of 700 MB 2,000 times).
            if (budget >= 0) budget = std::max<long long>(0, budget - kGenZoneCharge);
            // A block whose coordinates no longer resolve its shape (one that has run away to
            // 1e19 m, say, where neighbouring doubles are kilometres apart) cannot be zoned: its
            // corners are one point, or nearly, and the mesher would never finish. Nor can a zoned
            // block whose corner gridpoints no longer make a convex solid (a model that ran away
            // bends and folds its faces): the mesher would take minutes to find that out.
            for (size_t k = 0; k < blocks.size(); ++k) {
                const int b = blocks[k];
                const Polyhedron w = world_shape(m, b);
                Vec3 lo, hi;
                w.bounds(lo, hi);
                const double across = (hi - lo).norm();
                const double far = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
                const double fine = far * std::numeric_limits<double>::epsilon();
                const double feature = std::min(across, edges[k]);
                if (!(std::isfinite(far) && fine <= kResolvedFraction * feature)) {
                    fail(a.loc,
                         "block " + std::to_string(m.blocks.id[b]) + " lies " + num(far) +
                             " m from the origin, where coordinates are no finer than " + num(fine) +
                             " m: its shape (" + num(across) + " m across) and zones of " + num(edges[k]) +
                             " m are lost there",
                         {"a block gets there by running away: look at its velocity ('print block') and at the loads"},
                         "generate");
                }
                if (!(m.blocks.flags[b] & kDeformable)) continue;
                std::string why;
                if (std::isfinite(across) && is_convex_polyhedron(w, kDistortedFraction * across, &why)) continue;
                fail(a.loc,
                     "block " + std::to_string(m.blocks.id[b]) + " cannot be zoned again: its corners, where its "
                         "gridpoints have moved, no longer make a convex solid (" + why + ", by more than " +
                         num(kDistortedFraction * across) + " m, 1 % of its size)",
                     {"corners move that far when the model runs away: look at the gridpoint velocities ('print gridpoint') "
                      "and at the loads, or restore the model from before"},
                     "generate");
            }
            // Bodies: joined blocks of the range that share a whole face deform as one.
            const std::vector<int> clumps_before = m.blocks.clump;
            const int clumps_ended = dissolve_clumps(m, blocks);
            refresh_world_vertices(m);
            detect_contacts(m);
            std::vector<Polyhedron> solids;
            solids.reserve(blocks.size());
            for (int b : blocks) solids.push_back(world_shape(m, b));
            TetMesh mesh;
            const std::string why = mesh_solids(solids, edges, mesh, &ctx.interp.interrupt);
            if (ctx.interp.interrupt.load() || !why.empty()) {
                m.blocks.clump = clumps_before; // the blocks were not zoned: their clumps stay
                m.geometry_changed = true;
            }
            if (ctx.interp.interrupt.load()) fail(a.loc, "interrupted: the blocks were not zoned", {}, "generate");
            if (!why.empty()) fail(a.loc, why, {"try another edge length"}, "generate");
            std::vector<int> position(m.blocks.size(), -1);
            for (size_t k = 0; k < blocks.size(); ++k) position[blocks[k]] = static_cast<int>(k);
            std::vector<int> parent(blocks.size());
            std::iota(parent.begin(), parent.end(), 0);
            auto share_face = [&](int ka, int kb) {
                for (int sa : mesh.face_surface[ka]) {
                    for (int sb : mesh.face_surface[kb]) {
                        if (sa == sb) return true;
                    }
                }
                return false;
            };
            auto unite = [&](int ka, int kb) {
                if (share_face(ka, kb)) parent[find_root(parent, ka)] = find_root(parent, kb);
            };
            const ContactSet& cs = m.contacts;
            for (int c = 0; c < cs.size(); ++c) {
                if (!cs.joined(c)) continue;
                const int ka = position[cs.block_a[c]], kb = position[cs.block_b[c]];
                if (ka >= 0 && kb >= 0) unite(ka, kb);
            }
            // Deformable blocks zoned again keep their continuum.
            for (size_t i = 0; i < blocks.size(); ++i) {
                for (size_t j = i + 1; j < blocks.size(); ++j) {
                    const int bi = blocks[i], bj = blocks[j];
                    if (m.blocks.body[bi] > 0 && m.blocks.body[bi] == m.blocks.body[bj]) {
                        unite(static_cast<int>(i), static_cast<int>(j));
                    }
                }
            }
            std::vector<int> body(blocks.size());
            for (size_t k = 0; k < blocks.size(); ++k) body[k] = find_root(parent, static_cast<int>(k));
            BlockMesh bm;
            bm.nodes = std::move(mesh.nodes);
            bm.tets = std::move(mesh.tets);
            bm.corner_node = std::move(mesh.corner_node);
            zone_blocks(m, blocks, body, bm);
            for (size_t k = 0; k < blocks.size(); ++k) m.blocks.zone_edge[blocks[k]] = edges[k];
            long made = 0;
            for (const auto& t : bm.tets) made += static_cast<long>(t.size());
            if (budget >= 0) budget = std::max<long long>(0, budget - std::max<long long>(0, made - kGenZoneCharge));
            if (clumps_ended > 0 && !ctx.interp.quiet) {
                ctx.out << "zoned " << clumps_ended << " clump" << (clumps_ended == 1 ? "" : "s")
                        << " (a solid that is not convex): " << (clumps_ended == 1 ? "its" : "their")
                        << " blocks deform as one continuum, glued across the faces between them\n";
            }
            if (!ctx.interp.quiet) {
                ctx.out << "zoned " << blocks.size() << " blocks: " << made << " zones, " << m.gridpoints.size()
                        << " gridpoints in the model; zone quality (radius ratio) worst " << num(mesh.worst_quality)
                        << ", mean " << num(mesh.mean_quality) << "\n";
            }
            warn_of_poor_zones(ctx, blocks, edges, solids, mesh.solid_worst);
            // Loads given to a block while rigid act on its centroid or points of it, which a
            // deformable block no longer has: they go, and the warning says so.
            std::vector<int> loaded;
            for (int b : blocks) {
                if (m.blocks.loads[b].empty()) continue;
                loaded.push_back(m.blocks.id[b]);
                m.blocks.loads[b].clear();
            }
            if (!loaded.empty()) {
                std::string ids;
                for (size_t k = 0; k < loaded.size() && k < 8; ++k) ids += (k ? ", " : "") + std::to_string(loaded[k]);
                if (loaded.size() > 8) ids += ", ...";
                warn(ctx, a.loc,
                     "the loads given to block" + std::string(loaded.size() == 1 ? " " : "s ") + ids +
                         " while rigid ('bound xload ...', 'bound stress') are removed: a deformable block takes "
                         "loads on its gridpoints and faces (give them again with 'bound' after zoning)");
            }
            // The in-situ fields given before: the new zones and the joints of their blocks take them.
            if (!m.insitu.empty()) {
                const InsituCount ic = apply_kept_insitu(m, blocks);
                report_insitu(ctx, a.loc, ic, "in-situ stress given before: ");
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
