// Every FISH intrinsic, one case each: an expression and the value it must give on a model whose
// answer is known (a block resting on a fixed base under a tilted gravity; a zoned cube under a
// stated in-situ stress). A last test checks that no declared intrinsic is left without a case.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "fish/intrinsics.h"
#include "fish/runtime.h"
#include "engine/energy.h"
#include "test_util.h"

using odec::test::Session;

namespace {

struct Case {
    const char* intrinsic; // the intrinsic the case is for
    const char* expr;      // FISH expression, evaluated inside a function
    double want;           // expected number (ignored when text is set)
    double tol;            // absolute tolerance
    const char* text;      // expected string, or nullptr
};

// Evaluates every case's expression inside one function `check` (with `prelude` first) and
// compares each result.
void run_cases(Session& s, const std::string& prelude, const std::vector<Case>& cases) {
    std::string def = "def check\n" + prelude;
    for (size_t k = 0; k < cases.size(); ++k) def += "  r_" + std::to_string(k) + " = " + cases[k].expr + "\n";
    def += "end\n@check\n";
    ASSERT_TRUE(s.run(def)) << s.error();
    for (size_t k = 0; k < cases.size(); ++k) {
        const Case& c = cases[k];
        const odec::fish::Symbol* sym = s.interp.fish().find("r_" + std::to_string(k));
        ASSERT_NE(sym, nullptr);
        const odec::fish::Value& v = sym->value;
        if (c.text) {
            EXPECT_EQ(odec::fish::to_text(v), c.text) << c.intrinsic << ": " << c.expr;
            continue;
        }
        const bool numeric = v.is_number() || v.type == odec::fish::Type::Bool;
        ASSERT_TRUE(numeric) << c.intrinsic << ": " << c.expr << " gave " << odec::fish::to_text(v);
        EXPECT_NEAR(v.number(), c.want, c.tol) << c.intrinsic << ": " << c.expr;
    }
}

const double kPi = 3.14159265358979323846;

// A 1 m cube (2000 kg) on a fixed 2 x 2 x 1 m base, gravity (1, 0, -10): the contact carries
// 20,000 N normal and 2,000 N of shear; joint stiffness 1e10 Pa/m closes it by 2e-6 m.
const char* kRestingBlock = "poly brick 0 2 0 2 -1 0\npoly brick 0.5 1.5 0.5 1.5 0 1\n"
                            "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\n"
                            "grav 1 0 -10\nfix range z -1 0\nsolve ratio 1e-7\n";

// Sums over the sub-contacts of the one contact, walked with cx_next.
const char* kSubContactSums = "  top = b_near(1, 1, 0.5)\n  base = b_near(1, 1, -0.5)\n  c = contact_head\n"
                              "  sgn2 = sgn(b_z(c_b2(c)) - b_z(c_b1(c)))\n"
                              "  n = 0\n  sa = 0\n  sf = 0\n  ss = 0\n  sx = 0\n  sy = 0\n  sz = 0\n  sv = 0\n"
                              "  sd = 0\n  sdis = 0\n  sst = 0\n  zz = 0\n  sst2 = 0\n"
                              "  s = c_cx(c)\n"
                              "  loop while s # 0\n"
                              "    n = n + 1\n    sa = sa + cx_area(s)\n    sf = sf + cx_nforce(s)\n"
                              "    ss = ss + cx_nstress(s) * cx_area(s)\n"
                              "    sx = sx + cx_xsforce(s)\n    sy = sy + cx_ysforce(s)\n    sz = sz + cx_zsforce(s)\n"
                              "    sv = sv + xcomp(cx_sforce(s))\n    sst2 = sst2 + xcomp(cx_sstress(s)) * cx_area(s)\n"
                              "    sd = sd + cx_ndis(s) * cx_area(s)\n    sdis = sdis + cx_sdis(s) * cx_area(s)\n"
                              "    sst = sst + cx_state(s)\n    zz = zz + abs(zcomp(cx_pos(s)))\n"
                              "    s = cx_next(s)\n"
                              "  endloop\n";

std::vector<Case> math_cases() {
    return {
        {"abs", "abs(-2.5)", 2.5, 0, nullptr},
        {"sqrt", "sqrt(16)", 4, 0, nullptr},
        {"sin", "sin(pi / 6)", 0.5, 1e-15, nullptr},
        {"cos", "cos(pi / 3)", 0.5, 1e-15, nullptr},
        {"tan", "tan(pi / 4)", 1, 1e-15, nullptr},
        {"asin", "asin(1)", kPi / 2, 1e-15, nullptr},
        {"acos", "acos(0)", kPi / 2, 1e-15, nullptr},
        {"atan", "atan(1)", kPi / 4, 1e-15, nullptr},
        {"atan2", "atan2(1, -1)", 3 * kPi / 4, 1e-15, nullptr},
        {"exp", "exp(1)", std::exp(1.0), 1e-15, nullptr},
        {"ln", "ln(exp(2))", 2, 1e-15, nullptr},
        {"log", "log(1000)", 3, 1e-15, nullptr},
        {"sgn", "sgn(-3) * 10 + sgn(0)", -10, 0, nullptr},
        {"min", "min(3, 1.5, 2)", 1.5, 0, nullptr},
        {"max", "max(3, 1.5, 4, 2)", 4, 0, nullptr},
        {"pi", "pi", kPi, 0, nullptr},
        {"degrad", "degrad * 180", kPi, 1e-15, nullptr},
        {"float", "float('2.5') + float(1) / 4", 2.75, 0, nullptr},
        {"int", "int(-2.7) * 10 + int(2.7)", -18, 0, nullptr},
        {"round", "round(2.4) * 10 + round(-2.6)", 17, 0, nullptr},
        {"urand", "urand", 0.5, 0.5, nullptr},
        {"grand", "abs(grand) < 10", 1, 0, nullptr},
        {"string", "string(2.5) + string(3)", 0, 0, "2.53"},
        {"strlen", "strlen('rock')", 4, 0, nullptr},
        {"substr", "substr('joint set', 3, 4)", 0, 0, "int "},
        {"type", "type(1) * 1000 + type(1.0) * 100 + type('a') * 10 + type(vector(1,2,3))", 1235, 0, nullptr},
        {"vector", "vector(1, 2, 3)", 0, 0, "(1.0,2.0,3.0)"},
        {"mag", "mag(vector(3, 4, 12))", 13, 1e-15, nullptr},
        {"unit", "xcomp(unit(vector(3, 0, 4)))", 0.6, 1e-15, nullptr},
        {"dot", "dot(vector(1, 2, 3), vector(3, 2, 1))", 10, 0, nullptr},
        {"cross", "cross(vector(1, 0, 0), vector(0, 1, 0))", 0, 0, "(0.0,0.0,1.0)"},
        {"xcomp", "xcomp(vector(7, 8, 9))", 7, 0, nullptr},
        {"ycomp", "ycomp(vector(7, 8, 9))", 8, 0, nullptr},
        {"zcomp", "zcomp(vector(7, 8, 9))", 9, 0, nullptr},
    };
}

std::vector<Case> block_cases() {
    return {
        {"block_head", "b_id(block_head)", 1, 0, nullptr},
        {"b_next", "b_id(b_next(block_head)) * 10 + b_next(b_next(block_head))", 20, 0, nullptr},
        {"b_id", "b_id(top)", 2, 0, nullptr},
        {"b_x", "b_x(top)", 1, 1e-5, nullptr},
        {"b_y", "b_y(top)", 1, 1e-9, nullptr},
        {"b_z", "b_z(top)", 0.5, 1e-5, nullptr},
        {"b_pos", "zcomp(b_pos(base))", -0.5, 1e-12, nullptr},
        {"b_vol", "b_vol(top) + b_vol(base) * 10", 41, 1e-12, nullptr},
        {"b_mass", "b_mass(top)", 2000, 1e-9, nullptr},
        {"b_region", "b_region(top)", 0, 0, nullptr},
        {"b_mat", "b_mat(top)", 1, 0, nullptr},
        {"b_fix", "b_fix(base) * 10 + b_fix(top)", 10, 0, nullptr},
        {"b_type", "b_type(top)", 1, 0, nullptr},
        {"b_clump", "b_clump(top)", 0, 0, nullptr}, // a block alone (clump_test.cpp: one of a clump)
        {"b_xdis", "b_xdis(top)", 4e-7, 1e-7, nullptr},
        {"b_ydis", "b_ydis(top)", 0, 1e-12, nullptr},
        {"b_zdis", "b_zdis(top)", -2e-6, 1e-8, nullptr},
        {"b_disp", "zcomp(b_disp(top))", -2e-6, 1e-8, nullptr},
        {"b_force", "mag(b_force(top))", 0, 20, nullptr},
        {"b_xforce", "abs(b_xforce(top))", 0, 20, nullptr},
        {"b_yforce", "abs(b_yforce(top))", 0, 20, nullptr},
        {"b_zforce", "abs(b_zforce(top))", 0, 20, nullptr},
        {"b_zone", "b_zone(top)", 0, 0, nullptr},
        {"b_gp", "b_gp(top)", 0, 0, nullptr},
        {"b_near", "b_id(b_near(vector(1, 1, -0.9)))", 1, 0, nullptr},
        {"contact_head", "c_id(contact_head)", 1, 0, nullptr},
        {"c_next", "c_next(contact_head)", 0, 0, nullptr},
        {"c_id", "c_id(c)", 1, 0, nullptr},
        {"c_b1", "b_id(c_b1(c)) + b_id(c_b2(c))", 3, 0, nullptr},
        {"c_b2", "b_z(c_b2(c)) # b_z(c_b1(c))", 1, 0, nullptr},
        {"c_type", "c_type(c)", 0, 0, nullptr},
        {"c_cx", "n", 4, 0, nullptr},
        {"c_pos", "xcomp(c_pos(c)) + ycomp(c_pos(c))", 2, 1e-5, nullptr},
        {"c_x", "c_x(c)", 1, 1e-5, nullptr},
        {"c_y", "c_y(c)", 1, 1e-9, nullptr},
        {"c_z", "c_z(c)", 0, 1e-5, nullptr},
        {"c_n", "zcomp(c_n(c)) * sgn2", 1, 1e-9, nullptr},
        {"c_nx", "c_nx(c)", 0, 1e-6, nullptr},
        {"c_ny", "c_ny(c)", 0, 1e-6, nullptr},
        {"c_nz", "c_nz(c) * sgn2", 1, 1e-9, nullptr},
        {"c_area", "c_area(c)", 1, 1e-9, nullptr},
        {"c_jmat", "c_jmat(c)", 1, 0, nullptr},
        // The weight, and the pull of the x gravity resisted on the upper block.
        {"c_nforce", "c_nforce(c)", 20000, 2, nullptr},
        {"c_sforce", "xcomp(c_sforce(c)) * sgn2", -2000, 1, nullptr},
        {"c_near", "c_id(c_near(1, 1, 0.1))", 1, 0, nullptr},
        {"cx_next", "n", 4, 0, nullptr},
        {"cx_area", "sa", 1, 1e-9, nullptr},
        {"cx_nforce", "sf", 20000, 2, nullptr},
        {"cx_nstress", "ss", 20000, 2, nullptr},
        {"cx_xsforce", "sx * sgn2", -2000, 1, nullptr},
        {"cx_ysforce", "sy", 0, 1e-3, nullptr},
        {"cx_zsforce", "sz", 0, 1e-3, nullptr},
        {"cx_sforce", "sv * sgn2", -2000, 1, nullptr},
        {"cx_sstress", "sst2 * sgn2", -2000, 1, nullptr},
        {"cx_ndis", "sd", 2e-6, 1e-9, nullptr},
        {"cx_sdis", "sdis", 2e-7, 1e-9, nullptr},
        {"cx_state", "sst", 0, 0, nullptr},
        {"cx_pos", "zz", 0, 4e-5, nullptr},
        {"nblock", "nblock", 2, 0, nullptr},
        {"ncontact", "ncontact", 1, 0, nullptr},
        {"nzone", "nzone", 0, 0, nullptr},
        {"ngp", "ngp", 0, 0, nullptr},
        {"gravity", "xcomp(gravity) * 100 + zcomp(gravity)", 90, 1e-12, nullptr},
        {"unbal", "unbal < 20", 1, 0, nullptr},
        {"mech_ratio", "mech_ratio < 1e-7", 1, 0, nullptr},
        {"solve_verdict", "solve_verdict", 0, 0, "equilibrium"},
        {"fos_f", "fos_f", 0, 0, nullptr}, // before any 'solve fos' (after one: SolveFos, fos_test.cpp)
        {"zone_head", "zone_head", 0, 0, nullptr},
        {"gp_head", "gp_head", 0, 0, nullptr},
    };
}

std::vector<Case> block_write_cases() {
    return {
        {"b_extra", "b_extra(top)", 0, 0, "marked"},
        {"c_extra", "c_extra(c) * 2 + c_extra(c_near(1, 1, 0))", 126, 0, nullptr},
        {"b_xvel", "b_xvel(top)", 0.25, 0, nullptr},
        {"b_yvel", "b_yvel(top)", -0.5, 0, nullptr},
        {"b_zvel", "b_zvel(top)", 0.125, 0, nullptr},
        {"b_vel", "b_vel(top)", 0, 0, "(0.25,-0.5,0.125)"},
    };
}

// A block turned 10 degrees about z, then 20 about y, then 30 about x (world axes), spinning at
// the last about x: its turn R = Rx(30) Ry(20) Rz(10), whose X-Y-Z angles are (30, 20, 10).
std::vector<Case> block_turn_cases() {
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(30 * kPi / 180, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(20 * kPi / 180, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(10 * kPi / 180, Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    const Eigen::AngleAxisd turn(r);
    const Eigen::Vector3d rv = turn.angle() * turn.axis();
    const double w = 30 * kPi / 180 / 0.1;
    return {
        {"b_rot", "mag(b_rot(b))", turn.angle(), 1e-12, nullptr},
        {"b_xrot", "b_xrot(b)", rv.x(), 1e-12, nullptr},
        {"b_yrot", "b_yrot(b)", rv.y(), 1e-12, nullptr},
        {"b_zrot", "b_zrot(b)", rv.z(), 1e-12, nullptr},
        {"b_euler", "xcomp(b_euler(b)) * 1e4 + ycomp(b_euler(b)) * 1e2 + zcomp(b_euler(b))", 302010, 1e-8, nullptr},
        {"b_rvel", "mag(b_rvel(b) - vector(w, 0, 0))", 0, 1e-15, nullptr},
        {"b_xrvel", "b_xrvel(b)", w, 1e-15, nullptr},
        {"b_yrvel", "b_yrvel(b)", 0, 0, nullptr},
        {"b_zrvel", "b_zrvel(b)", 0, 0, nullptr},
    };
}

std::vector<Case> zone_cases() {
    const double r = std::sqrt(0.5) * 1e6; // principal stresses -1.5 MPa -/+ r
    return {
        {"zone_head", "z_id(zone_head)", 1, 0, nullptr},
        {"z_next", "nz - nzone", 0, 0, nullptr},
        {"z_id", "z_id(z_next(zone_head))", 2, 0, nullptr},
        {"z_sxx", "z_sxx(z)", -1e6, 1e-6, nullptr},
        {"z_syy", "z_syy(z)", -2e6, 1e-6, nullptr},
        {"z_szz", "z_szz(z)", -3e6, 1e-6, nullptr},
        {"z_sxy", "z_sxy(z)", 5e5, 1e-6, nullptr},
        {"z_sxz", "z_sxz(z)", 0, 1e-6, nullptr},
        {"z_syz", "z_syz(z)", 0, 1e-6, nullptr},
        {"z_sig1", "z_sig1(z)", -3e6, 1e-3, nullptr},
        {"z_sig2", "z_sig2(z)", -1.5e6 - r, 1e-3, nullptr},
        {"z_sig3", "z_sig3(z)", -1.5e6 + r, 1e-3, nullptr},
        {"z_vol", "vol", 1, 1e-12, nullptr},
        {"z_pos", "mag(z_pos(z_near(0.1, 0.1, 0.1)) - vector(0.1, 0.1, 0.1)) < 0.3", 1, 0, nullptr},
        {"z_x", "z_x(z_near(0.9, 0.1, 0.1)) > 0.5", 1, 0, nullptr},
        {"z_y", "z_y(z_near(0.1, 0.9, 0.1)) > 0.5", 1, 0, nullptr},
        {"z_z", "z_z(z_near(0.1, 0.1, 0.9)) > 0.5", 1, 0, nullptr},
        {"z_near", "z_x(z_near(vector(0.1, 0.1, 0.1))) < 0.5", 1, 0, nullptr},
        {"z_state", "z_state(z)", 0, 0, nullptr},
        {"z_model", "z_model(z)", 1, 0, nullptr},
        {"z_block", "b_id(z_block(z))", 1, 0, nullptr},
        {"z_gp", "gp_id(z_gp(z, 1)) > 0 and gp_id(z_gp(z, 4)) > 0", 1, 0, nullptr},
        {"z_extra", "z_extra(z)", 0, 0, "zone"},
        {"b_zone", "z_id(b_zone(block_head))", 1, 0, nullptr},
        {"b_gp", "gp_id(b_gp(block_head)) > 0", 1, 0, nullptr},
        {"b_type", "b_type(block_head)", 2, 0, nullptr},
        {"gp_head", "gp_id(gp_head)", 1, 0, nullptr},
        {"gp_next", "ng - ngp", 0, 0, nullptr},
        {"gp_id", "gp_id(gp_next(gp_head))", 2, 0, nullptr},
        {"gp_near", "gp_x(gp_near(vector(0.9, 0.9, 0.9)))", 1, 0, nullptr},
        {"gp_x", "gp_x(corner)", 1, 0, nullptr},
        {"gp_y", "gp_y(corner)", 1, 0, nullptr},
        {"gp_z", "gp_z(corner)", 1, 0, nullptr},
        {"gp_pos", "mag(gp_pos(corner))", std::sqrt(3.0), 1e-12, nullptr},
        {"gp_mass", "mass", 2000, 1e-9, nullptr},
        {"gp_extra", "gp_extra(corner)", 3.5, 0, nullptr},
        {"nzone", "nzone > 0", 1, 0, nullptr},
        {"ngp", "ngp > 8", 1, 0, nullptr},
    };
}

std::vector<Case> zone_step_cases() {
    return {
        {"gp_xvel", "gp_xvel(g)", 0.1, 1e-3, nullptr},
        {"gp_yvel", "gp_yvel(g)", 0.2, 2e-3, nullptr},
        {"gp_zvel", "gp_zvel(g)", -0.3, 3e-3, nullptr},
        {"gp_vel", "mag(gp_vel(g))", std::sqrt(0.14), 4e-3, nullptr},
        {"gp_xdis", "gp_xdis(g)", 1e-8, 1e-10, nullptr},
        {"gp_ydis", "gp_ydis(g)", 2e-8, 2e-10, nullptr},
        {"gp_zdis", "gp_zdis(g)", -3e-8, 3e-10, nullptr},
        {"gp_disp", "mag(gp_disp(g))", std::sqrt(0.14) * 1e-7, 4e-10, nullptr},
        {"gp_xforce", "fx", 0, 1e-3, nullptr},
        {"gp_yforce", "fy", 0, 1e-3, nullptr},
        {"gp_zforce", "fz", 0, 1e-3, nullptr},
        {"gp_force", "mag(gp_force(g)) > 1e4", 1, 0, nullptr},
        {"time", "time", 1e-7, 1e-20, nullptr},
        {"ncycle", "ncycle", 1, 0, nullptr},
        {"step", "step", 1, 0, nullptr},
        {"dt", "dt", 1e-7, 0, nullptr},
    };
}

// A cable of 4 segments from (-1,0,0) to (1,0,0), its first two nodes outside the block
// (0 < x < 2), its first node driven at 1e-3 m/s along -x for one step of 1e-3 s.
std::vector<Case> cable_cases() {
    return {
        {"cable_num", "cable_num", 1, 0, nullptr},
        {"cable_id", "cable_id(1)", 1, 0, nullptr},
        {"cable_nseg", "cable_nseg(1)", 4, 0, nullptr},
        // Segment 1 joins two free nodes: node 1 pulled out by 1e-6 m, EA/L0 = 2e7 / 0.5.
        {"cable_force", "cable_force(1,1)", 500 + 4e7 * 1e-6, 1e-6, nullptr},
        {"cable_yield", "cable_yield(1,1)", 0, 0, nullptr},
        {"cable_grout", "cable_grout(1,1)", 0, 0, nullptr},
        {"cable_slip", "cable_slip(1,3)", 0, 0, nullptr},
        {"cable_gstate", "cable_gstate(1,1) * 10 + cable_gstate(1,3)", -10, 0, nullptr},
        {"cable_pos", "xcomp(cable_pos(1,2))", -0.5, 1e-5, nullptr},
        {"cable_disp", "xcomp(cable_disp(1,1))", -1e-6, 1e-18, nullptr},
        {"cable_block", "cable_block(1,2) * 10 + cable_block(1,3)", 1, 0, nullptr},
    };
}

// A joint 4 m long and 2 m wide with the aperture 2e-4 m, its pressure held at 1e5 Pa along x = 0
// and 0 along x = 4, the upper block cut across at x = 2 (flow-parallel-plate.dat, cut once):
// linear pressure, Q = a^3 W dp / (12 mu L).
std::vector<Case> flow_cases() {
    return {
        {"fl_pp", "fl_pp(2,0,0)", 5e4, 5, nullptr},
        {"fl_aperture", "fl_aperture(vector(2,2,0))", 2e-4, 1e-12, nullptr},
        {"fl_flow", "fl_flow", 8e-12 * 2 * 1e5 / (12 * 1e-3 * 4), 1e-9, nullptr},
        {"fl_nnode", "fl_nnode", 8, 0, nullptr}, // 6 on the joint, 2 atop the cut
    };
}

// A liner on the top of a unit cube zoned with 'gen edge 1' (4 elements, 5 nodes), held at its
// base, under gravity; the bond has no shear stiffness, so nothing loads the liner in its plane.
// Solved: the bond carries the liner's whole weight, rho t g = 5000 N; the liner, supported
// all over, bends little (a plate of 1 m spanning would carry some 600 N m/m).
std::vector<Case> liner_cases() {
    return {
        {"li_num", "li_num", 1, 0, nullptr},
        {"li_id", "li_id(1)", 1, 0, nullptr},
        {"li_nel", "li_nel(1)", 4, 0, nullptr},
        {"li_nnode", "li_nnode(1)", 5, 0, nullptr},
        {"li_bond_n", "bsum", 5000, 1e-3, nullptr},
        {"li_bond_s", "li_bond_s(1,1)", 0, 0, nullptr},
        {"li_bstate", "li_bstate(1,1)", 0, 0, nullptr},
        {"li_nx", "li_nx(1,1)", 0, 1e-6, nullptr},
        {"li_ny", "li_ny(1,2)", 0, 1e-6, nullptr},
        {"li_nxy", "li_nxy(1,4)", 0, 1e-6, nullptr},
        {"li_mx", "abs(li_mx(1,1)) < 10", 1, 0, nullptr},
        {"li_my", "abs(li_my(1,3)) < 10", 1, 0, nullptr},
        {"li_mxy", "abs(li_mxy(1,2)) < 10", 1, 0, nullptr},
        {"li_centroid", "zcomp(li_centroid(1,1))", 1, 1e-5, nullptr},
        {"li_pos", "zcomp(li_pos(1,5))", 1, 1e-5, nullptr},
        {"li_disp", "zcomp(li_disp(1,1)) < 0", 1, 0, nullptr},
    };
}

// Intrinsics tested by scripts of their own below (files, arrays, out, error, memory offsets).
const std::vector<std::string> kScripted = {"open", "write", "read", "close", "array_size", "out",
                                            "lose_array", "error", "imem", "fmem"};

} // namespace

TEST(FishIntrinsics, MathAndConversion) {
    Session s;
    run_cases(s, "",
              math_cases());
    // The random sequences are the same in every session.
    Session t;
    ASSERT_TRUE(t.run("def r\n  a = urand\n  b = grand\nend\n@r")) << t.error();
    Session u;
    ASSERT_TRUE(u.run("def r\n  a = urand\n  b = grand\nend\n@r")) << u.error();
    EXPECT_EQ(t.interp.fish().find("a")->value.f, u.interp.fish().find("a")->value.f);
    EXPECT_EQ(t.interp.fish().find("b")->value.f, u.interp.fish().find("b")->value.f);
}

TEST(FishIntrinsics, FilesArraysOutAndError) {
    Session s;
    ASSERT_TRUE(s.run("def io\n"
                      "  array lines(3)\n  array back(3)\n"
                      "  lines(1) = 'first'\n  lines(2) = 2.5\n  lines(3) = 7\n"
                      "  o1 = open('fish_intrinsics_io.txt', 1, 1)\n"
                      "  w = write(lines, 3)\n"
                      "  c1 = close\n"
                      "  o2 = open('fish_intrinsics_io.txt', 0, 1)\n"
                      "  r1 = read(back, 3)\n"
                      "  r2 = read(back, 1)\n"
                      "  c2 = close\n"
                      "  n = array_size(back)\n"
                      "  o = out('printed by out')\n"
                      "  lose_array(back)\n"
                      "end\n@io"))
        << s.error();
    auto g = [&](const char* n) { return s.interp.fish().find(n)->value; };
    EXPECT_EQ(g("o1").number(), 0);
    EXPECT_EQ(g("w").number(), 0);
    EXPECT_EQ(g("c1").number(), 0);
    EXPECT_EQ(g("o2").number(), 0);
    EXPECT_EQ(g("r1").number(), 0);
    EXPECT_EQ(g("r2").number(), -1); // the file's end
    EXPECT_EQ(g("c2").number(), 0);
    EXPECT_EQ(g("n").number(), 3);
    EXPECT_EQ(g("o").number(), 0);
    EXPECT_NE(s.out.str().find("printed by out"), std::string::npos);
    const auto& back = s.interp.fish().find("back")->array;
    ASSERT_TRUE(back);
    EXPECT_TRUE(back->items.empty()); // lose_array freed it
    std::remove("fish_intrinsics_io.txt");

    Session e;
    EXPECT_FALSE(e.run("def stop\n  error = 'the dip must be below 90'\nend\n@stop\nset kp = 1"));
    EXPECT_NE(e.error().find("the dip must be below 90"), std::string::npos) << e.error();
    EXPECT_EQ(e.interp.fish().find("kp"), nullptr); // the script stopped at the error
}

TEST(FishIntrinsics, BlocksAndContactsOfARestingBlock) {
    Session s;
    ASSERT_TRUE(s.run(kRestingBlock)) << s.error();
    run_cases(s, kSubContactSums,
              block_cases());
    // Values a script stores with objects, and velocities it assigns.
    run_cases(s,
              "  top = b_near(1, 1, 0.5)\n  c = contact_head\n"
              "  b_extra(top) = 'marked'\n  c_extra(c) = 42\n"
              "  b_xvel(top) = 0.25\n  b_yvel(top) = -0.5\n  b_zvel(top) = 0.125\n",
              block_write_cases());
}

// Contacts are found once after a change of geometry, not at every 'contact_head' or
// 'change' that needs them before the next step (a FISH loop over blocks that asked for
// contact_head found every contact again at each turn: seconds a call on a large model).
TEST(FishIntrinsics, ContactsAreFoundOnceAfterEachChangeOfGeometry) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 2 -1 0\npoly brick 0.5 1.5 0.5 1.5 0 1\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\n"
                      "def count\n  n = 0\n  loop k (1, 5)\n    c = contact_head\n"
                      "    loop while c # 0\n      n = n + 1\n      c = c_next(c)\n    endloop\n"
                      "  endloop\nend\n@count\n")) << s.error();
    EXPECT_EQ(s.interp.fish().find("n")->value.number(), 5);
    EXPECT_EQ(s.model.contacts.n_detections, 1);
    ASSERT_TRUE(s.run("change jmat 1\nchange jmat 1 range z -0.5 0.5\n@count\n")) << s.error();
    EXPECT_EQ(s.model.contacts.n_detections, 1);
    // A third block on top: found at the next call, once.
    ASSERT_TRUE(s.run("poly brick 0.5 1.5 0.5 1.5 1 2\n@count\n@count\n")) << s.error();
    EXPECT_EQ(s.interp.fish().find("n")->value.number(), 10);
    EXPECT_EQ(s.model.contacts.n_detections, 2);
}

