// Contact bookkeeping and queries: clearing, joint materials, gluing, and what print,
// hist and pictures read (per-contact means over the sub-contacts).
#include "engine/contact.h"

#include <algorithm>
#include <limits>

#include "engine/blocks.h"
#include "engine/common_plane.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "engine/range.h"

namespace odec {

const char* contact_state_name(ContactState s) {
    switch (s) {
    case ContactState::Elastic: return "elastic";
    case ContactState::Slipping: return "slipping";
    case ContactState::Open: return "open";
    case ContactState::Failed: return "failed";
    }
    return "?";
}

void ContactSet::clear() {
    id.clear(); block_a.clear(); block_b.clear(); normal_code.clear(); gap.clear();
    joint.clear(); free_motion.clear(); sub_offset.assign(1, 0);
    sub_code.clear(); key_table = KeyTable{}; sub_area.clear();
    sub_point.clear(); sub_un.clear(); sub_udil.clear(); sub_us.clear(); sub_ss.clear();
    sub_tri.clear();
    detected = false;
    surface_ready = false;
    colored = false;
    ref_centroid.clear(); ref_orientation.clear(); geo_centroid.clear(); geo_orientation.clear();
    radius.clear();
    summary_revision = -1;
    open_by_reference = false;
}

void ContactSet::compact_key_table() {
    std::size_t live = 0;
    for (const std::uint32_t code : sub_code) live += key_code_in_table(code);
    if (key_table.keys.size() <= 2 * live + 1024) {
        key_table.live = live;
        return;
    }
    std::vector<std::int64_t> keys;
    keys.reserve(live);
    for (std::uint32_t& code : sub_code) {
        if (!key_code_in_table(code)) continue;
        keys.push_back(key_table.keys[key_code_index(code)]);
        code = table_key_code(keys.size() - 1);
    }
    key_table.keys.swap(keys);
    key_table.live = live;
}

int ContactSet::sub_owner(int k) const {
    // The last contact whose first sub-contact is at or before k (empty contacts share it).
    return static_cast<int>(std::upper_bound(sub_offset.begin(), sub_offset.end() - 1, k) - sub_offset.begin()) - 1;
}

ContactInfo contact_info(const Model& m, int c, bool touch_area) {
    const ContactSet& cs = m.contacts;
    ContactInfo info;
    info.id = cs.id[c];
    info.block_a = cs.block_a[c];
    info.block_b = cs.block_b[c];
    info.normal = cs.normal(c);
    info.jmat = cs.jmat(c);
    info.jcons = cs.jcons(c);
    info.joined = cs.joined(c);
    const int k0 = cs.sub_offset[c], k1 = cs.sub_offset[c + 1];
    info.n_subs = k1 - k0;
    double area = 0, sn = 0, un = 0;
    const double kn = contact_kn(m, c);
    Vec3 x = Vec3::Zero(), ss = Vec3::Zero(), us = Vec3::Zero();
    bool any_slip = false, all_open = true, any_failed = false;
    for (int k = k0; k < k1; ++k) {
        const double w = cs.sub_area[k];
        x += w * sub_point(m, c, k);
        area += w;
        sn += w * cs.sub_sn_for(c, k, kn);
        un += w * (sub_closure(m, c, k) + cs.sub_dilation(k));
        ss += w * cs.sub_shear_stress(c, k);
        us += w * cs.sub_shear_disp(c, k);
        any_slip |= (cs.sub_flags(k) & kSubSlip) != 0;
        all_open &= (cs.sub_flags(k) & kSubOpen) != 0;
        any_failed |= (cs.sub_flags(k) & kSubFailed) != 0;
    }
    info.area = touch_area ? contact_touch_area(m, c) : 0.0;
    if (area > 0) {
        info.centroid = x / area;
        info.normal_stress = sn / area;
        info.normal_disp = un / area;
        info.shear_stress_vec = ss / area;
        info.shear_disp_vec = us / area;
        info.shear_stress = info.shear_stress_vec.norm();
        info.shear_disp = info.shear_disp_vec.norm();
    } else {
        info.centroid = contact_point(m, c);
        info.normal_disp = 0.0 - cs.gap[c]; // never -0
    }
    if (any_slip) info.state = ContactState::Slipping;
    else if (all_open) info.state = ContactState::Open;
    else if (any_failed) info.state = ContactState::Failed;
    else info.state = ContactState::Elastic;
    return info;
}

Vec3 contact_centroid(const Model& m, int c) {
    const ContactSet& cs = m.contacts;
    double area = 0;
    Vec3 x = Vec3::Zero();
    for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
        x += cs.sub_area[k] * sub_point(m, c, k);
        area += cs.sub_area[k];
    }
    return area > 0 ? Vec3(x / area) : contact_point(m, c);
}

