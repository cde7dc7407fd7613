#include "render/contact_bridge.h"

#include "engine/flow.h"

namespace odec {

namespace {

// State of one sub-contact, with the same precedence contact_info() gives a whole contact
// (slipping, then open, then failed), so a contact reads like its sub-contacts.
ContactState sub_state(std::uint8_t flags) {
    if (flags & kSubSlip) return ContactState::Slipping;
    if (flags & kSubOpen) return ContactState::Open;
    if (flags & kSubFailed) return ContactState::Failed;
    return ContactState::Elastic;
}

void reserve_rows(ContactRows& r, size_t n, bool sub) {
    r.centroid.reserve(n); r.normal.reserve(n); r.area.reserve(n); r.block1.reserve(n); r.block2.reserve(n);
    r.normal_stress.reserve(n); r.shear_stress.reserve(n); r.normal_disp.reserve(n); r.shear_disp.reserve(n);
    r.force.reserve(n); r.state.reserve(n);
    if (sub) r.parent.reserve(n);
}

} // namespace

std::vector<std::string> contact_state_names() {
    std::vector<std::string> names;
    for (ContactState s : {ContactState::Elastic, ContactState::Slipping, ContactState::Open, ContactState::Failed})
        names.push_back(contact_state_name(s));
    return names;
}

ContactView make_contact_view(const Model& m, const std::vector<int>* contact_indices) {
    const ContactSet& cs = m.contacts;
    const BlockSet& bs = m.blocks;
    ContactView view;
    view.state_names = contact_state_names();

    std::vector<int> all;
    if (!contact_indices) {
        all.resize(cs.size());
        for (int c = 0; c < cs.size(); ++c) all[c] = c;
    }
    const std::vector<int>& chosen = contact_indices ? *contact_indices : all;
    // The sub-contact arrays may lag the contact arrays only if detection never ran.
    const bool have_subs = static_cast<int>(cs.sub_offset.size()) == cs.size() + 1;

    ContactRows& rows = view.contacts;
    ContactRows& subs = view.sub_contacts;
    // The pore pressures and apertures, when the flow nodes were made for these sub-contacts.
    const FlowSet& fl = m.flow;
    const bool flow = fl.configured && have_subs && static_cast<int>(fl.sub_node.size()) == cs.n_subs() &&
                      fl.sub_aperture.size() == fl.sub_node.size();
    reserve_rows(rows, chosen.size(), false);
    if (have_subs) reserve_rows(subs, static_cast<size_t>(cs.n_subs()), true);

    for (int c : chosen) {
        if (c < 0 || c >= cs.size()) continue;
        const ContactInfo info = contact_info(m, c);
        const int row = rows.size();
        const int id_a = bs.id[info.block_a], id_b = bs.id[info.block_b];
        rows.centroid.push_back(info.centroid);
        rows.normal.push_back(info.normal);
        rows.area.push_back(info.area);
        rows.block1.push_back(id_a);
        rows.block2.push_back(id_b);
        rows.normal_stress.push_back(info.normal_stress);
        rows.shear_stress.push_back(info.shear_stress_vec);
        rows.normal_disp.push_back(info.normal_disp); // closure positive, as print and hist
        rows.shear_disp.push_back(info.shear_disp_vec);
        rows.state.push_back(static_cast<int>(info.state));
        if (flow) {
            const ContactFlow cf = contact_flow(m, c);
            rows.pore_pressure.push_back(cf.pp);
            rows.aperture.push_back(cf.aperture);
        }

        Vec3 force = Vec3::Zero();
        if (have_subs) {
            const double kn = contact_kn(m, c);
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                // The force the joint law puts on block b: area * (sn n + ss).
                const double sn = cs.sub_sn_for(c, k, kn);
                const Vec3 f = cs.sub_area[k] * (sn * info.normal + cs.sub_shear_stress(c, k));
                force += f;
                subs.centroid.push_back(sub_point(m, c, k));
                subs.normal.push_back(info.normal);
                subs.area.push_back(cs.sub_area[k]);
                subs.block1.push_back(id_a);
                subs.block2.push_back(id_b);
                subs.normal_stress.push_back(sn);
                subs.shear_stress.push_back(cs.sub_shear_stress(c, k));
                subs.normal_disp.push_back(sub_closure(m, c, k) + cs.sub_dilation(k));
                subs.shear_disp.push_back(cs.sub_shear_disp(c, k));
                subs.force.push_back(f);
                subs.state.push_back(static_cast<int>(sub_state(cs.sub_flags(k))));
                subs.parent.push_back(row);
                if (flow) {
                    const int node = fl.sub_node[k];
                    subs.pore_pressure.push_back(node >= 0 ? fl.pp[node] : 0.0);
                    subs.aperture.push_back(fl.sub_aperture[k]);
                }
            }
        }
        rows.force.push_back(force);
    }
    return view;
}

} // namespace odec