TEST(FishIntrinsics, RotationAndSpinOfATurnedBlock) {
    // Turned by spins about the world z, y and x axes in turn, 0.1 s each (no gravity, no
    // contacts, undamped: each spin turns it by exactly its angle).
    auto spin = [](double x, double y, double z) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "ini xrvel %.17g yrvel %.17g zrvel %.17g\nstep 100\n", x, y, z);
        return std::string(buf);
    };
    const double d = kPi / 180 / 0.1; // 1 degree in 0.1 s, rad/s
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick -1 1 -2 2 -0.5 0.5\nprop mat=1 dens=1000\ndamp off\nset dt 1e-3\n" +
                      spin(0, 0, 10 * d) + spin(0, 20 * d, 0) + spin(30 * d, 0, 0)))
        << s.error();
    run_cases(s, "  b = block_head\n  w = 30 * degrad / 0.1\n", block_turn_cases());
    // A spin set from FISH is the spin at the present time, and turns the block.
    run_cases(s, "  b = block_head\n  b_zrvel(b) = -0.5\n  b_xrvel(b) = 0\n",
              {{"b_zrvel", "b_zrvel(b)", -0.5, 0, nullptr}, {"b_rvel", "b_rvel(b)", 0, 0, "(0.0,0.0,-0.5)"}});
    const odec::Quat before = s.model.blocks.orientation[0];
    ASSERT_TRUE(s.run("step 100")) << s.error();
    const odec::Quat turned = s.model.blocks.orientation[0] * before.conjugate();
    EXPECT_NEAR(Eigen::AngleAxisd(turned).angle(), 0.05, 1e-12);
    // After 'reset disp' the turn counts from there.
    ASSERT_TRUE(s.run("reset disp")) << s.error();
    run_cases(s, "  b = block_head\n", {{"b_rot", "mag(b_rot(b))", 0, 0, nullptr}, {"b_euler", "mag(b_euler(b))", 0, 0, nullptr}});
    // A fixed block does not turn.
    EXPECT_FALSE(s.run("fix\ndef f\n  b_xrvel(block_head) = 1\nend\n@f"));
    EXPECT_NE(s.error().find("'b_xrvel': block 1 is fixed: it does not turn"), std::string::npos) << s.error();
}

