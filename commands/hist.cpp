#include "analysis_mode.h"
#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/cable.h"
#include "engine/liner.h"
#include "engine/contact.h"
#include "engine/zones.h"
#include "fish/intrinsics.h"
#include "fish/runtime.h"
#include "io/csv.h"

#include <cmath>
#include <cstdio>

namespace odec {

namespace {

struct BlockQuantity {
    const char* name;
    HistoryKind kind;
};
const BlockQuantity kBlockQuantities[] = {
    {"xdisplacement", HistoryKind::XDis}, {"ydisplacement", HistoryKind::YDis}, {"zdisplacement", HistoryKind::ZDis},
    {"xvelocity", HistoryKind::XVel},     {"yvelocity", HistoryKind::YVel},     {"zvelocity", HistoryKind::ZVel},
    {"xacceleration", HistoryKind::XAcc}, {"yacceleration", HistoryKind::YAcc}, {"zacceleration", HistoryKind::ZAcc},
};


} // namespace

const CommandSpec& hist_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("history", 3, "record a quantity as the model cycles, or write recorded histories");
        c.keyword("unbalanced", 2, "largest unbalanced force on a block, N").in_choice(1);
        c.keyword("ratio", 2, "mean unbalanced-force ratio").in_choice(1);
        c.keyword("time", 2, "model time, s").in_choice(1);
        c.keyword("damp", 4, "mass-proportional damping coefficient in use ('damp auto' or 'damp ... mass'), 1/s; 0 with local damping or none").in_choice(1);
        c.keyword("step", 2, "step number").in_choice(1);
        for (const BlockQuantity& q : kBlockQuantities) {
            const std::string n = q.name;
            const bool dis = n[1] == 'd', acc = n[1] == 'a';
            c.keyword(n, 4, std::string(dis ? "displacement " : acc ? "acceleration " : "velocity ") + n[0] +
                                " component of the material point of the block containing or nearest the point, " +
                                (dis ? "m, since the last 'reset disp'" : acc ? "m/s^2" : "m/s"))
                .vec("x,y,z")
                .in_choice(1);
        }
        for (const char* s : {"sxx", "syy", "szz", "sxy", "sxz", "syz"}) {
            c.keyword(s, 3, std::string(s) + " stress of the zone containing or nearest the point, Pa (tension positive)")
                .vec("x,y,z")
                .in_choice(1);
        }
        for (const char* r : {"xreaction", "yreaction", "zreaction"}) {
            c.keyword(r, 4, std::string("total ") + r[0] + " unbalanced force on the held gridpoints "
                            "(and fixed blocks) of the range: the load on the supports, N")
                .in_choice(1);
        }
        c.keyword("nstress", 2, "normal stress of the contact nearest the point (or the one given by contact), Pa (compression positive)").vec("x,y,z").optional().in_choice(1);
        c.keyword("sstress", 2, "shear stress of the contact nearest the point (or the one given by contact), Pa").vec("x,y,z").optional().in_choice(1);
        c.keyword("ndis", 2, "normal closure of the contact nearest the point (or the one given by contact), m").vec("x,y,z").optional().in_choice(1);
        c.keyword("sdis", 2, "shear displacement of the contact nearest the point (or the one given by contact), m").vec("x,y,z").optional().in_choice(1);
        c.keyword("nf_sum", 4, "total normal force of the contact nearest the point (or the one given by contact), N (compression positive)").vec("x,y,z").optional().in_choice(1);
        c.keyword("sf_sum", 4, "magnitude of the total shear force of the contact nearest the point (or the one given by contact), N").vec("x,y,z").optional().in_choice(1);
        c.keyword("fish", 4, "the value of a FISH variable or function (also written 'hist @name'), in its own unit")
            .word("name")
            .in_choice(1);
        {
            std::vector<std::string> terms;
            for (const EnergyTermInfo& t : energy_terms()) terms.push_back(t.name);
            c.keyword("energy", 3, "a term of the energy account ('set energy on'), J: kinetic, jstrain, zstrain, "
                                   "gravity, load, velocity, boundary, damping, slip, plastic, initial, given or "
                                   "error ('help set' and 'print energy' say what each is)")
                .one_of("term", terms)
                .in_choice(1);
        }
        c.keyword("cable_force", 7, "axial force of the cable segment whose middle is nearest the point, N (tension positive)")
            .vec("x,y,z")
            .in_choice(1);
        c.keyword("cable_grout", 7, "grout force on the cable node nearest the point, along the cable from its first "
                                    "node to its last, N")
            .vec("x,y,z")
            .in_choice(1);
        c.keyword("pp", 2, "pore pressure of the flow node nearest the point, Pa ('config flow')").vec("x,y,z").in_choice(1);
        c.keyword("aperture", 3, "hydraulic aperture of the flow node nearest the point, m (mean over its area)").vec("x,y,z").in_choice(1);
        c.keyword("flowrate", 5, "flow the fixed-pressure boundaries feed into the joints, m^3/s").in_choice(1);
        c.keyword("liner_nx", 8, "membrane force n_x of the liner element whose centroid is nearest the point, N/m "
                                 "(tension positive; x around the liner's axis: 'help liner')")
            .vec("x,y,z")
            .in_choice(1);
        c.keyword("liner_mx", 8, "bending moment m_x of the liner element whose centroid is nearest the point, N m/m "
                                 "(positive: the face on the void's side in tension)")
            .vec("x,y,z")
            .in_choice(1);
        c.keyword("contact", 4, "with a contact quantity: follow the contact with this id instead of a point")
            .integer("id", 1);
        c.keyword("write", 2, "write histories n ... to a CSV file").integer("n", 1).repeat().in_choice(1);
        c.keyword("list", 2, "list the histories: number, samples, the step of the first, label").in_choice(1);
        c.keyword("vs", 2, "with 'write': history m as the first column instead of the step").integer("m", 1);
        c.keyword("file", 2, "with 'write': the CSV file").string("name");
        c.keyword("ncyc", 2, "steps between samples (for all histories)").integer("n", 1).defaults("10");
        c.keyword("label", 3, "title of history n").integer("n", 1).string("text");
        c.range("with a reaction: which gridpoints (by position) and rigid blocks (by centroid) are summed");
        c.describe("Each history is numbered in the order it was made, from 1. Samples are taken every "
                   "'ncyc' steps; a history made during a run has its own from the next sample on ('print "
                   "hist' leaves it blank before, 'hist write' leaves the cell empty). A block quantity follows "
                   "the material point of the block found at the point when the history is made (in a "
                   "deformable block, the gridpoint nearest the point), into whichever piece holds it when a "
                   "joint set cuts the block: its displacement is where it is less where it was at the last "
                   "'reset disp' (or when the block was made), exact however far the block has turned. A FISH "
                   "history whose function fails, or gives no finite number, stops 'step' or 'solve' with the "
                   "reason; the step it failed at stands, without its sample. A zone stress follows "
                   "the zone containing the point. A reaction sums, over the gridpoints of the range whose "
                   "velocity component is held ('fix', 'bound xvel ...') and the fixed rigid blocks of the "
                   "range, the unbalanced force there: the force the rest of the model exerts on what holds "
                   "it. A footing pushed down at constant velocity reads the resistance of the ground as a "
                   "positive 'zreaction'; a base carrying a weight reads it as a negative one.");
        c.example("hist zdis 0,0,5");
        c.example("hist write 1 2 vs 3 file 'fall.csv'");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            HistorySet& hs = m.histories;
            const std::string what = a.chosen(1);
            if (a.has("contact") && what != "nstress" && what != "sstress" && what != "ndis" && what != "sdis" &&
                what != "nf_sum" && what != "sf_sum") {
                fail(a.find("contact")->loc, "'contact' goes with a contact quantity: nstress, sstress, ndis, sdis, nf_sum or sf_sum", {}, "history");
            }
            if ((a.has("vs") || a.has("file")) && what != "write") {
                const KeywordUse* u = a.has("vs") ? a.find("vs") : a.find("file");
                fail(u->loc, "'" + u->spec->name + "' goes with 'write'", {}, "history");
            }
            if ((what == "write" || what == "list") && (a.has("ncyc") || a.has("label"))) {
                const KeywordUse* u = a.has("ncyc") ? a.find("ncyc") : a.find("label");
                fail(u->loc, "'" + u->spec->name + "' does not go with '" + what + "': give it in a 'history' of its own",
                     {}, "history");
            }
            if (what == "write") {
                std::vector<int> numbers;
                for (const Value& v : a.find("write")->values) numbers.push_back(history_number(m, v, "history"));
                const int vs = a.has("vs") ? history_number(m, a.find("vs")->values[0], "history") : 0;
                if (!a.has("file")) fail(a.find("write")->loc, "'write' needs 'file name.csv'", {}, "history");
                check_file_allowed(ctx, a.find("file")->values[0].loc, a.text("file"), "history");
                std::string error;
                size_t rows = 0;
                if (!write_histories_csv(hs, numbers, vs, a.text("file"), error, &rows)) {
                    fail(a.find("file")->values[0].loc, error, {}, "history");
                }
                if (!ctx.interp.quiet) {
                    ctx.out << "wrote " << rows << " samples of " << numbers.size() << " histories to "
                            << a.text("file") << "\n";
                }
                return;
            }
            if (what == "list") {
                std::ostream& o = ctx.out;
                o << "   n   samples   first step  label\n";
                for (size_t k = 0; k < hs.items.size(); ++k) {
                    const History& h = hs.items[k];
                    char line[64];
                    const std::string from = h.values.empty() ? "-" : std::to_string(hs.sample_steps[h.first]);
                    std::snprintf(line, sizeof line, "%4zu %9zu %12s  ", k + 1, h.values.size(), from.c_str());
                    o << line << h.label << "\n";
                }
                o << hs.items.size() << " histories, sampled every " << hs.ncyc << " steps ("
                  << hs.sample_steps.size() << " samples; a history made during a run has its own from the "
                  << "next sample on)\n";
                return;
            }
            if (a.has("label")) history_number(m, a.find("label")->values[0], "history");
            if (a.has("ncyc")) hs.ncyc = a.integer("ncyc");
            if (a.has("label")) {
                const KeywordUse* u = a.find("label");
                hs.items[static_cast<int>(u->values[0].number) - 1].label = u->values[1].text;
            }
            if (what.empty()) {
                if (!a.has("ncyc") && !a.has("label")) {
                    fail(a.loc, "'history' needs a quantity to record, or 'write', 'ncyc' or 'label'", {}, "history");
                }
                return;
            }
            if (a.has_range && what.find("reaction") == std::string::npos) {
                fail(a.loc, "'range' goes with a reaction (xreaction, yreaction, zreaction)", {}, "history");
            }
            History h;
            if (what == "unbalanced") h.kind = HistoryKind::Unbalanced;
            else if (what == "ratio") h.kind = HistoryKind::Ratio;
            else if (what == "time") {
                h.kind = HistoryKind::Time;
                note_static_time(ctx, "a history of time");
            }
            else if (what == "step") h.kind = HistoryKind::Step;
            else if (what == "damp") h.kind = HistoryKind::Damp;
            else if (what == "energy") {
                h.kind = HistoryKind::Energy;
                h.source = a.text("energy");
                if (!m.energy.on && !ctx.interp.quiet) {
                    ctx.out << "note: the energy account is off: this history reads 0 until 'set energy on'\n";
                }
            }
            else if (what == "fish") {
                h.kind = HistoryKind::Fish;
                const Value& v = a.find("fish")->values[0];
                h.source = v.text;
                if (!h.source.empty() && h.source[0] == '@') h.source.erase(0, 1);
                std::string lower = h.source;
                for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
                if (ctx.interp.fish().command_local(lower)) {
                    fail(v.loc, "'" + h.source + "' is an argument or local of '" + ctx.interp.fish().command_function() +
                                    "', gone when it returns: a history samples a global as the model cycles",
                         {"assign the value to a global and record that"}, "history");
                }
                const fish::Symbol* s = ctx.interp.fish().find(lower);
                if (!s && !fish::find_intrinsic(lower)) {
                    fail(v.loc, "'" + h.source + "' is no FISH variable or function",
                         {"define it first: def " + h.source + " ... end"}, "history");
                }
                if (s && s->array) fail(v.loc, "'" + h.source + "' is an array: a history records one value", {}, "history");
            }
            for (const BlockQuantity& q : kBlockQuantities) {
                if (what != q.name) continue;
                h.kind = q.kind;
                h.point = a.vec(what);
                // The point rides on the block: from far away its motion would be its rotation
                // times a huge lever, overflowing to inf.
                if (h.point.cwiseAbs().maxCoeff() > 1e9) {
                    fail(a.find(what)->values[0].loc,
                         "the point " + vec_text(h.point) + " is too far from the origin: a history point must be "
                         "within 1e+09 m, on or near the block it follows",
                         {}, "history");
                }
                const int b = find_block_at(m, h.point);
                if (b < 0) fail(a.find(what)->loc, "there are no blocks to follow", {"create blocks first"}, "history");
                h.block_id = m.blocks.id[b];
                // The block's own gridpoint: one across a joint would follow the other block.
                if (m.blocks.flags[b] & kDeformable) h.gridpoint = find_gridpoint_of_block_near(m, b, h.point);
                h.body_offset = m.blocks.orientation[b].conjugate() * (h.point - m.blocks.centroid[b]);
            }
            const struct { const char* name; HistoryKind kind; } zone_quantities[] = {
                {"sxx", HistoryKind::SXX}, {"syy", HistoryKind::SYY}, {"szz", HistoryKind::SZZ},
                {"sxy", HistoryKind::SXY}, {"sxz", HistoryKind::SXZ}, {"syz", HistoryKind::SYZ}};
            for (const auto& q : zone_quantities) {
                if (what != q.name) continue;
                h.kind = q.kind;
                h.point = a.vec(what);
                h.zone = find_zone_at(m, h.point);
                if (h.zone < 0) {
                    fail(a.find(what)->loc, "there are no zones to follow",
                         {"divide blocks into zones with 'gen edge e'"}, "history");
                }
            }
            const struct { const char* name; HistoryKind kind; } reactions[] = {
                {"xreaction", HistoryKind::XReaction}, {"yreaction", HistoryKind::YReaction},
                {"zreaction", HistoryKind::ZReaction}};
            for (const auto& q : reactions) {
                if (what != q.name) continue;
                h.kind = q.kind;
                h.gridpoints = select_gridpoints(m, a.range);
                for (int b : select_blocks(m, a.range)) {
                    if (!(m.blocks.flags[b] & kDeformable)) h.blocks.push_back(m.blocks.id[b]);
                }
                if (h.gridpoints.empty() && h.blocks.empty()) {
                    fail(a.find(what)->loc, "the range selects no gridpoint or block to sum the reaction over", {},
                         "history");
                }
            }
            const struct { const char* name; HistoryKind kind; } contact_quantities[] = {
                {"nstress", HistoryKind::NStress}, {"sstress", HistoryKind::SStress},
                {"ndis", HistoryKind::NDis}, {"sdis", HistoryKind::SDis},
                {"nf_sum", HistoryKind::NForce}, {"sf_sum", HistoryKind::SForce}};
            for (const auto& q : contact_quantities) {
                if (what != q.name) continue;
                h.kind = q.kind;
                const KeywordUse* u = a.find(what);
                const KeywordUse* by_id = a.find("contact");
                if (u->values.empty() == (by_id == nullptr)) {
                    fail(u->loc, "'" + what + "' needs a point x,y,z or 'contact id', one of them", {}, "history");
                }
                refresh_world_vertices(m);
                detect_contacts(m);
                int c = -1;
                if (by_id) {
                    c = contact_index(m, by_id->values[0].number > 0 ? static_cast<int>(by_id->values[0].number) : 0);
                    if (c < 0) {
                        fail(by_id->values[0].loc, "there is no contact " + std::to_string(static_cast<int>(by_id->values[0].number)),
                             {"'print contact' lists them"}, "history");
                    }
                    h.point = contact_centroid(m, c);
                } else {
                    h.point = u->values[0].vec;
                    c = find_contact_at(m, h.point);
                    if (c < 0) fail(u->loc, "there are no contacts to follow", {"blocks touch once they are made and cycled"}, "history");
                }
                h.contact_id = m.contacts.id[c];
            }
            if (what == "cable_force" || what == "cable_grout") {
                const bool force = what == "cable_force";
                h.kind = force ? HistoryKind::CableForce : HistoryKind::CableGrout;
                h.point = a.vec(what);
                int c = -1;
                const int k = force ? nearest_cable_segment(m, h.point, c) : nearest_cable_node(m, h.point, c);
                if (k < 0) fail(a.find(what)->loc, "there are no cables to follow", {"make one with 'cable'"}, "history");
                h.cable_id = m.cables.id[c];
                h.cable_item = force ? k - m.cables.first_segment(c) + 1 : k - m.cables.node_offset[c] + 1;
            }
            if (what == "pp" || what == "aperture" || what == "flowrate") {
                if (!m.flow.configured) fail(a.find(what)->loc, "fluid flow is not configured", {"give 'config flow' first (3DEC writes 'config fluid')"}, "history");
                h.kind = what == "pp" ? HistoryKind::PorePressure : what == "aperture" ? HistoryKind::Aperture : HistoryKind::FlowRate;
                if (what != "flowrate") h.point = a.vec(what);
            }
            if (what == "liner_nx" || what == "liner_mx") {
                h.kind = what == "liner_nx" ? HistoryKind::LinerNx : HistoryKind::LinerMx;
                h.point = a.vec(what);
                const int e = nearest_liner_element(m, h.point);
                if (e < 0) fail(a.find(what)->loc, "there are no liners to follow", {"make one with 'liner'"}, "history");
                const int c = m.liners.liner_of_element(e);
                h.cable_id = m.liners.id[c];
                h.cable_item = e - m.liners.elem_offset[c] + 1;
            }
            h.label = history_default_label(h);
            // Its own samples start with the next one the model takes.
            h.first = static_cast<long>(hs.sample_steps.size());
            hs.items.push_back(std::move(h));
            if (!ctx.interp.quiet) {
                ctx.out << "history " << hs.items.size() << ": " << hs.items.back().label << "\n";
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
