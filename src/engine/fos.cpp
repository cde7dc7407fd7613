#include "engine/fos.h"

#include <algorithm>
#include <cmath>

#include "engine/contact.h"

namespace odec {

namespace {

constexpr double kDeg = M_PI / 180.0;

// tan(phi_F) = tan(phi) / F, in degrees.
double reduced_angle(double phi_deg, double F) { return std::atan(std::tan(phi_deg * kDeg) / F) / kDeg; }

bool joint_has_target(const JointMaterial& j, const FosTargets& t) {
    return (t.friction && (j.friction > 0 || j.res_friction > 0)) || (t.cohesion && j.cohesion > 0) ||
           (t.tension && j.tension > 0);
}

bool zone_has_target(const Material& mt, const FosTargets& t) {
    return (t.friction && mt.friction > 0) || (t.cohesion && mt.cohesion > 0) || (t.tension && mt.tension > 0);
}

// A strength so large that nothing reaches it (Pa).
constexpr double kHuge = 1e30;

} // namespace

FosReducible fos_reducible(const Model& m, const FosTargets& t) {
    FosReducible r;
    if (t.joints) {
        const int n = static_cast<int>(m.joint_materials.size());
        std::vector<char> used(std::max(n, 1), 0);
        auto use = [&](int jm) {
            if (jm > 0 && jm < n) used[jm] = 1;
        };
        for (int c = 0; c < m.contacts.size(); ++c) use(m.contacts.jmat(c));
        for (const JointPlane& p : m.joint_planes) use(p.jmat > 0 ? p.jmat : m.settings.default_jmat);
        use(m.settings.default_jmat);
        for (int k = 1; k < n; ++k) {
            const JointMaterial& j = m.joint_materials[k];
            if (used[k] && j.defined && joint_has_target(j, t)) r.joint_materials.push_back(k);
        }
    }
    if (t.zones) {
        const int n = static_cast<int>(m.materials.size());
        std::vector<char> used(std::max(n, 1), 0);
        for (int z = 0; z < m.zones.size(); ++z) {
            if (m.zones.model[z] != kZoneMohrCoulomb) continue;
            const int b = m.zones.block[z];
            if (b < 0 || b >= m.blocks.size() || (m.blocks.flags[b] & kExcavated)) continue;
            const int mat = m.blocks.material[b];
            if (mat > 0 && mat < n) used[mat] = 1;
        }
        for (int k = 1; k < n; ++k) {
            if (used[k] && m.materials[k].defined && zone_has_target(m.materials[k], t)) r.zone_materials.push_back(k);
        }
    }
    return r;
}

FosIsolation fos_isolate(Model& m, const Range& range, FosReducible& r) {
    FosIsolation iso;
    iso.active = true;
    iso.n_joint_materials = static_cast<int>(m.joint_materials.size());
    iso.n_materials = static_cast<int>(m.materials.size());
    std::vector<int> joint_copy(iso.n_joint_materials, 0), material_copy(iso.n_materials, 0);
    for (int k : r.joint_materials) joint_copy[k] = -1; // reducible, no copy yet
    for (int k : r.zone_materials) material_copy[k] = -1;
    ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        const int jm = cs.jmat(c);
        if (jm <= 0 || jm >= iso.n_joint_materials || joint_copy[jm] == 0) continue;
        if (!range.contains_contact(m, contact_centroid(m, c), cs.block_a[c], cs.block_b[c])) continue;
        if (joint_copy[jm] < 0) {
            joint_copy[jm] = static_cast<int>(m.joint_materials.size());
            m.joint_materials.push_back(m.joint_materials[jm]);
            iso.joint_original.push_back(jm);
        }
        cs.set_jmat(c, joint_copy[jm]);
    }
    BlockSet& s = m.blocks;
    std::vector<char> zoned_mc(s.size(), 0);
    for (int z = 0; z < m.zones.size(); ++z) {
        const int b = m.zones.block[z];
        if (m.zones.model[z] == kZoneMohrCoulomb && b >= 0 && b < s.size()) zoned_mc[b] = 1;
    }
    for (int b = 0; b < s.size(); ++b) {
        const int mat = s.material[b];
        if (!zoned_mc[b] || (s.flags[b] & kExcavated) || mat <= 0 || mat >= iso.n_materials || material_copy[mat] == 0) continue;
        if (!range.contains_block(m, b)) continue;
        if (material_copy[mat] < 0) {
            material_copy[mat] = static_cast<int>(m.materials.size());
            m.materials.push_back(m.materials[mat]);
            iso.material_original.push_back(mat);
        }
        s.material[b] = material_copy[mat];
    }
    r.joint_materials.clear();
    for (int k = 0; k < static_cast<int>(iso.joint_original.size()); ++k) r.joint_materials.push_back(iso.n_joint_materials + k);
    r.zone_materials.clear();
    for (int k = 0; k < static_cast<int>(iso.material_original.size()); ++k) r.zone_materials.push_back(iso.n_materials + k);
    return iso;
}

void fos_unisolate(Model& m, const FosIsolation& iso) {
    if (!iso.active) return;
    ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        const int k = cs.jmat(c) - iso.n_joint_materials;
        if (k >= 0 && k < static_cast<int>(iso.joint_original.size())) cs.set_jmat(c, iso.joint_original[k]);
    }
    BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        const int k = s.material[b] - iso.n_materials;
        if (k >= 0 && k < static_cast<int>(iso.material_original.size())) s.material[b] = iso.material_original[k];
    }
    m.joint_materials.resize(iso.n_joint_materials);
    m.materials.resize(iso.n_materials);
}

FosBase fos_base(const Model& m) { return FosBase{m.joint_materials, m.materials}; }