TEST(FishIntrinsics, ZonesAndGridpointsOfAStressedCube) {
    // A zoned 1 m cube (2000 kg) under sxx -1, syy -2, szz -3, sxy 0.5 MPa: principal stresses
    // -3, -1.5 -/+ sqrt(0.5) MPa.
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\ngen edge 0.5\n"
                      "insitu stress -1e6 -2e6 -3e6 5e5 0 0\n"))
        << s.error();
    run_cases(s,
              "  z = zone_head\n  nz = 0\n  vol = 0\n  zn = z\n"
              "  loop while zn # 0\n    nz = nz + 1\n    vol = vol + z_vol(zn)\n    zn = z_next(zn)\n  endloop\n"
              "  ng = 0\n  mass = 0\n  g = gp_head\n"
              "  loop while g # 0\n    ng = ng + 1\n    mass = mass + gp_mass(g)\n    g = gp_next(g)\n  endloop\n"
              "  corner = gp_near(1, 1, 1)\n  z_extra(z) = 'zone'\n  gp_extra(corner) = 3.5\n",
              zone_cases());
    // One step of 1e-7 s from a given velocity: the gridpoints move by v dt (their stresses
    // change v by less than 1 % in that time); the unbalanced forces sum to zero.
    ASSERT_TRUE(s.run("ini xvel 0.1 yvel 0.2 zvel -0.3\nset dt 1e-7\nstep 1\n")) << s.error();
    run_cases(s,
              "  g = gp_near(1, 1, 1)\n  fx = 0\n  fy = 0\n  fz = 0\n  h = gp_head\n"
              "  loop while h # 0\n    fx = fx + gp_xforce(h)\n    fy = fy + gp_yforce(h)\n"
              "    fz = fz + zcomp(gp_force(h))\n    h = gp_next(h)\n  endloop\n",
              zone_step_cases());
}

