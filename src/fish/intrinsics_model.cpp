// The model seen from FISH: walks over blocks, contacts, sub-contacts, gridpoints and zones,
// their quantities, and the model's globals. Units are SI; stresses are tension positive for
// zones and compression positive for contacts (as `print` shows them); forces on a contact are
// those on its second block.
#include <cmath>

#include "engine/blocks.h"
#include "engine/cable.h"
#include "engine/clump.h"
#include "engine/liner.h"
#include "engine/contact.h"
#include "engine/flow.h"
#include "engine/cycle.h"
#include "engine/model.h"
#include "engine/zones.h"
#include "fish/intrinsics.h"
#include "fish/runtime.h"

namespace odec::fish {

namespace {

using A = const Value*;
using L = const SourceLoc&;

const char* kind_name(PtrKind k) {
    switch (k) {
    case PtrKind::Block: return "block";
    case PtrKind::Contact: return "contact";
    case PtrKind::Sub: return "sub-contact";
    case PtrKind::Gridpoint: return "gridpoint";
    case PtrKind::Zone: return "zone";
    }
    return "object";
}

int count_of(const Model& m, PtrKind k) {
    switch (k) {
    case PtrKind::Block: return m.blocks.size();
    case PtrKind::Contact: return m.contacts.size();
    case PtrKind::Sub: return m.contacts.n_subs();
    case PtrKind::Gridpoint: return m.gridpoints.size();
    case PtrKind::Zone: return m.zones.size();
    }
    return 0;
}

// The index a pointer argument stands for, checked.
int ptr(Runtime& rt, A a, int i, PtrKind k, const char* fn, L loc) {
    const Value& v = a[i];
    if (v.type != Type::Pointer || v.kind != k) {
        fish_fail(loc, std::string("'") + fn + "' needs a " + kind_name(k) + " pointer, not " +
                           (v.type == Type::Pointer ? std::string("a ") + kind_name(v.kind) + " pointer" : std::string(type_name(v))),
                  {v.is_null() ? "the walk has ended: the pointer is 0" : "take it from a walk or a finder"});
    }
    if (v.i < 0 || v.i >= count_of(rt.host.model(), k)) {
        fish_fail(loc, std::string("'") + fn + "': that " + kind_name(k) + " no longer exists",
                  {"the model changed since the pointer was taken (blocks deleted, contacts refreshed)"});
    }
    return static_cast<int>(v.i);
}

Model& model(Runtime& rt) { return rt.host.model(); }

// A detection of the contacts that FISH asks for counts against a session's bound on FISH
// work (Runtime::budget) as 200 loop iterations a block, about what it costs: a walk that
// changes the blocks at each step detects them again each time.
void ensure_contacts(Runtime& rt, Model& m, L loc) {
    if (!m.contacts_current()) {
        const long long cost = 200LL * m.blocks.size();
        rt.spend(cost, loc);
        ensure_contacts_current(m, false);
    }
}

Value vec(const Vec3& v) { return Value::vector(v); }
Value num(double x) { return Value::real(x); }

double checked(const Value& v, const char* fn, L loc) {
    if (!v.is_number() || !std::isfinite(v.number())) fish_fail(loc, std::string("'") + fn + "' takes a finite number");
    return v.number();
}

// -- blocks ------------------------------------------------------------------------------------
Value f_block_head(Runtime& rt, A, int, L) { return model(rt).blocks.size() > 0 ? Value::pointer(PtrKind::Block, 0) : Value::null(); }
Value f_b_next(Runtime& rt, A a, int, L loc) {
    const int b = ptr(rt, a, 0, PtrKind::Block, "b_next", loc);
    return b + 1 < model(rt).blocks.size() ? Value::pointer(PtrKind::Block, b + 1) : Value::null();
}
#define BLOCK(fn) const int b = ptr(rt, a, 0, PtrKind::Block, fn, loc); const BlockSet& B = model(rt).blocks; (void)B
Value f_b_id(Runtime& rt, A a, int, L loc) { BLOCK("b_id"); return Value::integer(B.id[b]); }
Value f_b_x(Runtime& rt, A a, int, L loc) { BLOCK("b_x"); return num(B.centroid[b].x()); }
Value f_b_y(Runtime& rt, A a, int, L loc) { BLOCK("b_y"); return num(B.centroid[b].y()); }
Value f_b_z(Runtime& rt, A a, int, L loc) { BLOCK("b_z"); return num(B.centroid[b].z()); }
Value f_b_pos(Runtime& rt, A a, int, L loc) { BLOCK("b_pos"); return vec(B.centroid[b]); }
Value f_b_vol(Runtime& rt, A a, int, L loc) { BLOCK("b_vol"); return num(B.volume[b]); }
Value f_b_mass(Runtime& rt, A a, int, L loc) { BLOCK("b_mass"); return num(B.mass[b]); }
Value f_b_region(Runtime& rt, A a, int, L loc) { BLOCK("b_region"); return Value::integer(B.region[b]); }
Value f_b_mat(Runtime& rt, A a, int, L loc) { BLOCK("b_mat"); return Value::integer(B.material[b]); }
Value f_b_clump(Runtime& rt, A a, int, L loc) { BLOCK("b_clump"); return Value::integer(B.clump[b]); }
Value f_b_fix(Runtime& rt, A a, int, L loc) { BLOCK("b_fix"); return Value::integer((B.flags[b] & kFixed) ? 1 : 0); }
Value f_b_type(Runtime& rt, A a, int, L loc) { BLOCK("b_type"); return Value::integer((B.flags[b] & kDeformable) ? 2 : 1); }
Value f_b_vel(Runtime& rt, A a, int, L loc) { BLOCK("b_vel"); return vec(velocity_at_t(model(rt), b)); }
Value f_b_xvel(Runtime& rt, A a, int, L loc) { BLOCK("b_xvel"); return num(velocity_at_t(model(rt), b).x()); }
Value f_b_yvel(Runtime& rt, A a, int, L loc) { BLOCK("b_yvel"); return num(velocity_at_t(model(rt), b).y()); }
Value f_b_zvel(Runtime& rt, A a, int, L loc) { BLOCK("b_zvel"); return num(velocity_at_t(model(rt), b).z()); }
Value f_b_disp(Runtime& rt, A a, int, L loc) { BLOCK("b_disp"); return vec(B.disp[b]); }
Value f_b_xdis(Runtime& rt, A a, int, L loc) { BLOCK("b_xdis"); return num(B.disp[b].x()); }
Value f_b_ydis(Runtime& rt, A a, int, L loc) { BLOCK("b_ydis"); return num(B.disp[b].y()); }
Value f_b_zdis(Runtime& rt, A a, int, L loc) { BLOCK("b_zdis"); return num(B.disp[b].z()); }
Value f_b_force(Runtime& rt, A a, int, L loc) { BLOCK("b_force"); return vec(B.force[b]); }
Value f_b_xforce(Runtime& rt, A a, int, L loc) { BLOCK("b_xforce"); return num(B.force[b].x()); }
Value f_b_yforce(Runtime& rt, A a, int, L loc) { BLOCK("b_yforce"); return num(B.force[b].y()); }
Value f_b_zforce(Runtime& rt, A a, int, L loc) { BLOCK("b_zforce"); return num(B.force[b].z()); }
Value f_b_zone(Runtime& rt, A a, int, L loc) {
    BLOCK("b_zone");
    const auto& z = rt.block_zones()[static_cast<size_t>(b)];
    return z.empty() ? Value::null() : Value::pointer(PtrKind::Zone, z.front(), b);
}
Value f_b_gp(Runtime& rt, A a, int, L loc) {
    BLOCK("b_gp");
    const auto& g = rt.block_gridpoints()[static_cast<size_t>(b)];
    return g.empty() ? Value::null() : Value::pointer(PtrKind::Gridpoint, g.front(), b);
}
Value f_b_near(Runtime& rt, A a, int n, L loc) {
    const int b = find_block_at(model(rt), point_args(a, n, 0, "b_near", loc));
    return b < 0 ? Value::null() : Value::pointer(PtrKind::Block, b);
}
void set_block_vel(Runtime& rt, A a, const Value& v, int k, const char* fn, L loc) {
    const int b = ptr(rt, a, 0, PtrKind::Block, fn, loc);
    Model& m = model(rt);
    const double x = checked(v, fn, loc);
    // A piece of a clump: its centroid's velocity, the whole clump following (clump.h).
    if (m.blocks.clump[b] != 0) {
        set_clump_component_at_t(m, b, k, x, false);
        return;
    }
    // The velocity given is the velocity at t, as b_xvel reads it: the stored mid-step
    // velocity differs from it by half a step of acceleration.
    double lead = velocity_at_t(m, b)[k] - m.blocks.vel[b][k];
    if (!std::isfinite(lead)) lead = 0;
    m.blocks.vel[b][k] = (m.blocks.flags[b] & kFixed) ? x : x - lead;
}
// The turn since 'reset disp' (0 for a deformable block: its gridpoints carry its motion).
Vec3 block_turn(Runtime& rt, int b) { return rotation_since_reset(model(rt), b); }
Value f_b_rot(Runtime& rt, A a, int, L loc) { BLOCK("b_rot"); return vec(block_turn(rt, b)); }
Value f_b_xrot(Runtime& rt, A a, int, L loc) { BLOCK("b_xrot"); return num(block_turn(rt, b).x()); }
Value f_b_yrot(Runtime& rt, A a, int, L loc) { BLOCK("b_yrot"); return num(block_turn(rt, b).y()); }
Value f_b_zrot(Runtime& rt, A a, int, L loc) { BLOCK("b_zrot"); return num(block_turn(rt, b).z()); }
Value f_b_euler(Runtime& rt, A a, int, L loc) {
    BLOCK("b_euler");
    const Quat turn = (B.orientation[b] * B.ref_orientation[b].conjugate()).normalized();
    return vec(euler_xyz(turn.toRotationMatrix()) * (180.0 / M_PI));
}
Value f_b_rvel(Runtime& rt, A a, int, L loc) { BLOCK("b_rvel"); return vec(spin_at_t(model(rt), b)); }
Value f_b_xrvel(Runtime& rt, A a, int, L loc) { BLOCK("b_xrvel"); return num(spin_at_t(model(rt), b).x()); }
Value f_b_yrvel(Runtime& rt, A a, int, L loc) { BLOCK("b_yrvel"); return num(spin_at_t(model(rt), b).y()); }
Value f_b_zrvel(Runtime& rt, A a, int, L loc) { BLOCK("b_zrvel"); return num(spin_at_t(model(rt), b).z()); }
void set_block_spin(Runtime& rt, A a, const Value& v, int k, const char* fn, L loc) {
    const int b = ptr(rt, a, 0, PtrKind::Block, fn, loc);
    Model& m = model(rt);
    const double x = checked(v, fn, loc);
    if (m.blocks.flags[b] & (kFixed | kDeformable)) {
        fish_fail(loc, std::string("'") + fn + "': block " + std::to_string(m.blocks.id[b]) + " is " +
                           ((m.blocks.flags[b] & kFixed) ? "fixed: it does not turn" : "deformable: its gridpoints carry its motion"));
    }
    // A piece of a clump: the clump's spin, the piece's centroid keeping its velocity (clump.h).
    if (m.blocks.clump[b] != 0) {
        set_clump_component_at_t(m, b, k, x, true);
        return;
    }
    // The spin given is the spin at t, as b_xrvel reads it (the integration holds it half a step back).
    double lead = spin_at_t(m, b)[k] - m.blocks.ang_vel[b][k];
    if (!std::isfinite(lead)) lead = 0;
    m.blocks.ang_vel[b][k] = x - lead;
}
void s_b_xrvel(Runtime& rt, A a, int, const Value& v, L loc) { set_block_spin(rt, a, v, 0, "b_xrvel", loc); }
void s_b_yrvel(Runtime& rt, A a, int, const Value& v, L loc) { set_block_spin(rt, a, v, 1, "b_yrvel", loc); }
void s_b_zrvel(Runtime& rt, A a, int, const Value& v, L loc) { set_block_spin(rt, a, v, 2, "b_zrvel", loc); }
void s_b_xvel(Runtime& rt, A a, int, const Value& v, L loc) { set_block_vel(rt, a, v, 0, "b_xvel", loc); }
void s_b_yvel(Runtime& rt, A a, int, const Value& v, L loc) { set_block_vel(rt, a, v, 1, "b_yvel", loc); }
void s_b_zvel(Runtime& rt, A a, int, const Value& v, L loc) { set_block_vel(rt, a, v, 2, "b_zvel", loc); }

Value extra_get(Runtime& rt, int slot, long long id) {
    auto it = rt.extras[slot].find(id);
    return it == rt.extras[slot].end() ? Value::integer(0) : it->second;
}
Value f_b_extra(Runtime& rt, A a, int, L loc) { BLOCK("b_extra"); return extra_get(rt, 0, B.id[b]); }
void s_b_extra(Runtime& rt, A a, int, const Value& v, L loc) { BLOCK("b_extra"); rt.extras[0][B.id[b]] = v; }

// -- contacts ------------------------------------------------------------------------------------
Value f_contact_head(Runtime& rt, A, int, L loc) {
    Model& m = model(rt);
    ensure_contacts(rt, m, loc);
    return m.contacts.size() > 0 ? Value::pointer(PtrKind::Contact, 0) : Value::null();
}
Value f_c_next(Runtime& rt, A a, int, L loc) {
    const int c = ptr(rt, a, 0, PtrKind::Contact, "c_next", loc);
    return c + 1 < model(rt).contacts.size() ? Value::pointer(PtrKind::Contact, c + 1) : Value::null();
}
#define CONTACT(fn) const int c = ptr(rt, a, 0, PtrKind::Contact, fn, loc); const ContactSet& C = model(rt).contacts; (void)C
Value f_c_id(Runtime& rt, A a, int, L loc) { CONTACT("c_id"); return Value::integer(C.id[c]); }
Value f_c_b1(Runtime& rt, A a, int, L loc) { CONTACT("c_b1"); return Value::pointer(PtrKind::Block, C.block_a[c]); }
Value f_c_b2(Runtime& rt, A a, int, L loc) { CONTACT("c_b2"); return Value::pointer(PtrKind::Block, C.block_b[c]); }
Value f_c_type(Runtime& rt, A a, int, L loc) {
    CONTACT("c_type");
    const Model& m = model(rt);
    return Value::integer((is_deformable(m, C.block_a[c]) ? 1 : 0) + (is_deformable(m, C.block_b[c]) ? 1 : 0));
}
Value f_c_cx(Runtime& rt, A a, int, L loc) {
    CONTACT("c_cx");
    return C.sub_offset[c] < C.sub_offset[c + 1] ? Value::pointer(PtrKind::Sub, C.sub_offset[c], c) : Value::null();
}
Value f_c_pos(Runtime& rt, A a, int, L loc) { CONTACT("c_pos"); return vec(contact_centroid(model(rt), c)); }
Value f_c_x(Runtime& rt, A a, int, L loc) { CONTACT("c_x"); return num(contact_centroid(model(rt), c).x()); }
Value f_c_y(Runtime& rt, A a, int, L loc) { CONTACT("c_y"); return num(contact_centroid(model(rt), c).y()); }
Value f_c_z(Runtime& rt, A a, int, L loc) { CONTACT("c_z"); return num(contact_centroid(model(rt), c).z()); }
Value f_c_n(Runtime& rt, A a, int, L loc) { CONTACT("c_n"); return vec(C.normal(c)); }
Value f_c_nx(Runtime& rt, A a, int, L loc) { CONTACT("c_nx"); return num(C.normal(c).x()); }
Value f_c_ny(Runtime& rt, A a, int, L loc) { CONTACT("c_ny"); return num(C.normal(c).y()); }
Value f_c_nz(Runtime& rt, A a, int, L loc) { CONTACT("c_nz"); return num(C.normal(c).z()); }
Value f_c_area(Runtime& rt, A a, int, L loc) { CONTACT("c_area"); return num(contact_info(model(rt), c).area); }
Value f_c_jmat(Runtime& rt, A a, int, L loc) { CONTACT("c_jmat"); return Value::integer(C.jmat(c)); }
Value f_c_nforce(Runtime& rt, A a, int, L loc) {
    CONTACT("c_nforce");
    double f = 0;
    const double kn = contact_kn(model(rt), c);
    for (int k = C.sub_offset[c]; k < C.sub_offset[c + 1]; ++k) f += C.sub_sn_for(c, k, kn) * C.sub_area[k];
    return num(f);
}
Value f_c_sforce(Runtime& rt, A a, int, L loc) {
    CONTACT("c_sforce");
    Vec3 f = Vec3::Zero();
    for (int k = C.sub_offset[c]; k < C.sub_offset[c + 1]; ++k) f += C.sub_shear_stress(c, k) * static_cast<double>(C.sub_area[k]);
    return vec(f);
}
Value f_c_near(Runtime& rt, A a, int n, L loc) {
    Model& m = model(rt);
    ensure_contacts(rt, m, loc);
    const int c = find_contact_at(m, point_args(a, n, 0, "c_near", loc));
    return c < 0 ? Value::null() : Value::pointer(PtrKind::Contact, c);
}
// -- fluid flow in the joints --------------------------------------------------------------------
// The flow node nearest the point (its nodes made for the contacts as they stand), or a failure.
int flow_node_arg(Runtime& rt, A a, int n, const char* name, L loc) {
    Model& m = model(rt);
    if (!m.flow.configured) fish_fail(loc, std::string("'") + name + "': fluid flow is not configured ('config flow')");
    ensure_contacts(rt, m, loc);
    flow_sync(m);
    flow_apertures(m);
    const int i = flow_node_at(m, point_args(a, n, 0, name, loc));
    if (i < 0) fish_fail(loc, std::string("'") + name + "': there are no flow nodes (no joints between rigid blocks)");
    return i;
}
Value f_fl_pp(Runtime& rt, A a, int n, L loc) { return num(model(rt).flow.pp[flow_node_arg(rt, a, n, "fl_pp", loc)]); }
Value f_fl_aperture(Runtime& rt, A a, int n, L loc) {
    const int i = flow_node_arg(rt, a, n, "fl_aperture", loc);
    const FlowSet& f = model(rt).flow;
    return num(f.area[i] > 0 ? f.volume[i] / f.area[i] : 0.0);
}
Value f_fl_flow(Runtime& rt, A, int, L loc) {
    if (!model(rt).flow.configured) fish_fail(loc, "'fl_flow': fluid flow is not configured ('config flow')");
    return num(fixed_inflow(model(rt)));
}
Value f_fl_nnode(Runtime& rt, A, int, L loc) {
    Model& m = model(rt);
    if (!m.flow.configured) fish_fail(loc, "'fl_nnode': fluid flow is not configured ('config flow')");
    ensure_contacts(rt, m, loc);
    flow_sync(m);
    return Value::integer(m.flow.n_nodes());
}
Value f_c_extra(Runtime& rt, A a, int, L loc) { CONTACT("c_extra"); return extra_get(rt, 1, C.id[c]); }
void s_c_extra(Runtime& rt, A a, int, const Value& v, L loc) { CONTACT("c_extra"); rt.extras[1][C.id[c]] = v; }

// -- sub-contacts ------------------------------------------------------------------------------------
Value f_cx_next(Runtime& rt, A a, int, L loc) {
    const int s = ptr(rt, a, 0, PtrKind::Sub, "cx_next", loc);
    const ContactSet& C = model(rt).contacts;
    const int c = C.sub_owner(s);
    return s + 1 < C.sub_offset[c + 1] ? Value::pointer(PtrKind::Sub, s + 1, c) : Value::null();
}
#define SUB(fn) const int s = ptr(rt, a, 0, PtrKind::Sub, fn, loc); const ContactSet& C = model(rt).contacts; (void)C
Value f_cx_pos(Runtime& rt, A a, int, L loc) { SUB("cx_pos"); return vec(sub_point(model(rt), C.sub_owner(s), s)); }
Value f_cx_area(Runtime& rt, A a, int, L loc) { SUB("cx_area"); return num(C.sub_area[s]); }
Value f_cx_nforce(Runtime& rt, A a, int, L loc) { SUB("cx_nforce"); return num(sub_normal_stress(model(rt), s) * C.sub_area[s]); }
Value f_cx_sforce(Runtime& rt, A a, int, L loc) { SUB("cx_sforce"); return vec(C.sub_shear_stress(C.sub_owner(s), s) * C.sub_area[s]); }
Value f_cx_xsforce(Runtime& rt, A a, int, L loc) { SUB("cx_xsforce"); return num(C.sub_shear_stress(C.sub_owner(s), s).x() * C.sub_area[s]); }
Value f_cx_ysforce(Runtime& rt, A a, int, L loc) { SUB("cx_ysforce"); return num(C.sub_shear_stress(C.sub_owner(s), s).y() * C.sub_area[s]); }
Value f_cx_zsforce(Runtime& rt, A a, int, L loc) { SUB("cx_zsforce"); return num(C.sub_shear_stress(C.sub_owner(s), s).z() * C.sub_area[s]); }
Value f_cx_nstress(Runtime& rt, A a, int, L loc) { SUB("cx_nstress"); return num(sub_normal_stress(model(rt), s)); }
Value f_cx_sstress(Runtime& rt, A a, int, L loc) { SUB("cx_sstress"); return vec(C.sub_shear_stress(C.sub_owner(s), s)); }
// The closure the joint's spring carries (the dilation included), as print, hist and export give it.
Value f_cx_ndis(Runtime& rt, A a, int, L loc) { SUB("cx_ndis"); return num(sub_closure(model(rt), C.sub_owner(s), s) + C.sub_dilation(s)); }
Value f_cx_sdis(Runtime& rt, A a, int, L loc) { SUB("cx_sdis"); return num(C.sub_shear_disp(C.sub_owner(s), s).norm()); }
Value f_cx_state(Runtime& rt, A a, int, L loc) { SUB("cx_state"); return Value::integer(C.sub_flags(s) & (kSubSlip | kSubOpen | kSubFailed)); }

// -- gridpoints ------------------------------------------------------------------------------------
Value f_gp_head(Runtime& rt, A, int, L) { return model(rt).gridpoints.size() > 0 ? Value::pointer(PtrKind::Gridpoint, 0) : Value::null(); }
Value f_gp_next(Runtime& rt, A a, int, L loc) {
    const int g = ptr(rt, a, 0, PtrKind::Gridpoint, "gp_next", loc);
    const int scope = a[0].scope;
    if (scope < 0) return g + 1 < model(rt).gridpoints.size() ? Value::pointer(PtrKind::Gridpoint, g + 1) : Value::null();
    const auto& lists = rt.block_gridpoints();
    if (scope >= static_cast<int>(lists.size())) return Value::null();
    const auto& l = lists[static_cast<size_t>(scope)];
    const auto it = std::upper_bound(l.begin(), l.end(), g);
    return it == l.end() ? Value::null() : Value::pointer(PtrKind::Gridpoint, *it, scope);
}
#define GP(fn) const int g = ptr(rt, a, 0, PtrKind::Gridpoint, fn, loc); const GridpointSet& G = model(rt).gridpoints; (void)G
Value f_gp_id(Runtime& rt, A a, int, L loc) { GP("gp_id"); return Value::integer(g + 1); }
Value f_gp_x(Runtime& rt, A a, int, L loc) { GP("gp_x"); return num(G.pos[g].x()); }
Value f_gp_y(Runtime& rt, A a, int, L loc) { GP("gp_y"); return num(G.pos[g].y()); }
Value f_gp_z(Runtime& rt, A a, int, L loc) { GP("gp_z"); return num(G.pos[g].z()); }
Value f_gp_pos(Runtime& rt, A a, int, L loc) { GP("gp_pos"); return vec(G.pos[g]); }
Value f_gp_disp(Runtime& rt, A a, int, L loc) { GP("gp_disp"); return vec(G.disp[g]); }
Value f_gp_xdis(Runtime& rt, A a, int, L loc) { GP("gp_xdis"); return num(G.disp[g].x()); }
Value f_gp_ydis(Runtime& rt, A a, int, L loc) { GP("gp_ydis"); return num(G.disp[g].y()); }
Value f_gp_zdis(Runtime& rt, A a, int, L loc) { GP("gp_zdis"); return num(G.disp[g].z()); }
Value f_gp_vel(Runtime& rt, A a, int, L loc) { GP("gp_vel"); return vec(gridpoint_velocity_at_t(model(rt), g)); }
Value f_gp_xvel(Runtime& rt, A a, int, L loc) { GP("gp_xvel"); return num(gridpoint_velocity_at_t(model(rt), g).x()); }
Value f_gp_yvel(Runtime& rt, A a, int, L loc) { GP("gp_yvel"); return num(gridpoint_velocity_at_t(model(rt), g).y()); }
Value f_gp_zvel(Runtime& rt, A a, int, L loc) { GP("gp_zvel"); return num(gridpoint_velocity_at_t(model(rt), g).z()); }
Value f_gp_force(Runtime& rt, A a, int, L loc) { GP("gp_force"); return vec(G.force[g]); }
Value f_gp_xforce(Runtime& rt, A a, int, L loc) { GP("gp_xforce"); return num(G.force[g].x()); }
Value f_gp_yforce(Runtime& rt, A a, int, L loc) { GP("gp_yforce"); return num(G.force[g].y()); }
Value f_gp_zforce(Runtime& rt, A a, int, L loc) { GP("gp_zforce"); return num(G.force[g].z()); }
Value f_gp_mass(Runtime& rt, A a, int, L loc) { GP("gp_mass"); return num(G.mass[g]); }
Value f_gp_near(Runtime& rt, A a, int n, L loc) {
    const int g = find_gridpoint_near(model(rt), point_args(a, n, 0, "gp_near", loc));
    return g < 0 ? Value::null() : Value::pointer(PtrKind::Gridpoint, g);
}
Value f_gp_extra(Runtime& rt, A a, int, L loc) { GP("gp_extra"); return extra_get(rt, 2, g); }
void s_gp_extra(Runtime& rt, A a, int, const Value& v, L loc) { GP("gp_extra"); rt.extras[2][g] = v; }

// -- zones ------------------------------------------------------------------------------------
Value f_zone_head(Runtime& rt, A, int, L) { return model(rt).zones.size() > 0 ? Value::pointer(PtrKind::Zone, 0) : Value::null(); }
Value f_z_next(Runtime& rt, A a, int, L loc) {
    const int z = ptr(rt, a, 0, PtrKind::Zone, "z_next", loc);
    const int scope = a[0].scope;
    if (scope < 0) return z + 1 < model(rt).zones.size() ? Value::pointer(PtrKind::Zone, z + 1) : Value::null();
    const auto& lists = rt.block_zones();
    if (scope >= static_cast<int>(lists.size())) return Value::null();
    const auto& l = lists[static_cast<size_t>(scope)];
    const auto it = std::upper_bound(l.begin(), l.end(), z);
    return it == l.end() ? Value::null() : Value::pointer(PtrKind::Zone, *it, scope);
}
#define ZONE(fn) const int z = ptr(rt, a, 0, PtrKind::Zone, fn, loc); const ZoneSet& Z = model(rt).zones; (void)Z
Value f_z_id(Runtime& rt, A a, int, L loc) { ZONE("z_id"); return Value::integer(z + 1); }
Value f_z_sxx(Runtime& rt, A a, int, L loc) { ZONE("z_sxx"); return num(Z.stress[z][0]); }
Value f_z_syy(Runtime& rt, A a, int, L loc) { ZONE("z_syy"); return num(Z.stress[z][1]); }
Value f_z_szz(Runtime& rt, A a, int, L loc) { ZONE("z_szz"); return num(Z.stress[z][2]); }
Value f_z_sxy(Runtime& rt, A a, int, L loc) { ZONE("z_sxy"); return num(Z.stress[z][3]); }
Value f_z_sxz(Runtime& rt, A a, int, L loc) { ZONE("z_sxz"); return num(Z.stress[z][4]); }
Value f_z_syz(Runtime& rt, A a, int, L loc) { ZONE("z_syz"); return num(Z.stress[z][5]); }
Value principal(Runtime& rt, A a, int which, const char* fn, L loc) {
    ZONE(fn);
    Vec3 p;
    principal_stresses(Z.stress[z], p);
    Vec3 s = p;
    std::sort(s.data(), s.data() + 3);
    return num(s[which]);
}
Value f_z_sig1(Runtime& rt, A a, int, L loc) { return principal(rt, a, 0, "z_sig1", loc); }
Value f_z_sig2(Runtime& rt, A a, int, L loc) { return principal(rt, a, 1, "z_sig2", loc); }
Value f_z_sig3(Runtime& rt, A a, int, L loc) { return principal(rt, a, 2, "z_sig3", loc); }
Value f_z_vol(Runtime& rt, A a, int, L loc) { ZONE("z_vol"); return num(Z.volume[z]); }
Value f_z_pos(Runtime& rt, A a, int, L loc) { ZONE("z_pos"); return vec(zone_centroid(model(rt), z)); }
Value f_z_x(Runtime& rt, A a, int, L loc) { ZONE("z_x"); return num(zone_centroid(model(rt), z).x()); }
Value f_z_y(Runtime& rt, A a, int, L loc) { ZONE("z_y"); return num(zone_centroid(model(rt), z).y()); }
Value f_z_z(Runtime& rt, A a, int, L loc) { ZONE("z_z"); return num(zone_centroid(model(rt), z).z()); }
Value f_z_state(Runtime& rt, A a, int, L loc) { ZONE("z_state"); return Value::integer(Z.state[z]); }
Value f_z_model(Runtime& rt, A a, int, L loc) { ZONE("z_model"); return Value::integer(Z.model[z]); }
Value f_z_block(Runtime& rt, A a, int, L loc) { ZONE("z_block"); return Value::pointer(PtrKind::Block, Z.block[z]); }
Value f_z_gp(Runtime& rt, A a, int, L loc) {
    ZONE("z_gp");
    const long long k = int_arg(a, 1, "z_gp", loc);
    if (k < 1 || k > 4) fish_fail(loc, "'z_gp' takes a corner number 1 to 4, not " + std::to_string(k));
    return Value::pointer(PtrKind::Gridpoint, Z.gp[z][static_cast<size_t>(k - 1)]);
}
Value f_z_near(Runtime& rt, A a, int n, L loc) {
    const int z = find_zone_at(model(rt), point_args(a, n, 0, "z_near", loc));
    return z < 0 ? Value::null() : Value::pointer(PtrKind::Zone, z);
}
Value f_z_extra(Runtime& rt, A a, int, L loc) { ZONE("z_extra"); return extra_get(rt, 3, z); }
void s_z_extra(Runtime& rt, A a, int, const Value& v, L loc) { ZONE("z_extra"); rt.extras[3][z] = v; }

// -- globals ------------------------------------------------------------------------------------
Value f_time(Runtime& rt, A, int, L) { return num(model(rt).time); }
Value f_ncycle(Runtime& rt, A, int, L) { return Value::integer(model(rt).step); }
Value f_dt(Runtime& rt, A, int, L) { return num(model(rt).dt); }
Value f_unbal(Runtime& rt, A, int, L) { return num(max_unbalanced_force(model(rt))); }
Value f_mech_ratio(Runtime& rt, A, int, L) { return num(unbalanced_ratio(model(rt))); }
Value f_nblock(Runtime& rt, A, int, L) { return Value::integer(model(rt).blocks.size()); }
Value f_ncontact(Runtime& rt, A, int, L loc) {
    ensure_contacts(rt, model(rt), loc);
    return Value::integer(model(rt).contacts.size());
}
Value f_nzone(Runtime& rt, A, int, L) { return Value::integer(model(rt).zones.size()); }
Value f_ngp(Runtime& rt, A, int, L) { return Value::integer(model(rt).gridpoints.size()); }
Value f_gravity(Runtime& rt, A, int, L) { return vec(model(rt).gravity); }
Value f_solve_verdict(Runtime& rt, A, int, L) { return Value::string(rt.host.solve_verdict()); }
Value f_fos_f(Runtime& rt, A, int, L) { return num(rt.host.fos_factor()); }

// A term of the energy account (energy.h), J; 0 while it is off.
template <int K>
Value f_energy(Runtime& rt, A, int, L) {
    double v = 0;
    energy_term(model(rt), energy_terms()[K].name, v);
    return num(v);
}

Value f_memory(Runtime&, A, int, L loc) {
    fish_fail(loc, "odec has no memory offsets: imem() and fmem() have nothing to read",
              {"read the quantity through its intrinsic (c_nforce(c), b_x(b), gp_xdis(g), ...: 'help fish')"});
}

} // namespace

namespace {

// -- cables ------------------------------------------------------------------------------------
// A cable by its id (argument 0) and, when `item` is "segment" or "node", one of its segments or
// nodes (argument 1, from 1 at the cable's first end): its index in the cable arrays.
int cable_arg(Runtime& rt, A a, const char* fn, L loc, int& item, const char* kind) {
    const CableSet& cs = model(rt).cables;
    const long long id = int_arg(a, 0, fn, loc);
    const int c = id > 0 && id <= 2000000000 ? cs.index(static_cast<int>(id)) : -1;
    if (c < 0) fish_fail(loc, std::string("'") + fn + "': there is no cable " + std::to_string(id), {"'print cable' lists them"});
    item = -1;
    if (kind) {
        const bool seg = kind[0] == 's';
        const int n = seg ? cs.segments_of(c) : cs.segments_of(c) + 1;
        const long long k = int_arg(a, 1, fn, loc);
        if (k < 1 || k > n) {
            fish_fail(loc, std::string("'") + fn + "': cable " + std::to_string(id) + " has " + std::to_string(n) + " " +
                               kind + "s, numbered from 1");
        }
        item = static_cast<int>(k - 1) + (seg ? cs.first_segment(c) : cs.node_offset[c]);
    }
    return c;
}
Value f_cable_num(Runtime& rt, A, int, L) { return Value::integer(model(rt).cables.size()); }
Value f_cable_id(Runtime& rt, A a, int, L loc) {
    const CableSet& cs = model(rt).cables;
    const long long k = int_arg(a, 0, "cable_id", loc);
    if (k < 1 || k > cs.size()) fish_fail(loc, "'cable_id': there are " + std::to_string(cs.size()) + " cables, numbered from 1 in order");
    return Value::integer(cs.id[static_cast<size_t>(k - 1)]);
}
Value f_cable_nseg(Runtime& rt, A a, int, L loc) {
    int i;
    const int c = cable_arg(rt, a, "cable_nseg", loc, i, nullptr);
    return Value::integer(model(rt).cables.segments_of(c));
}
Value f_cable_force(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_force", loc, i, "segment");
    return num(model(rt).cables.axial[i]);
}
Value f_cable_yield(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_yield", loc, i, "segment");
    const std::uint8_t st = model(rt).cables.seg_state[i];
    return Value::integer((st & kCableYieldTensionNow) ? 1 : (st & kCableYieldCompNow) ? 2 : (st & kCableYieldPast) ? 3 : 0);
}
Value f_cable_grout(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_grout", loc, i, "node");
    return num(model(rt).cables.grout_force[i]);
}
Value f_cable_slip(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_slip", loc, i, "node");
    return num(model(rt).cables.slip[i]);
}
Value f_cable_gstate(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_gstate", loc, i, "node");
    const CableSet& cs = model(rt).cables;
    if (cs.host_block[i] <= 0) return Value::integer(-1);
    return Value::integer((cs.state[i] & kGroutSlipNow) ? 1 : (cs.state[i] & kGroutSlipPast) ? 2 : 0);
}
Value f_cable_pos(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_pos", loc, i, "node");
    return vec(model(rt).cables.pos[i]);
}
Value f_cable_disp(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_disp", loc, i, "node");
    return vec(model(rt).cables.disp[i]);
}
Value f_cable_block(Runtime& rt, A a, int, L loc) {
    int i;
    cable_arg(rt, a, "cable_block", loc, i, "node");
    return Value::integer(model(rt).cables.host_block[i]);
}

// -- liners ------------------------------------------------------------------------------------
// A liner by its id (argument 0) and, when `kind` is "element" or "node", one of its elements or
// nodes (argument 1, from 1): its index in the liner arrays.
int liner_arg(Runtime& rt, A a, const char* fn, L loc, int& item, const char* kind) {
    const LinerSet& ls = model(rt).liners;
    const long long id = int_arg(a, 0, fn, loc);
    const int c = id > 0 && id <= 2000000000 ? ls.index(static_cast<int>(id)) : -1;
    if (c < 0) fish_fail(loc, std::string("'") + fn + "': there is no liner " + std::to_string(id), {"'print liner' lists them"});
    item = -1;
    if (kind) {
        const bool el = kind[0] == 'e';
        const int first = el ? ls.elem_offset[c] : ls.node_offset[c];
        const int n = (el ? ls.elem_offset[c + 1] : ls.node_offset[c + 1]) - first;
        const long long k = int_arg(a, 1, fn, loc);
        if (k < 1 || k > n) {
            fish_fail(loc, std::string("'") + fn + "': liner " + std::to_string(id) + " has " + std::to_string(n) + " " +
                               kind + "s, numbered from 1");
        }
        item = static_cast<int>(k - 1) + first;
    }
    return c;
}
Value f_li_num(Runtime& rt, A, int, L) { return Value::integer(model(rt).liners.size()); }
Value f_li_id(Runtime& rt, A a, int, L loc) {
    const LinerSet& ls = model(rt).liners;
    const long long k = int_arg(a, 0, "li_id", loc);
    if (k < 1 || k > ls.size()) fish_fail(loc, "'li_id': there are " + std::to_string(ls.size()) + " liners, numbered from 1 in order");
    return Value::integer(ls.id[static_cast<size_t>(k - 1)]);
}
Value f_li_nel(Runtime& rt, A a, int, L loc) {
    int i;
    const int c = liner_arg(rt, a, "li_nel", loc, i, nullptr);
    const LinerSet& ls = model(rt).liners;
    return Value::integer(ls.elem_offset[c + 1] - ls.elem_offset[c]);
}
Value f_li_nnode(Runtime& rt, A a, int, L loc) {
    int i;
    const int c = liner_arg(rt, a, "li_nnode", loc, i, nullptr);
    const LinerSet& ls = model(rt).liners;
    return Value::integer(ls.node_offset[c + 1] - ls.node_offset[c]);
}
Value liner_resultant(Runtime& rt, A a, L loc, const char* fn, int which) {
    int e;
    liner_arg(rt, a, fn, loc, e, "element");
    const LinerResultants r = liner_resultants(model(rt).liners, e);
    const double v[6] = {r.nx, r.ny, r.nxy, r.mx, r.my, r.mxy};
    return num(v[which]);
}
Value f_li_nx(Runtime& rt, A a, int, L loc) { return liner_resultant(rt, a, loc, "li_nx", 0); }
Value f_li_ny(Runtime& rt, A a, int, L loc) { return liner_resultant(rt, a, loc, "li_ny", 1); }
Value f_li_nxy(Runtime& rt, A a, int, L loc) { return liner_resultant(rt, a, loc, "li_nxy", 2); }
Value f_li_mx(Runtime& rt, A a, int, L loc) { return liner_resultant(rt, a, loc, "li_mx", 3); }
Value f_li_my(Runtime& rt, A a, int, L loc) { return liner_resultant(rt, a, loc, "li_my", 4); }
Value f_li_mxy(Runtime& rt, A a, int, L loc) { return liner_resultant(rt, a, loc, "li_mxy", 5); }
Value f_li_centroid(Runtime& rt, A a, int, L loc) {
    int e;
    liner_arg(rt, a, "li_centroid", loc, e, "element");
    return vec(liner_resultants(model(rt).liners, e).centroid);
}
Value f_li_pos(Runtime& rt, A a, int, L loc) {
    int i;
    liner_arg(rt, a, "li_pos", loc, i, "node");
    return vec(model(rt).liners.pos[i]);
}
Value f_li_disp(Runtime& rt, A a, int, L loc) {
    int i;
    liner_arg(rt, a, "li_disp", loc, i, "node");
    return vec(model(rt).liners.disp[i]);
}
Value f_li_bond_n(Runtime& rt, A a, int, L loc) {
    int i;
    liner_arg(rt, a, "li_bond_n", loc, i, "node");
    return num(model(rt).liners.bond_n[i]);
}
Value f_li_bond_s(Runtime& rt, A a, int, L loc) {
    int i;
    liner_arg(rt, a, "li_bond_s", loc, i, "node");
    return num(model(rt).liners.bond_s[i].norm());
}
Value f_li_bstate(Runtime& rt, A a, int, L loc) {
    int i;
    liner_arg(rt, a, "li_bstate", loc, i, "node");
    const LinerSet& ls = model(rt).liners;
    if (ls.host_block[i] <= 0) return Value::integer(-1);
    return Value::integer(ls.state[i] & (kBondSlipNow | kBondBrokenTension | kBondBrokenShear | kBondOpen));
}

} // namespace

const std::vector<Intrinsic>& model_intrinsics() {
    static const std::vector<Intrinsic> t = {
        {"block_head", 0, 0, "", "the first block (0 when there are none)", "block", f_block_head, nullptr},
        {"b_next", 1, 1, "b", "the block after b (0 after the last)", "block", f_b_next, nullptr},
        {"b_id", 1, 1, "b", "the block's id, as print and range id show it", "block", f_b_id, nullptr},
        {"b_x", 1, 1, "b", "x of the block's centroid, m", "block", f_b_x, nullptr},
        {"b_y", 1, 1, "b", "y of the block's centroid, m", "block", f_b_y, nullptr},
        {"b_z", 1, 1, "b", "z of the block's centroid, m", "block", f_b_z, nullptr},
        {"b_pos", 1, 1, "b", "the block's centroid (vector), m", "block", f_b_pos, nullptr},
        {"b_vol", 1, 1, "b", "the block's volume, m^3", "block", f_b_vol, nullptr},
        {"b_mass", 1, 1, "b", "the block's mass, kg", "block", f_b_mass, nullptr},
        {"b_region", 1, 1, "b", "the block's region number", "block", f_b_region, nullptr},
        {"b_mat", 1, 1, "b", "the block's material number", "block", f_b_mat, nullptr},
        {"b_fix", 1, 1, "b", "1 when the block is fixed, else 0", "block", f_b_fix, nullptr},
        {"b_type", 1, 1, "b", "1 rigid, 2 deformable (zoned)", "block", f_b_type, nullptr},
        {"b_clump", 1, 1, "b", "the clump the block is a piece of (a solid that is not convex, one rigid body), named "
                               "by the id of its first piece; 0 for a block alone", "block", f_b_clump, nullptr},
        {"b_vel", 1, 1, "b", "velocity of the centroid (vector), m/s", "block", f_b_vel, nullptr},
        {"b_xvel", 1, 1, "b", "x velocity of the centroid, m/s (assignable; the piece of a clump takes its clump along)", "block", f_b_xvel, s_b_xvel},
        {"b_yvel", 1, 1, "b", "y velocity of the centroid, m/s (assignable)", "block", f_b_yvel, s_b_yvel},
        {"b_zvel", 1, 1, "b", "z velocity of the centroid, m/s (assignable)", "block", f_b_zvel, s_b_zvel},
        {"b_disp", 1, 1, "b", "displacement of the centroid since 'reset disp' (vector), m", "block", f_b_disp, nullptr},
        {"b_xdis", 1, 1, "b", "x displacement of the centroid, m", "block", f_b_xdis, nullptr},
        {"b_ydis", 1, 1, "b", "y displacement of the centroid, m", "block", f_b_ydis, nullptr},
        {"b_zdis", 1, 1, "b", "z displacement of the centroid, m", "block", f_b_zdis, nullptr},
        {"b_rot", 1, 1, "b", "the block's turn since 'reset disp' as a rotation vector: its axis (world axes, "
                             "right-hand rule) times its angle, rad, 0 to pi; exact for any rotation (0 for a "
                             "deformable block)", "block", f_b_rot, nullptr},
        {"b_xrot", 1, 1, "b", "x component of b_rot, rad", "block", f_b_xrot, nullptr},
        {"b_yrot", 1, 1, "b", "y component of b_rot, rad", "block", f_b_yrot, nullptr},
        {"b_zrot", 1, 1, "b", "z component of b_rot, rad", "block", f_b_zrot, nullptr},
        {"b_euler", 1, 1, "b", "the block's turn since 'reset disp' as angles (a,b,c), degrees, X-Y-Z convention: "
                               "a about x, then b about the turned y, then c about the twice-turned z (R = Rx(a) "
                               "Ry(b) Rz(c); equally c about the world z, then b about y, then a about x); a and "
                               "c -180 to 180, b -90 to 90 (vector)", "block", f_b_euler, nullptr},
        {"b_rvel", 1, 1, "b", "the block's spin, its angular velocity about the world axes (vector), rad/s",
         "block", f_b_rvel, nullptr},
        {"b_xrvel", 1, 1, "b", "spin about the x axis, rad/s, right-hand rule (assignable, rigid blocks; a clump turns with its piece)", "block", f_b_xrvel, s_b_xrvel},
        {"b_yrvel", 1, 1, "b", "spin about the y axis, rad/s (assignable, rigid blocks)", "block", f_b_yrvel, s_b_yrvel},
        {"b_zrvel", 1, 1, "b", "spin about the z axis, rad/s (assignable, rigid blocks)", "block", f_b_zrvel, s_b_zrvel},
        {"b_force", 1, 1, "b", "unbalanced force on the block in the last step (vector), N", "block", f_b_force, nullptr},
        {"b_xforce", 1, 1, "b", "x unbalanced force on the block, N", "block", f_b_xforce, nullptr},
        {"b_yforce", 1, 1, "b", "y unbalanced force on the block, N", "block", f_b_yforce, nullptr},
        {"b_zforce", 1, 1, "b", "z unbalanced force on the block, N", "block", f_b_zforce, nullptr},
        {"b_zone", 1, 1, "b", "the block's first zone (0 for a rigid block); z_next walks the block's zones", "block", f_b_zone, nullptr},
        {"b_gp", 1, 1, "b", "the block's first gridpoint (0 for a rigid block); gp_next walks the block's gridpoints", "block", f_b_gp, nullptr},
        {"b_near", 1, 3, "x,y,z | v", "the block containing the point, or the nearest", "block", f_b_near, nullptr},
        {"b_extra", 1, 1, "b", "a value the script stored with the block (assignable; 0 until then)", "block", f_b_extra, s_b_extra},
        {"contact_head", 0, 0, "", "the first contact (0 when there are none); contacts are found first if the model changed", "contact", f_contact_head, nullptr},
        {"c_next", 1, 1, "c", "the contact after c (0 after the last)", "contact", f_c_next, nullptr},
        {"c_id", 1, 1, "c", "the contact's id, as print contact shows it", "contact", f_c_id, nullptr},
        {"c_b1", 1, 1, "c", "the contact's first block", "contact", f_c_b1, nullptr},
        {"c_b2", 1, 1, "c", "the contact's second block (the normal points from b1 to b2)", "contact", f_c_b2, nullptr},
        {"c_type", 1, 1, "c", "0 between rigid blocks, 1 rigid and deformable, 2 between deformable blocks", "contact", f_c_type, nullptr},
        {"c_cx", 1, 1, "c", "the contact's first sub-contact; cx_next walks them", "contact", f_c_cx, nullptr},
        {"c_pos", 1, 1, "c", "area centroid of the contact (vector), m", "contact", f_c_pos, nullptr},
        {"c_x", 1, 1, "c", "x of the contact's centroid, m", "contact", f_c_x, nullptr},
        {"c_y", 1, 1, "c", "y of the contact's centroid, m", "contact", f_c_y, nullptr},
        {"c_z", 1, 1, "c", "z of the contact's centroid, m", "contact", f_c_z, nullptr},
        {"c_n", 1, 1, "c", "unit normal of the common plane, from b1 to b2 (vector)", "contact", f_c_n, nullptr},
        {"c_nx", 1, 1, "c", "x component of the contact's unit normal", "contact", f_c_nx, nullptr},
        {"c_ny", 1, 1, "c", "y component of the contact's unit normal", "contact", f_c_ny, nullptr},
        {"c_nz", 1, 1, "c", "z component of the contact's unit normal", "contact", f_c_nz, nullptr},
        {"c_area", 1, 1, "c", "area where the contact's blocks touch now, m^2 (an edge pressing into a face: the strip its penetration makes; cx_area: the sub-contacts' spring areas)", "contact", f_c_area, nullptr},
        {"c_jmat", 1, 1, "c", "the contact's joint material number", "contact", f_c_jmat, nullptr},
        {"c_nforce", 1, 1, "c", "normal force, compression positive, N", "contact", f_c_nforce, nullptr},
        {"c_sforce", 1, 1, "c", "shear force on b2 (vector), N", "contact", f_c_sforce, nullptr},
        {"c_near", 1, 3, "x,y,z | v", "the contact nearest the point", "contact", f_c_near, nullptr},
        {"c_extra", 1, 1, "c", "a value the script stored with the contact (assignable; 0 until then)", "contact", f_c_extra, s_c_extra},
        {"cx_next", 1, 1, "s", "the next sub-contact of the same contact (0 after the last)", "contact", f_cx_next, nullptr},
        {"cx_pos", 1, 1, "s", "position of the sub-contact (vector), m", "contact", f_cx_pos, nullptr},
        {"cx_area", 1, 1, "s", "spring area of the sub-contact, m^2: its share of the contact polygon, or, for a corner of a face tilted to the plane pressing into the other block, its own share of its faces (chiefly of the face nearest the plane)", "contact", f_cx_area, nullptr},
        {"cx_nforce", 1, 1, "s", "normal force, compression positive, N", "contact", f_cx_nforce, nullptr},
        {"cx_sforce", 1, 1, "s", "shear force on the second block (vector), N", "contact", f_cx_sforce, nullptr},
        {"cx_xsforce", 1, 1, "s", "x component of the shear force, N", "contact", f_cx_xsforce, nullptr},
        {"cx_ysforce", 1, 1, "s", "y component of the shear force, N", "contact", f_cx_ysforce, nullptr},
        {"cx_zsforce", 1, 1, "s", "z component of the shear force, N", "contact", f_cx_zsforce, nullptr},
        {"cx_nstress", 1, 1, "s", "normal stress, compression positive, Pa", "contact", f_cx_nstress, nullptr},
        {"cx_sstress", 1, 1, "s", "shear stress on the second block (vector), Pa", "contact", f_cx_sstress, nullptr},
        {"cx_ndis", 1, 1, "s", "normal closure, compression positive, m", "contact", f_cx_ndis, nullptr},
        {"cx_sdis", 1, 1, "s", "magnitude of the shear displacement, m", "contact", f_cx_sdis, nullptr},
        {"cx_state", 1, 1, "s", "state bits: 1 slipping, 2 open, 4 failed (0 elastic)", "contact", f_cx_state, nullptr},
        {"fl_pp", 1, 3, "x,y,z | v", "pore pressure of the flow node nearest the point, Pa", "flow", f_fl_pp, nullptr},
        {"fl_aperture", 1, 3, "x,y,z | v", "hydraulic aperture of the flow node nearest the point (mean over its area), m", "flow", f_fl_aperture, nullptr},
        {"fl_flow", 0, 0, "", "flow the fixed-pressure boundaries feed into the joints, m^3/s", "flow", f_fl_flow, nullptr},
        {"fl_nnode", 0, 0, "", "the number of flow nodes", "flow", f_fl_nnode, nullptr},
        {"cable_num", 0, 0, "", "the number of cables", "cable", f_cable_num, nullptr},
        {"cable_id", 1, 1, "k", "the id of the k-th cable (from 1, in order)", "cable", f_cable_id, nullptr},
        {"cable_nseg", 1, 1, "id", "the number of segments of cable id (it has one node more)", "cable", f_cable_nseg, nullptr},
        {"cable_force", 2, 2, "id,k", "axial force of segment k of cable id, N (tension positive)", "cable", f_cable_force, nullptr},
        {"cable_yield", 2, 2, "id,k", "state of segment k: 0 elastic, 1 yielding in tension, 2 in compression, 3 yielded earlier", "cable", f_cable_yield, nullptr},
        {"cable_grout", 2, 2, "id,k", "grout force on node k of cable id, along the cable from its first node to its last, N", "cable", f_cable_grout, nullptr},
        {"cable_slip", 2, 2, "id,k", "plastic slip of the grout at node k, along the cable, m", "cable", f_cable_slip, nullptr},
        {"cable_gstate", 2, 2, "id,k", "grout at node k: 0 elastic, 1 slipping, 2 slipped earlier, -1 no grout (in no block)", "cable", f_cable_gstate, nullptr},
        {"cable_pos", 2, 2, "id,k", "position of node k of cable id (vector), m", "cable", f_cable_pos, nullptr},
        {"cable_disp", 2, 2, "id,k", "displacement of node k since it was made or 'reset disp' (vector), m", "cable", f_cable_disp, nullptr},
        {"cable_block", 2, 2, "id,k", "id of the block node k is grouted into (0: none)", "cable", f_cable_block, nullptr},
        {"li_num", 0, 0, "", "the number of liners", "liner", f_li_num, nullptr},
        {"li_id", 1, 1, "k", "the id of the k-th liner (from 1, in order)", "liner", f_li_id, nullptr},
        {"li_nel", 1, 1, "id", "the number of elements of liner id", "liner", f_li_nel, nullptr},
        {"li_nnode", 1, 1, "id", "the number of nodes of liner id", "liner", f_li_nnode, nullptr},
        {"li_nx", 2, 2, "id,k", "membrane force n_x of element k of liner id, N/m (tension positive; x across the liner's axis)", "liner", f_li_nx, nullptr},
        {"li_ny", 2, 2, "id,k", "membrane force n_y of element k, N/m (tension positive; y along the axis)", "liner", f_li_ny, nullptr},
        {"li_nxy", 2, 2, "id,k", "membrane shear force n_xy of element k, N/m", "liner", f_li_nxy, nullptr},
        {"li_mx", 2, 2, "id,k", "bending moment m_x of element k, N m/m (positive: the face on the void's side in tension)", "liner", f_li_mx, nullptr},
        {"li_my", 2, 2, "id,k", "bending moment m_y of element k, N m/m (same sign convention)", "liner", f_li_my, nullptr},
        {"li_mxy", 2, 2, "id,k", "twisting moment m_xy of element k, N m/m", "liner", f_li_mxy, nullptr},
        {"li_centroid", 2, 2, "id,k", "centroid of element k of liner id (vector), m", "liner", f_li_centroid, nullptr},
        {"li_pos", 2, 2, "id,k", "position of node k of liner id (vector), m", "liner", f_li_pos, nullptr},
        {"li_disp", 2, 2, "id,k", "displacement of node k since the liner was made or 'reset disp' (vector), m", "liner", f_li_disp, nullptr},
        {"li_bond_n", 2, 2, "id,k", "normal force of the bond on node k, N (compression positive)", "liner", f_li_bond_n, nullptr},
        {"li_bond_s", 2, 2, "id,k", "magnitude of the bond's shear force on node k, N", "liner", f_li_bond_s, nullptr},
        {"li_bstate", 2, 2, "id,k", "bond at node k: bits 1 slipping, 2 broken in tension, 4 broken in shear, 8 open (0 intact); -1 no rock under it", "liner", f_li_bstate, nullptr},
        {"gp_head", 0, 0, "", "the first gridpoint of the model (0 when none)", "gridpoint", f_gp_head, nullptr},
        {"gp_next", 1, 1, "g", "the next gridpoint: of the same block after b_gp, of the model after gp_head", "gridpoint", f_gp_next, nullptr},
        {"gp_id", 1, 1, "g", "the gridpoint's number, as print gp shows it", "gridpoint", f_gp_id, nullptr},
        {"gp_x", 1, 1, "g", "x of the gridpoint, m", "gridpoint", f_gp_x, nullptr},
        {"gp_y", 1, 1, "g", "y of the gridpoint, m", "gridpoint", f_gp_y, nullptr},
        {"gp_z", 1, 1, "g", "z of the gridpoint, m", "gridpoint", f_gp_z, nullptr},
        {"gp_pos", 1, 1, "g", "position of the gridpoint (vector), m", "gridpoint", f_gp_pos, nullptr},
        {"gp_disp", 1, 1, "g", "displacement since 'reset disp' (vector), m", "gridpoint", f_gp_disp, nullptr},
        {"gp_xdis", 1, 1, "g", "x displacement, m", "gridpoint", f_gp_xdis, nullptr},
        {"gp_ydis", 1, 1, "g", "y displacement, m", "gridpoint", f_gp_ydis, nullptr},
        {"gp_zdis", 1, 1, "g", "z displacement, m", "gridpoint", f_gp_zdis, nullptr},
        {"gp_vel", 1, 1, "g", "velocity (vector), m/s", "gridpoint", f_gp_vel, nullptr},
        {"gp_xvel", 1, 1, "g", "x velocity, m/s", "gridpoint", f_gp_xvel, nullptr},
        {"gp_yvel", 1, 1, "g", "y velocity, m/s", "gridpoint", f_gp_yvel, nullptr},
        {"gp_zvel", 1, 1, "g", "z velocity, m/s", "gridpoint", f_gp_zvel, nullptr},
        {"gp_force", 1, 1, "g", "unbalanced force (vector), N", "gridpoint", f_gp_force, nullptr},
        {"gp_xforce", 1, 1, "g", "x unbalanced force, N", "gridpoint", f_gp_xforce, nullptr},
        {"gp_yforce", 1, 1, "g", "y unbalanced force, N", "gridpoint", f_gp_yforce, nullptr},
        {"gp_zforce", 1, 1, "g", "z unbalanced force, N", "gridpoint", f_gp_zforce, nullptr},
        {"gp_mass", 1, 1, "g", "mass of the gridpoint, kg", "gridpoint", f_gp_mass, nullptr},
        {"gp_near", 1, 3, "x,y,z | v", "the gridpoint nearest the point (0 when there are none)", "gridpoint", f_gp_near, nullptr},
        {"gp_extra", 1, 1, "g", "a value the script stored with the gridpoint (assignable)", "gridpoint", f_gp_extra, s_gp_extra},
        {"zone_head", 0, 0, "", "the first zone of the model (0 when none)", "zone", f_zone_head, nullptr},
        {"z_next", 1, 1, "z", "the next zone: of the same block after b_zone, of the model after zone_head", "zone", f_z_next, nullptr},
        {"z_id", 1, 1, "z", "the zone's number, as print zone shows it", "zone", f_z_id, nullptr},
        {"z_sxx", 1, 1, "z", "stress xx, Pa, tension positive", "zone", f_z_sxx, nullptr},
        {"z_syy", 1, 1, "z", "stress yy, Pa, tension positive", "zone", f_z_syy, nullptr},
        {"z_szz", 1, 1, "z", "stress zz, Pa, tension positive", "zone", f_z_szz, nullptr},
        {"z_sxy", 1, 1, "z", "stress xy, Pa", "zone", f_z_sxy, nullptr},
        {"z_sxz", 1, 1, "z", "stress xz, Pa", "zone", f_z_sxz, nullptr},
        {"z_syz", 1, 1, "z", "stress yz, Pa", "zone", f_z_syz, nullptr},
        {"z_sig1", 1, 1, "z", "smallest (most compressive) principal stress, Pa, tension positive", "zone", f_z_sig1, nullptr},
        {"z_sig2", 1, 1, "z", "intermediate principal stress, Pa", "zone", f_z_sig2, nullptr},
        {"z_sig3", 1, 1, "z", "largest principal stress, Pa, tension positive", "zone", f_z_sig3, nullptr},
        {"z_vol", 1, 1, "z", "volume of the zone, m^3", "zone", f_z_vol, nullptr},
        {"z_pos", 1, 1, "z", "centroid of the zone (vector), m", "zone", f_z_pos, nullptr},
        {"z_x", 1, 1, "z", "x of the zone's centroid, m", "zone", f_z_x, nullptr},
        {"z_y", 1, 1, "z", "y of the zone's centroid, m", "zone", f_z_y, nullptr},
        {"z_z", 1, 1, "z", "z of the zone's centroid, m", "zone", f_z_z, nullptr},
        {"z_state", 1, 1, "z", "plastic state bits: 1 shear now, 2 tension now, 4 shear past, 8 tension past", "zone", f_z_state, nullptr},
        {"z_model", 1, 1, "z", "zone model: 0 null, 1 elastic, 2 Mohr-Coulomb", "zone", f_z_model, nullptr},
        {"z_block", 1, 1, "z", "the block the zone belongs to", "zone", f_z_block, nullptr},
        {"z_gp", 2, 2, "z,i", "corner i (1 to 4) of the zone: a gridpoint", "zone", f_z_gp, nullptr},
        {"z_near", 1, 3, "x,y,z | v", "the zone containing the point, or the nearest", "zone", f_z_near, nullptr},
        {"z_extra", 1, 1, "z", "a value the script stored with the zone (assignable)", "zone", f_z_extra, s_z_extra},
        {"time", 0, 0, "", "model time, s", "model", f_time, nullptr},
        {"ncycle", 0, 0, "", "steps taken since 'new'", "model", f_ncycle, nullptr},
        {"step", 0, 0, "", "steps taken since 'new' (as ncycle)", "model", f_ncycle, nullptr},
        {"dt", 0, 0, "", "the timestep in use, s", "model", f_dt, nullptr},
        {"unbal", 0, 0, "", "largest unbalanced force, N", "model", f_unbal, nullptr},
        {"mech_ratio", 0, 0, "", "mean unbalanced-force ratio", "model", f_mech_ratio, nullptr},
        {"nblock", 0, 0, "", "number of blocks", "model", f_nblock, nullptr},
        {"ncontact", 0, 0, "", "number of contacts", "model", f_ncontact, nullptr},
        {"nzone", 0, 0, "", "number of zones", "model", f_nzone, nullptr},
        {"ngp", 0, 0, "", "number of gridpoints", "model", f_ngp, nullptr},
        {"gravity", 0, 0, "", "gravity (vector), m/s^2", "model", f_gravity, nullptr},
        {"solve_verdict", 0, 0, "", "how the last solve ended: 'equilibrium', 'mechanism', 'not converged' or "
                                    "'interrupted' ('' before any solve since 'new' or 'restore')", "model",
         f_solve_verdict, nullptr},
        {"fos_f", 0, 0, "", "the factor of safety the last 'solve fos' found (the middle of its final bracket); 0 "
                            "before any since 'new' or 'restore', or when the search ended without one", "model",
         f_fos_f, nullptr},
        {"energy_kinetic", 0, 0, "", "kinetic energy of the free blocks and gridpoints (translation and rotation, real masses), J ('set energy on'; 0 while the account is off)", "model", f_energy<0>, nullptr},
        {"energy_jstrain", 0, 0, "", "strain energy stored in the joints, J", "model", f_energy<1>, nullptr},
        {"energy_zstrain", 0, 0, "", "elastic strain energy stored in the zones, J", "model", f_energy<2>, nullptr},
        {"energy_gravity", 0, 0, "", "work done by gravity since the energy account began, J", "model", f_energy<3>, nullptr},
        {"energy_load", 0, 0, "", "work done by the applied loads since the energy account began, J", "model", f_energy<4>, nullptr},
        {"energy_velocity", 0, 0, "", "work done by the prescribed velocities since the energy account began, J", "model", f_energy<5>, nullptr},
        {"energy_boundary", 0, 0, "", "work done at the boundary (load + velocity) since the energy account began, J", "model", f_energy<6>, nullptr},
        {"energy_damping", 0, 0, "", "energy dissipated by damping since the energy account began, J", "model", f_energy<7>, nullptr},
        {"energy_slip", 0, 0, "", "energy dissipated in the joints since the energy account began, J", "model", f_energy<8>, nullptr},
        {"energy_plastic", 0, 0, "", "energy dissipated by zone plasticity since the energy account began, J", "model", f_energy<9>, nullptr},
        {"energy_initial", 0, 0, "", "stored energy when the energy account began, J", "model", f_energy<10>, nullptr},
        {"energy_given", 0, 0, "", "stored energy changed by commands between steps since the energy account began, J", "model", f_energy<11>, nullptr},
        {"energy_error", 0, 0, "", "error of the energy balance: stored + dissipated - (initial + given + work), J", "model", f_energy<12>, nullptr},
        {"imem", 1, 1, "i", "(classic) integer memory at an offset: odec has none, the call stops with the "
                            "intrinsic to use instead", "model", f_memory, nullptr},
        {"fmem", 1, 1, "i", "(classic) real memory at an offset: odec has none, the call stops with the "
                            "intrinsic to use instead", "model", f_memory, nullptr},
    };
    return t;
}

} // namespace odec::fish
