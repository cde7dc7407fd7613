#include "commands.h"
#include "common.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/cycle.h"

#include <cmath>

namespace odec {

namespace {

std::string col(const std::string& s, size_t w) { return s.size() >= w ? s + " " : std::string(w - s.size(), ' ') + s; }

void print_blocks(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    const BlockSet& s = m.blocks;
    const std::vector<int> sel = select_blocks(m, a.range, true);
    std::ostream& o = ctx.out;
    o << col("id", 6) << col("centroid x", 13) << col("y", 13) << col("z", 13) << col("disp x", 13) << col("y", 13)
      << col("z", 13) << col("vel x", 13) << col("y", 13) << col("z", 13) << col("mass", 13) << col("mat", 5)
      << col("reg", 5) << "  group  state\n";
    for (int b : sel) {
        const Vec3 v = velocity_at_t(m, b);
        std::string state = (s.flags[b] & kFixed) ? "fixed" : "free";
        if (s.flags[b] & kExcavated) state = "excavated";
        if (s.flags[b] & kHidden) state += ",hidden";
        o << col(std::to_string(s.id[b]), 6) << col(num(s.centroid[b].x()), 13) << col(num(s.centroid[b].y()), 13)
          << col(num(s.centroid[b].z()), 13) << col(num(s.disp[b].x()), 13) << col(num(s.disp[b].y()), 13)
          << col(num(s.disp[b].z()), 13) << col(num(v.x()), 13) << col(num(v.y()), 13) << col(num(v.z()), 13)
          << col(num(s.mass[b]), 13) << col(std::to_string(s.material[b]), 5) << col(std::to_string(s.region[b]), 5)
          << "  " << (s.group[b] >= 0 ? m.group_names[s.group[b]] : "-") << "  " << state << "\n";
    }
    o << sel.size() << " of " << s.size() << " blocks\n";
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
        for (size_t i = 0; i < numbers.size(); ++i) o << col(num(hs.items[numbers[i] - 1].values[k]), width[i]);
        o << "\n";
    }
}

void print_contacts(CommandContext& ctx, const Args& a) {
    const Model& m = ctx.model;
    std::ostream& o = ctx.out;
    o << col("id", 6) << col("block a", 8) << col("block b", 8) << col("centroid x", 12) << col("y", 12) << col("z", 12)
      << col("area", 11) << col("nstress", 12) << col("sstress", 12) << col("ndis", 12) << col("sdis", 12)
      << col("jmat", 5) << "  state\n";
    int n = 0;
    for (int c = 0; c < m.contacts.size(); ++c) {
        const ContactInfo ci = contact_info(m, c);
        if (a.has_range && !a.range.contains_contact(m, ci.centroid, ci.block_a, ci.block_b)) continue;
        ++n;
        o << col(std::to_string(ci.id), 6) << col(std::to_string(m.blocks.id[ci.block_a]), 8)
          << col(std::to_string(m.blocks.id[ci.block_b]), 8) << col(num(ci.centroid.x()), 12)
          << col(num(ci.centroid.y()), 12) << col(num(ci.centroid.z()), 12) << col(num(ci.area), 11)
          << col(num(ci.normal_stress), 12) << col(num(ci.shear_stress), 12) << col(num(ci.normal_disp), 12)
          << col(num(ci.shear_disp), 12) << col(std::to_string(ci.jmat), 5) << "  " << contact_state_name(ci.state)
          << (ci.joined ? ",joined" : "") << "\n";
    }
    o << n << " of " << m.contacts.size() << " contacts (stresses in Pa, compression positive; displacements in m)\n";
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
        take(vel, velocity_at_t(m, b).norm(), b);
        if (!(s.flags[b] & kFixed)) take(unbal, s.force[b].norm(), b);
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
    case DampingMode::Auto: o << "auto"; break;
    case DampingMode::Rayleigh: o << "Rayleigh, fraction " << num(d.rayleigh_fraction) << " at " << num(d.rayleigh_frequency) << " Hz (mass)"; break;
    case DampingMode::Off: o << "off"; break;
    }
    o << "\n";
    o << "timestep:   " << (m.settings.dt_fixed > 0 ? num(m.settings.dt_fixed) + " s (set dt)"
                                                    : "automatic, dtfrac " + num(m.settings.dtfrac))
      << (m.dt > 0 ? ", in use " + num(m.dt) + " s" : "") << "\n";
    o << "step:       " << m.step << "  time " << num(m.time) << " s\n";
    o << "histories:  " << m.histories.items.size() << " (every " << m.histories.ncyc << " steps, "
      << m.histories.sample_steps.size() << " samples)\n";
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
        c.range();
        c.require_one_of(1);
        c.example("print block range z 0 10");
        c.example("print hist 1 2");
        c.handle([](CommandContext& ctx, const Args& a) {
            const std::string what = a.chosen(1);
            if (a.has_range && what != "block" && what != "contact") {
                fail(a.range_loc, "'range' goes with 'print block' and 'print contact'", {}, "print");
            }
            if (what == "block") print_blocks(ctx, a);
            else if (what == "contact") print_contacts(ctx, a);
            else if (what == "max") print_max(ctx);
            else if (what == "history") print_histories(ctx, a);
            else print_info(ctx);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