TEST(FishIntrinsics, Cables) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 -0.5 0.5 -0.5 0.5\nprop mat=1 dens=2700\nfix\n"
                      "prop mat=3 cb_area=1e-4 cb_e=2e11 cb_kbond=1e8 cb_sbond=1e5 cb_dens=7800\n"
                      "cable -1,0,0 1,0,0 seg 4 prop 3 pretension 500\ncable id 1 node 1 velocity -1e-3,0,0\n"
                      "set dt 1e-3\nstep 1"))
        << s.error();
    run_cases(s, "", cable_cases());
}

TEST(FishIntrinsics, Flow) {
    Session s;
    ASSERT_TRUE(s.run("config flow\npoly brick 0 4 0 2 -1 0\npoly brick 0 2 0 2 0 1\npoly brick 2 4 0 2 0 1\n"
                      "prop mat=1 dens=2500\nprop jmat=1 jkn=1e10 jks=1e10 azero=2e-4\nfix\n"
                      "bound pp 1e5 range x -0.01 0.01 z -0.01 0.01\nbound pp 0 range x 3.99 4.01 z -0.01 0.01\n"
                      "set substeps 20\nstep 100"))
        << s.error();
    run_cases(s, "", flow_cases());
}

TEST(FishIntrinsics, Liners) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\ngen edge 1\n"
                      "bound xvel 0 yvel 0 zvel 0 range z -0.01 0.01\n"
                      "prop mat=2 li_e=30e9 li_nu=0.2 li_thick=0.2 li_dens=2500 li_kn=1e10 li_ks=0\n"
                      "liner range z 0.99 1.01 prop 2\ngrav 0 0 -10\nsolve ratio 1e-9"))
        << s.error();
    run_cases(s, "  bsum = 0\n  loop k (1, li_nnode(1))\n    bsum = bsum + li_bond_n(1, k)\n  endloop\n", liner_cases());
}