Vec3 contact_point(const Model& m, int c) {
    const ContactSet& cs = m.contacts;
    const BlockSet& s = m.blocks;
    const int a = cs.block_a[c], b = cs.block_b[c];
    // The world vertices of the last step or refresh, as detection sees them; the blocks'
    // shapes placed now where those are not in step with the blocks (a model just restored).
    const int n = s.size();
    if (static_cast<int>(s.vertex_offset.size()) == n + 1 &&
        static_cast<int>(s.world_vertices.size()) == s.vertex_offset[n]) {
        const BlockView va{s.world_vertices.data() + s.vertex_offset[a], &s.shape[a]};
        const BlockView vb{s.world_vertices.data() + s.vertex_offset[b], &s.shape[b]};
        return plane_point(va, vb, cs.normal(c));
    }
    const Polyhedron pa = world_shape(m, a), pb = world_shape(m, b);
    return plane_point(BlockView{pa.vertices.data(), &pa}, BlockView{pb.vertices.data(), &pb}, cs.normal(c));
}

const JointMaterial* joint_material(const Model& m, int jm) {
    if (jm <= 0 || jm >= static_cast<int>(m.joint_materials.size()) || !m.joint_materials[jm].defined) return nullptr;
    return &m.joint_materials[jm];
}

const JointMaterial* contact_joint_material(const Model& m, int c) { return joint_material(m, m.contacts.jmat(c)); }

double contact_kn(const Model& m, int c) {
    const JointMaterial* j = contact_joint_material(m, c);
    return j ? j->kn : 0.0;
}

double sub_normal_stress(const Model& m, int c, int k) { return m.contacts.sub_sn_for(c, k, contact_kn(m, c)); }

double sub_normal_stress(const Model& m, int k) { return sub_normal_stress(m, m.contacts.sub_owner(k), k); }

Vec3 sub_point(const Model& m, int c, int k) {
    const ContactSet& cs = m.contacts;
    const int side = cs.sub_side(k);
    if (side >= 3) return m.gridpoints.pos[cs.sub_vertex(k)];
    const int owner = side == 1 ? cs.block_b[c] : cs.block_a[c];
    return m.blocks.centroid[owner] + m.blocks.orientation[owner] * cs.sub_point_local(k);
}

bool closure_by_reference(const Model& m, int c) {
    const ContactSet& cs = m.contacts;
    return cs.open_by_reference && !((m.blocks.flags[cs.block_a[c]] | m.blocks.flags[cs.block_b[c]]) & kDeformable);
}

double reference_shift(const Model& m, int a, int b, const Vec3& x, const Vec3& n) {
    const ContactSet& cs = m.contacts;
    const BlockSet& s = m.blocks;
    // The material point of X at x was at g + Rg R^T (x - c) when X stood at its reference.
    auto moved = [&](int blk) -> Vec3 {
        if (static_cast<size_t>(blk) >= cs.geo_centroid.size() || static_cast<size_t>(blk) >= cs.geo_orientation.size()) {
            return Vec3::Zero(); // no reference yet
        }
        const Vec3 r = x - s.centroid[blk];
        return x - cs.geo_centroid[blk] - cs.geo_orientation[blk] * (s.orientation[blk].conjugate() * r);
    };
    return n.dot(moved(b) - moved(a));
}