void reduce_strengths(Model& m, const FosBase& base, const FosReducible& r, const FosTargets& t, double F) {
    for (int k : r.joint_materials) {
        const JointMaterial& b = base.joint_materials[k];
        JointMaterial& j = m.joint_materials[k];
        j.friction = t.friction ? reduced_angle(b.friction, F) : b.friction;
        j.res_friction = t.friction ? reduced_angle(b.res_friction, F) : b.res_friction;
        j.cohesion = t.cohesion ? b.cohesion / F : b.cohesion;
        j.tension = t.tension ? b.tension / F : b.tension;
        j.dilation = t.associated ? j.friction : std::min(b.dilation, j.friction);
    }
    for (int k : r.zone_materials) {
        const Material& b = base.materials[k];
        Material& mt = m.materials[k];
        mt.friction = t.friction ? reduced_angle(b.friction, F) : b.friction;
        mt.cohesion = t.cohesion ? b.cohesion / F : b.cohesion;
        mt.tension = t.tension ? b.tension / F : b.tension;
        mt.dilation = t.associated ? mt.friction : std::min(b.dilation, mt.friction);
    }
}

void restore_strengths(Model& m, const FosBase& base, const FosReducible& r) {
    for (int k : r.joint_materials) {
        const JointMaterial& b = base.joint_materials[k];
        JointMaterial& j = m.joint_materials[k];
        j.friction = b.friction;
        j.res_friction = b.res_friction;
        j.cohesion = b.cohesion;
        j.tension = b.tension;
        j.dilation = b.dilation;
    }
    for (int k : r.zone_materials) {
        const Material& b = base.materials[k];
        Material& mt = m.materials[k];
        mt.friction = b.friction;
        mt.cohesion = b.cohesion;
        mt.tension = b.tension;
        mt.dilation = b.dilation;
    }
}

void perturb_for_response(Model& m, const FosReducible& r, double factor) {
    for (int k : r.joint_materials) {
        JointMaterial& j = m.joint_materials[k];
        j.cohesion = j.tension = kHuge;
        j.dilation = 0;
    }
    for (int k : r.zone_materials) {
        Material& mt = m.materials[k];
        mt.cohesion = mt.tension = kHuge;
        mt.dilation = 0;
    }
    ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            set_sub_closure(m, c, k, sub_closure(m, c, k) * factor); // and with it the normal stress
            cs.sub_ss[k] *= factor;
        }
    }
    for (Sym6& s : m.zones.stress) {
        for (double& v : s) v *= factor;
    }
}

bool fos_model_loaded(const Model& m) {
    if (m.gravity.squaredNorm() > 0) return true;
    for (const auto& loads : m.blocks.loads) {
        for (const BlockLoad& l : loads) {
            if (l.force.squaredNorm() > 0 || l.couple.squaredNorm() > 0) return true;
        }
    }
    for (const Vec3& f : m.gridpoints.applied) {
        if (f.squaredNorm() > 0) return true;
    }
    for (const Vec3& f : m.gridpoints.traction) {
        if (f.squaredNorm() > 0) return true;
    }
    for (const Sym6& s : m.zones.stress) {
        for (double v : s) {
            if (v != 0) return true;
        }
    }
    for (int c = 0; c < m.contacts.size(); ++c) {
        const double kn = contact_kn(m, c);
        for (int k = m.contacts.sub_offset[c]; k < m.contacts.sub_offset[c + 1]; ++k) {
            if (m.contacts.sub_sn_for(c, k, kn) != 0) return true;
        }
    }
    for (const Eigen::Vector2d& ss : m.contacts.sub_ss) {
        if (ss.squaredNorm() > 0) return true;
    }
    return false;
}

FosBracket::FosBracket(double resolution, double f1, double f2)
    : resolution_(resolution), f1_(f1), f2_(f2), given_(f1 > 0 && f2 > 0) {
    next_ = given_ ? f1_ : 1.0;
}

void FosBracket::report(bool stable) {
    if (end_ != End::Running || next_ <= 0) return;
    const double f = next_;
    if (stable) {
        if (!has_stable_ || f > stable_) stable_ = f;
        has_stable_ = true;
    } else {
        if (!has_fail_ || f < fail_) fail_ = f;
        has_fail_ = true;
    }
    if (given_) {
        if (f1_ == f2_) {
            end_ = stable ? End::OneStable : End::OneFails;
            next_ = 0;
            return;
        }
        if (f == f1_ && !stable) {
            end_ = End::Below;
            next_ = 0;
            return;
        }
        if (f == f2_ && stable) {
            end_ = End::Above;
            next_ = 0;
            return;
        }
    }
    choose();
}

void FosBracket::choose() {
    if (given_ && !has_fail_) {
        next_ = f2_; // f1 was stable: try f2
        return;
    }
    if (!has_fail_) {
        if (stable_ >= kFosFar) {
            end_ = End::Above;
            next_ = 0;
        } else {
            next_ = 2 * stable_;
        }
        return;
    }
    if (!has_stable_) {
        if (fail_ <= 1 / kFosFar) {
            end_ = End::Below;
            next_ = 0;
        } else {
            next_ = 0.5 * fail_;
        }
        return;
    }
    // Found when the bracket is narrow enough, or when it can narrow no more: its ends are
    // neighbouring numbers, whose midpoint is one of them (a resolution below what a double
    // holds would repeat that trial for ever).
    const double mid = 0.5 * (stable_ + fail_);
    if (fail_ - stable_ <= resolution_ || !(mid > stable_ && mid < fail_)) {
        end_ = End::Found;
        next_ = 0;
        return;
    }
    next_ = mid;
}

} // namespace odec