TEST(FishIntrinsics, MemoryOffsetsOfTheClassicCodesSayWhatToWrite) {
    Session s;
    ASSERT_TRUE(s.run(kRestingBlock)) << s.error();
    EXPECT_FALSE(s.run("def f\n  c = contact_head\n  x = fmem(c + $KCFN)\nend\n@f"));
    EXPECT_NE(s.error().find("'$KCFN' is a memory offset"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("write c_nforce(c)"), std::string::npos) << s.error();
    Session t;
    EXPECT_FALSE(t.run("def g\n  x = imem(5)\nend\n@g"));
    EXPECT_NE(t.error().find("odec has no memory offsets"), std::string::npos) << t.error();
    // Elsewhere a '$' name is an ordinary variable (classic scripts use them as private ones).
    Session u;
    ASSERT_TRUE(u.run("def h\n  $kp = 3\n  y = $kp * 2\nend\n@h")) << u.error();
    EXPECT_EQ(u.interp.fish().find("y")->value.number(), 6);
}

TEST(FishIntrinsics, SetGivesFishVariablesValues) {
    Session s;
    ASSERT_TRUE(s.run("def show\n  total = kn * 2\nend\n"
                      "set kn = 5e9 name = 'run 1' dir (0, 0, -1)\nset ncyc 20\n@show\nset kn 7\n"))
        << s.error();
    auto g = [&](const char* n) { return s.interp.fish().find(n)->value; };
    EXPECT_EQ(g("kn").number(), 7);
    EXPECT_EQ(g("total").number(), 1e10);
    EXPECT_EQ(g("name").s, "run 1");
    EXPECT_EQ(odec::fish::to_text(g("dir")), "(0.0,0.0,-1.0)");
    EXPECT_EQ(s.model.histories.ncyc, 20); // a setting is still a setting
    // A name that is neither a setting nor a FISH variable, without '=': the error lists the settings.
    EXPECT_FALSE(s.run("set nosuch 3"));
    EXPECT_NE(s.error().find("unknown keyword 'nosuch' for 'set'"), std::string::npos) << s.error();
    // A failed 'set' changes no variable.
    EXPECT_FALSE(s.run("set kn = 1 name"));
    EXPECT_EQ(g("kn").number(), 7);
    EXPECT_FALSE(s.run("set show = 1"));
    EXPECT_NE(s.error().find("is a FISH function"), std::string::npos) << s.error();
    // Names that are range filters elsewhere (x, id, z) are free here; values are taken in order.
    Session t;
    ASSERT_TRUE(t.run("set x = 1 id = 2 z = (1, 2, 3)\nset a = 4 b = a")) << t.error();
    EXPECT_EQ(t.interp.fish().find("id")->value.number(), 2);
    EXPECT_EQ(t.interp.fish().find("b")->value.number(), 4);
    EXPECT_TRUE(t.error().empty()) << t.error();
    // A mistyped setting becomes a variable, and says so.
    ASSERT_TRUE(t.run("set dtfrax = 0.2")) << t.error();
    EXPECT_NE(t.error().find("'dtfrax' is no setting of 'set' (did you mean 'dtfrac'?)"), std::string::npos) << t.error();
    EXPECT_FALSE(t.run("set v = (1e400, 0, 0)"));
    EXPECT_EQ(t.interp.fish().find("v"), nullptr);
    EXPECT_FALSE(t.run("set w = 1 u = nosuch"));
    EXPECT_NE(t.error().find("'nosuch' is no FISH variable or function"), std::string::npos) << t.error();
    EXPECT_EQ(t.interp.fish().find("w"), nullptr); // checked before anything was set
}

TEST(FishIntrinsics, EveryIntrinsicHasACase) {
    std::set<std::string> covered(kScripted.begin(), kScripted.end());
    for (const auto& table : {math_cases(), block_cases(), block_write_cases(), block_turn_cases(), zone_cases(),
                              zone_step_cases(), cable_cases(), flow_cases(), liner_cases()}) {
        for (const Case& c : table) covered.insert(c.intrinsic);
    }
    // The energy account's, each read against its term by Energy.CommandsAndFish (energy_test.cpp).
    for (const odec::EnergyTermInfo& t : odec::energy_terms()) covered.insert(std::string("energy_") + t.name);
    std::string missing;
    for (const odec::fish::Intrinsic* in : odec::fish::all_intrinsics()) {
        if (!covered.count(in->name)) missing += std::string(" ") + in->name;
    }
    EXPECT_TRUE(missing.empty()) << "intrinsics without a case:" << missing;
}

TEST(FishIntrinsics, HelpDescribesEachIntrinsic) {
    Session s;
    ASSERT_TRUE(s.run("help fish")) << s.error();
    for (const odec::fish::Intrinsic* in : odec::fish::all_intrinsics()) {
        EXPECT_NE(s.out.str().find(in->name), std::string::npos) << in->name;
    }
    Session t;
    ASSERT_TRUE(t.run("help fish c_nforce")) << t.error();
    EXPECT_NE(t.out.str().find("normal force, compression positive, N"), std::string::npos) << t.out.str();
    Session u; // the intrinsic named alone, as for a command
    ASSERT_TRUE(u.run("help z_sig1")) << u.error();
    EXPECT_NE(u.out.str().find("most compressive"), std::string::npos) << u.out.str();
    Session v;
    EXPECT_FALSE(v.run("help fish nosuch"));
    EXPECT_NE(v.error().find("'nosuch' is no FISH intrinsic"), std::string::npos) << v.error();
}

// cx_ndis is the closure print, hist and the export give (what the normal spring carries, sn / kn),
// also on a joint that dilates as it slips: it used to give the faces' overlap, which the
// dilation makes smaller (5.7e-5 m against 1e-4 m under 1 MPa on a 1e10 Pa/m joint).
TEST(FishIntrinsics, CxNdisIsTheClosureEveryOtherRouteGives) {
    Session s;
    ASSERT_TRUE(s.run("poly brick -0.5 2.0 -0.5 1.5 -1 0 region 1\npoly brick 0 1 0 1 -1e-4 0.0019 region 2\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30 jdil=10\nfix range region 1\n"
                      "bound xvel 0.01 zload -1e6 range region 2\nstep time 0.03\n"
                      "def worst\n  worst = 0\n  local c = contact_head\n  local k = c_cx(c)\n  loop while k # 0\n"
                      "    worst = max(worst, abs(cx_ndis(k) - cx_nstress(k) / 1e10))\n    k = cx_next(k)\n  endloop\nend\n"
                      "@worst"))
        << s.error();
    const odec::fish::Symbol* w = s.interp.fish().find("worst");
    ASSERT_NE(w, nullptr);
    EXPECT_LT(w->value.number(), 1e-7);  // the dilation of the last step aside (it was 4.3e-5)
    // The joint did dilate: the faces' overlap is well below the closure.
    const odec::ContactSet& cs = s.model.contacts;
    ASSERT_GT(cs.n_subs(), 0);
    EXPECT_GT(cs.sub_dilation(0), 1e-5);
}