double sub_closure(const Model& m, int c, int k) {
    const ContactSet& cs = m.contacts;
    if (!held_open(cs.sub_flags(k)) || !closure_by_reference(m, c)) return cs.sub_un[k];
    return cs.sub_un[k] - reference_shift(m, cs.block_a[c], cs.block_b[c], sub_point(m, c, k), cs.normal(c));
}

void set_sub_closure(Model& m, int c, int k, double un) {
    ContactSet& cs = m.contacts;
    if (!held_open(cs.sub_flags(k)) || !closure_by_reference(m, c)) {
        cs.sub_un[k] = un;
        return;
    }
    cs.sub_un[k] = un + reference_shift(m, cs.block_a[c], cs.block_b[c], sub_point(m, c, k), cs.normal(c));
}

void shift_open_closures(Model& m, int c, bool to_reference) {
    ContactSet& cs = m.contacts;
    if (!closure_by_reference(m, c)) return;
    for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
        if (!held_open(cs.sub_flags(k))) continue;
        const double d = reference_shift(m, cs.block_a[c], cs.block_b[c], sub_point(m, c, k), cs.normal(c));
        cs.sub_un[k] += to_reference ? d : -d;
    }
}

int find_contact_at(const Model& m, const Vec3& x) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int c = 0; c < m.contacts.size(); ++c) {
        const double d = (contact_centroid(m, c) - x).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best = c;
        }
    }
    return best;
}

int contact_index(const Model& m, int contact_id) {
    const ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        if (cs.id[c] == contact_id) return c;
    }
    return -1;
}

void ensure_contacts_current(Model& m, bool with_surface) {
    if (m.contacts_current() && (!with_surface || m.contacts.surface_ready)) return;
    refresh_world_vertices(m);
    detect_contacts(m);
}

int assign_joint_material(Model& m, const Range& r, int jmat, int jcons) {
    ensure_contacts_current(m, false); // contacts must exist before they can be changed
    ContactSet& cs = m.contacts;
    int changed = 0;
    for (int c = 0; c < cs.size(); ++c) {
        if (!r.contains_contact(m, contact_centroid(m, c), cs.block_a[c], cs.block_b[c])) continue;
        // As for blocks: hidden ones are left alone (3DEC's hide ... show ... change jmat).
        if ((m.blocks.flags[cs.block_a[c]] | m.blocks.flags[cs.block_b[c]]) & kHidden) continue;
        if (jmat > 0) cs.set_jmat(c, jmat);
        if (jcons > 0) cs.set_jcons(c, jcons);
        ++changed;
    }
    return changed;
}

int contact_without_joint_properties(const Model& m, bool loaded_only) {
    const ContactSet& cs = m.contacts;
    bool any_defined = false;
    for (const JointMaterial& j : m.joint_materials) any_defined = any_defined || j.defined;
    if (!any_defined) return -1;
    auto without = [&](int c) {
        if (contact_joint_material(m, c)) return false;
        return loaded_only ? cs.gap[c] < 0 : cs.jmat(c) > 0;
    };
    // Looked for on the threads: the run-away checks ask after every step.
    const int nc = cs.size();
    return parallel_first(nc, 8192, thread_count(), nc >= 4 * kParallelMinItems, without);
}

int join_blocks(Model& m, const std::vector<int>& block_indices) {
    ensure_contacts_current(m, false); // contacts must exist before they can be changed
    std::vector<char> sel(m.blocks.size(), 0);
    for (int b : block_indices) {
        if (b >= 0 && b < m.blocks.size()) sel[b] = 1;
    }
    ContactSet& cs = m.contacts;
    int n = 0;
    for (int c = 0; c < cs.size(); ++c) {
        if (sel[cs.block_a[c]] && sel[cs.block_b[c]]) {
            cs.set_joined(c, 1);
            ++n;
        }
    }
    return n;
}

} // namespace odec

