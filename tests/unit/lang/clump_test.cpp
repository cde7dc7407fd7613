// Clumps (engine/clump.h): the convex pieces of a rigid solid that is not convex move as one
// rigid body, against the analytic motion of one rigid body; no contact between them; what acts
// on one piece acts on the whole; the energy account of an arch of such voussoirs; save files.
#include <gtest/gtest.h>

#include <initializer_list>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "engine/blocks.h"
#include "engine/clump.h"
#include "engine/cycle.h"
#include "engine/verdict.h"
#include "engine/contact.h"
#include "engine/energy.h"
#include "test_util.h"

using odec::Vec3;
using odec::test::Session;
using odec::test::read_bytes;
using odec::test::write_bytes;

namespace {

std::string pt(double x, double y, double z) {
    std::ostringstream o;
    o.precision(12);
    o << "(" << x << "," << y << "," << z << ")";
    return o.str();
}

// A prism on a polygon in the x-z plane, from y = 0 to y = 1.
std::string prism(const std::vector<double>& x, const std::vector<double>& z, const char* extra = "") {
    std::string s = "poly prism a";
    for (size_t i = 0; i < x.size(); ++i) s += " " + pt(x[i], 0, z[i]);
    s += " b";
    for (size_t i = 0; i < x.size(); ++i) s += " " + pt(x[i], 1, z[i]);
    return s + " " + extra + "\n";
}

// An L: a 2 x 1 foot [0,2] x [0,1] and a 1 x 2 leg [0,1] x [1,3] in x-z, 1 m deep, shifted by
// (dx, dz). Density 1000: mass 4000 kg, centroid (0.75, 0.5, 1.25) + shift, inertia about the
// y axis through it 4000 (5/12 + 0.625) kg m^2 (each half: m (a^2 + b^2) / 12 about its own
// centroid plus m d^2, d^2 = 0.25^2 + 0.75^2).
std::string l_block(double dx = 0, double dz = 0) {
    return prism({0 + dx, 2 + dx, 2 + dx, 1 + dx, 1 + dx, 0 + dx}, {0 + dz, 0 + dz, 1 + dz, 1 + dz, 3 + dz, 3 + dz});
}
constexpr double kMass = 4000;
const Vec3 kCentroid(0.75, 0.5, 1.25);
constexpr double kIyy = 4000 * (5.0 / 12.0 + 0.625);

std::vector<int> pieces_of_clump(const odec::Model& m) {
    std::vector<int> out;
    for (int b = 0; b < m.blocks.size(); ++b) {
        if (m.blocks.clump[b] != 0) out.push_back(b);
    }
    return out;
}

// Rotation about y by angle a of vector r.
Vec3 turn_y(const Vec3& r, double a) {
    return Vec3(std::cos(a) * r.x() + std::sin(a) * r.z(), r.y(), -std::sin(a) * r.x() + std::cos(a) * r.z());
}

} // namespace

TEST(Clump, ANonConvexSolidIsOneClumpWithTheSolidsMassProperties) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(l_block() + "prop mat=1 dens=1000")) << s.error();
    const odec::Model& m = s.model;
    ASSERT_GE(m.blocks.size(), 2);
    EXPECT_NE(s.out.str().find("one rigid body (clump 1)"), std::string::npos) << s.out.str();
    const std::vector<int> p = pieces_of_clump(m);
    ASSERT_EQ(static_cast<int>(p.size()), m.blocks.size());
    for (int b : p) EXPECT_EQ(m.blocks.clump[b], 1);
    const odec::ClumpBody body = odec::clump_body(m.blocks, p.data(), static_cast<int>(p.size()));
    EXPECT_NEAR(body.mass, kMass, 1e-9 * kMass);
    EXPECT_LT((body.centroid - kCentroid).norm(), 1e-12);
    EXPECT_NEAR(body.inertia(1, 1), kIyy, 1e-9 * kIyy);
    EXPECT_NEAR(body.inertia(0, 1), 0.0, 1e-9 * kIyy);
    EXPECT_NEAR(body.inertia(1, 2), 0.0, 1e-9 * kIyy);
    // 'print block' names the clump, 'print info' counts it.
    s.out.str("");
    ASSERT_TRUE(s.run("print block\nprint info")) << s.error();
    EXPECT_NE(s.out.str().find("clump"), std::string::npos);
    EXPECT_NE(s.out.str().find("clumps:     1"), std::string::npos) << s.out.str();
}

// Thrown upward and spun about y (a principal axis through its centroid), under gravity: every
// piece follows the one rigid motion x(t) = C0 + v0 t + g t^2 / 2 + R_y(w t) (x0 - C0). Central
// differences are exact for a constant acceleration and a constant spin.
TEST(Clump, FallsAndTurnsExactlyAsOneRigidBody) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\ndamp off\n" + l_block() +
                      "prop mat=1 dens=1000\ngrav 0 0 -10\nset dt 1e-3\nset energy on\n"
                      "ini zvel 3 xvel 0.5 yrvel 2 range id 1"))
        << s.error();
    const odec::Model& m0 = s.model;
    const std::vector<int> p = pieces_of_clump(m0);
    ASSERT_GE(p.size(), 2u);
    std::vector<Vec3> c0, corner0;
    for (int b : p) {
        c0.push_back(m0.blocks.centroid[b]);
        corner0.push_back(m0.blocks.centroid[b] + m0.blocks.shape[b].vertices[0]);
    }
    // Every piece takes the clump's velocity at its own centroid, at t.
    for (int b : p) {
        const Vec3 expect = Vec3(0.5, 0, 3) + Vec3(0, 2, 0).cross(m0.blocks.centroid[b] - kCentroid);
        EXPECT_LT((odec::velocity_at_t(m0, b) - expect).norm(), 1e-12);
        EXPECT_LT((odec::spin_at_t(m0, b) - Vec3(0, 2, 0)).norm(), 1e-12);
    }
    ASSERT_TRUE(s.run("step 500")) << s.error();
    const odec::Model& m = s.model;
    const double t = 0.5;
    const Vec3 c = kCentroid + Vec3(0.5, 0, 3) * t + Vec3(0, 0, -5) * t * t;
    const double a = 2 * t;
    for (size_t i = 0; i < p.size(); ++i) {
        const int b = p[i];
        SCOPED_TRACE("piece " + std::to_string(m.blocks.id[b]));
        EXPECT_LT((m.blocks.centroid[b] - (c + turn_y(c0[i] - kCentroid, a))).norm(), 1e-9);
        const Vec3 corner = m.blocks.centroid[b] + m.blocks.orientation[b] * m.blocks.shape[b].vertices[0];
        EXPECT_LT((corner - (c + turn_y(corner0[i] - kCentroid, a))).norm(), 1e-9);
        EXPECT_LT((odec::rotation_since_reset(m, b) - Vec3(0, a, 0)).norm(), 1e-9);
        const Vec3 v = Vec3(0.5, 0, 3 - 10 * t) + Vec3(0, 2, 0).cross(m.blocks.centroid[b] - c);
        EXPECT_LT((odec::velocity_at_t(m, b) - v).norm(), 1e-9);
        // The displacement of a material point since it was made: exact for any rotation.
        EXPECT_LT((odec::point_displacement(m, b, m.blocks.shape[b].vertices[0]) - (corner - corner0[i])).norm(), 1e-9);
    }
    // The kinetic energy (half-step velocities) is the one body's, counted once: the pieces'
    // sum is M v^2 / 2 + I w^2 / 2 with I the clump's inertia about its centroid.
    const Vec3 v_half(0.5, 0, 3 - 10 * (t - 0.0005));
    const double ke = 0.5 * kMass * v_half.squaredNorm() + 0.5 * kIyy * 4;
    EXPECT_NEAR(odec::stored_kinetic_energy(m), ke, 1e-9 * ke);
    // And the account balances: gravity's work went into kinetic energy.
    // And the account balances: gravity's work went into kinetic energy, less the m g^2 dt^2 / 8
    // the half-step reading dips by where the spin and the velocity were given (energy.h), as
    // for one block.
    const odec::EnergyReading r = odec::energy_reading(m);
    EXPECT_NEAR(r.error(), -kMass * 100 * 1e-6 / 8, 1e-9 * r.kinetic) << "kinetic " << r.kinetic << " gravity " << r.gravity;
    EXPECT_EQ(m.contacts.size(), 0);
}

// A force at a point of one piece: the clump accelerates as F / M and turns as I^-1 (r x F)
// with r from the clump's centroid (not the piece's) to the point.
TEST(Clump, ALoadOnOnePieceActsOnTheWholeAboutItsCentroid) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\ndamp off\n" + l_block() +
                      "prop mat=1 dens=1000\nset dt 1e-4\nbound zload 1000 point 1.8,0.5,0.5\nstep 100"))
        << s.error();
    const odec::Model& m = s.model;
    const std::vector<int> p = pieces_of_clump(m);
    const double t = 0.01;
    const Vec3 r = Vec3(1.8, 0.5, 0.5) - kCentroid, f(0, 0, 1000);
    const double alpha = r.cross(f).y() / kIyy; // y is principal
    for (int b : p) {
        SCOPED_TRACE("piece " + std::to_string(m.blocks.id[b]));
        const Vec3 w = odec::spin_at_t(m, b);
        EXPECT_NEAR(w.y(), alpha * t, 1e-4 * std::abs(alpha * t));
        EXPECT_NEAR(w.x(), 0.0, 1e-12);
        EXPECT_NEAR(w.z(), 0.0, 1e-12);
    }
    const odec::ClumpBody body = odec::clump_body(m.blocks, p.data(), static_cast<int>(p.size()));
    // The velocity of the centroid at t: the half-step velocity plus half a step of acceleration.
    EXPECT_NEAR(body.vel.z() + 0.5 * 1e-4 * 1000 / kMass, 1000 * t / kMass, 1e-6 * 1000 * t / kMass);
    EXPECT_NEAR(body.vel.x(), 0.0, 1e-9);
}

// Resting on a fixed base: contacts with the base only, none between the pieces; it settles.
TEST(Clump, NoContactsBetweenItsPieces) {
    Session s;
    ASSERT_TRUE(s.run("poly brick -1 3 -1 2 -1 0\n" + l_block() +
                      "prop mat=1 dens=1000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40\ngrav 0 0 -10\nfix range z -1 0\n"
                      "step 400"))
        << s.error();
    const odec::Model& m = s.model;
    ASSERT_GT(m.contacts.size(), 0);
    for (int c = 0; c < m.contacts.size(); ++c) {
        const int a = m.contacts.block_a[c], b = m.contacts.block_b[c];
        EXPECT_FALSE(m.blocks.clump[a] != 0 && m.blocks.clump[a] == m.blocks.clump[b])
            << "contact " << m.contacts.id[c] << " between blocks " << m.blocks.id[a] << " and " << m.blocks.id[b];
        EXPECT_TRUE((m.blocks.flags[a] | m.blocks.flags[b]) & odec::kFixed);
    }
    // Only the foot's piece (or pieces) touches the base.
    for (int b : pieces_of_clump(m)) EXPECT_LT(std::abs(odec::velocity_at_t(m, b).z()), 1e-3);
}

// A clump at rest is in equilibrium as a whole: its pieces, each loaded by its own weight and the
// contacts it has, are not (the L block's upright carries its weight down through the foot, which
// is not a contact: the pieces share no contacts, NoContactsBetweenItsPieces). The unbalanced
// force and ratio that 'solve' stops on are the clump's; counted piece by piece they stayed near
// the pieces' weights and 'solve' never ended.
TEST(Clump, ItsUnbalancedForceIsTheWholeClumps) {
    Session s;
    ASSERT_TRUE(s.run("poly brick -1 3 -1 2 -1 0\n" + l_block(0, 0.001) +
                      "prop mat=1 dens=1000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40\ngrav 0 0 -10\n"
                      "fix range z -1 0\nsolve ratio 1e-5"))
        << s.error();
    ASSERT_TRUE(s.interp.last_solve);
    EXPECT_EQ(s.interp.last_solve->outcome, odec::SolveOutcome::Equilibrium);
    std::printf("[clump] L block on its base: equilibrium after %ld steps\n", s.model.step);
    EXPECT_LT(odec::unbalanced_ratio(s.model), 1e-5);
    EXPECT_LT(odec::max_unbalanced_force(s.model), 1e-4 * kMass * 10);
    // A piece alone carries much of its weight unbalanced, and is not counted on its own.
    double largest_piece = 0;
    int reported = 0;
    for (int b : pieces_of_clump(s.model)) {
        largest_piece = std::max(largest_piece, s.model.blocks.force[b].norm());
        Vec3 f;
        reported += odec::rigid_body_unbalanced(s.model, b, f) ? 1 : 0;
    }
    EXPECT_GT(largest_piece, 0.05 * kMass * 10);
    EXPECT_EQ(reported, 1);
}

TEST(Clump, FixDeleteAndIniTakeTheWholeClump) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(l_block() + "poly brick 5 6 0 1 0 1\nprop mat=1 dens=1000")) << s.error();
    const int n = s.model.blocks.size();
    const std::vector<int> p = pieces_of_clump(s.model);
    ASSERT_EQ(static_cast<int>(p.size()), n - 1);
    const int last = s.model.blocks.id[p.back()];
    s.out.str("");
    ASSERT_TRUE(s.run("fix range id " + std::to_string(last))) << s.error();
    EXPECT_NE(s.out.str().find("fixing the other"), std::string::npos) << s.out.str();
    for (int b : p) EXPECT_TRUE(s.model.blocks.flags[b] & odec::kFixed);
    ASSERT_TRUE(s.run("free range id " + std::to_string(last))) << s.error();
    for (int b : p) EXPECT_FALSE(s.model.blocks.flags[b] & odec::kFixed);
    // A velocity boundary holds the clump's centroid, on every piece.
    ASSERT_TRUE(s.run("bound xvel 0.25 range id " + std::to_string(last))) << s.error();
    for (int b : p) {
        EXPECT_EQ(s.model.blocks.vel_bc[b], 1);
        EXPECT_EQ(s.model.blocks.vel_bc_value[b].x(), 0.25);
    }
    ASSERT_TRUE(s.run("bound free range id " + std::to_string(last))) << s.error();
    for (int b : p) EXPECT_EQ(s.model.blocks.vel_bc[b], 0);
    // FISH: a piece's velocity and spin are set as a block's (its centroid's velocity, the spin
    // about it), the whole clump following; they read back as set.
    ASSERT_TRUE(s.run("def kick\n  bk = b_near(1.8, 0.5, 0.5)\n  b_zrvel(bk) = 0.5\n  b_xvel(bk) = 1\n"
                      "  if b_xvel(bk) # 1 then\n    error = 'b_xvel reads back otherwise'\n  endif\nend\n@kick"))
        << s.error();
    const int bk = odec::find_block_at(s.model, Vec3(1.8, 0.5, 0.5));
    for (int b : p) {
        const Vec3 expect = Vec3(1, 0, 0) + Vec3(0, 0, 0.5).cross(s.model.blocks.centroid[b] - s.model.blocks.centroid[bk]);
        EXPECT_LT((odec::velocity_at_t(s.model, b) - expect).norm(), 1e-12);
        EXPECT_LT((odec::spin_at_t(s.model, b) - Vec3(0, 0, 0.5)).norm(), 1e-12);
    }
    // b_clump names the clump (the id of its first piece): 1 here, 0 for the brick alone.
    ASSERT_TRUE(s.run("def chk\n  if b_clump(b_near(0.5, 0.5, 2.5)) # 1 then\n    error = 'not in clump 1'\n  endif\n"
                      "  if b_clump(b_near(5.5, 0.5, 0.5)) # 0 then\n    error = 'the brick is in a clump'\n  endif\nend\n@chk"))
        << s.error();
    s.out.str("");
    ASSERT_TRUE(s.run("delete range id " + std::to_string(last))) << s.error();
    EXPECT_NE(s.out.str().find("deleting the other"), std::string::npos) << s.out.str();
    EXPECT_EQ(s.model.blocks.size(), 1);
    EXPECT_EQ(s.model.blocks.clump[0], 0);
}

TEST(Clump, ACutThroughAPieceEndsTheClump) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(l_block() + "prop mat=1 dens=1000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40")) << s.error();
    const int before = s.model.blocks.size();
    s.out.str("");
    ASSERT_TRUE(s.run("jset dip 0 dd 0 origin 0,0,2")) << s.error();
    EXPECT_NE(s.out.str().find("the planes cut 1 clump"), std::string::npos) << s.out.str();
    EXPECT_EQ(s.model.blocks.size(), before + 1);
    EXPECT_TRUE(pieces_of_clump(s.model).empty());
    // Its pieces are glued to each other now, as before clumps, across the faces between them;
    // the new cut is a joint.
    ASSERT_TRUE(s.run("step 1")) << s.error();
    int joined = 0;
    for (int c = 0; c < s.model.contacts.size(); ++c) joined += s.model.contacts.joined(c);
    EXPECT_GE(joined, before - 1);
    EXPECT_GE(s.model.contacts.size() - joined, 1);
}

// An arch of nine voussoirs whose intrados is bent inward (each a clump of convex pieces), on a
// fixed base, under gravity from rest, without damping, on joints of 1e10 Pa/m: kinetic + joint
// strain energy + slip - work of gravity stays where it began, to 0.1 % of the most energy the
// account has handled (energy_motion_test.cpp has the convex arch).
TEST(Clump, AnArchOfNonConvexVoussoirsKeepsItsEnergy) {
    std::string model = "poly brick -7 7 -1 2 -1 0\n";
    const int n = 9;
    for (int i = 0; i < n; ++i) {
        const double a0 = M_PI * i / n, a1 = M_PI * (i + 1) / n, am = 0.5 * (a0 + a1);
        // Extrados: the two corners and the middle at 5.5 m; intrados: the middle at 4.5 m, bent
        // inward from the chord between the corners.
        model += prism({4.5 * std::cos(a0), 5.5 * std::cos(a0), 5.5 * std::cos(am), 5.5 * std::cos(a1),
                        4.5 * std::cos(a1), 4.5 * std::cos(am)},
                       {4.5 * std::sin(a0), 5.5 * std::sin(a0), 5.5 * std::sin(am), 5.5 * std::sin(a1),
                        4.5 * std::sin(a1), 4.5 * std::sin(am)});
    }
    Session s;
    ASSERT_TRUE(s.run("config dyn\ndamp off\nset dtfrac 0.02\n" + model +
                      "prop mat=1 dens=2500\nprop jmat=1 jkn=1e10 jks=1e10 jfric=80\ngrav 0 0 -10\n"
                      "fix range z -1 0\nset energy on\nhist ncyc 10\nhist energy error\nhist energy kinetic\n"
                      "solve time 0.2"))
        << s.error();
    const odec::Model& m = s.model;
    EXPECT_EQ(odec::list_clumps(m.blocks).size(), n);
    for (int c = 0; c < m.contacts.size(); ++c) {
        const int a = m.contacts.block_a[c], b = m.contacts.block_b[c];
        EXPECT_FALSE(m.blocks.clump[a] != 0 && m.blocks.clump[a] == m.blocks.clump[b]);
    }
    const auto& err = m.histories.items.at(0).values;
    const auto& kin = m.histories.items.at(1).values;
    double worst = 0, kinetic = 0;
    for (double e : err) worst = std::max(worst, std::abs(e));
    for (double e : kin) kinetic = std::max(kinetic, std::abs(e));
    const double peak = m.energy.peak;
    std::printf("[energy] arch of clumps, kn 1e10: %ld steps, largest kinetic %.6g J, largest |error| %.3g J = %.4f %% "
                "of %.6g J\n",
                m.step, kinetic, worst, 100 * worst / peak, peak);
    EXPECT_GT(kinetic, 0.05 * peak) << "it hardly moved";
    EXPECT_LT(worst, 1e-3 * peak) << "energy made or lost";
}

namespace {

// A save file of the format before clumps (11) made from one of this format: the clump array
// of the blocks (a length and an int per block, written after the inertial moments and before
// the world vertex offsets, which start at 0) taken out, the shear vectors of the sub-contacts
// `cs` written as vectors (format 17 holds them on their contacts' axes, two numbers each), the
// contacts' normals, gaps and joint models and the sub-contacts' points as format 17 had them
// (format 18 narrowed them), the
// lengths and the checksum made right.
std::string without_clumps(std::string file, const std::vector<int>& clumps, const odec::ContactSet& cs) {
    const int n_blocks = static_cast<int>(clumps.size());
    std::uint64_t n_version = 0;
    std::memcpy(&n_version, &file[16], 8);
    const size_t payload_length_at = 24 + n_version;
    const size_t blks = file.find("BLKS", payload_length_at + 8);
    // [n][clump] x n, then [n + 1][0] (the vertex offsets) or [0][0] (none, nor vertices).
    std::string pattern(8 + 4 * clumps.size(), '\0');
    std::uint64_t n = static_cast<std::uint64_t>(n_blocks);
    std::memcpy(&pattern[0], &n, 8);
    std::memcpy(&pattern[8], clumps.data(), 4 * clumps.size());
    // The last such array of the section (the world vertices follow it).
    std::uint64_t blks_length = 0;
    std::memcpy(&blks_length, &file[blks + 4], 8);
    size_t at = std::string::npos;
    for (size_t p = file.rfind(pattern, blks + 12 + blks_length); p != std::string::npos && p > blks;
         p = file.rfind(pattern, p - 1)) {
        std::uint64_t next = 0, after = 1;
        std::int32_t first = -1;
        std::memcpy(&next, &file[p + 8 + 4 * n_blocks], 8);
        std::memcpy(&first, &file[p + 16 + 4 * n_blocks], 4);
        std::memcpy(&after, &file[p + 16 + 4 * n_blocks], 8);
        if ((next == n + 1 && first == 0) || (next == 0 && after == 0)) {
            at = p;
            break;
        }
    }
    if (at == std::string::npos) return "";
    const size_t by = 8 + 4 * static_cast<size_t>(n_blocks);
    file.erase(at, by);
    auto shrink = [&](size_t at_length) {
        std::uint64_t len = 0;
        std::memcpy(&len, &file[at_length], 8);
        len -= by;
        std::memcpy(&file[at_length], &len, 8);
    };
    shrink(blks + 4);
    shrink(payload_length_at);
    // Formats 13 and 14 (after the clumps) added fluid flow and liners: their sections, the last
    // before the checksum; their stages' times, the last two of the profile; the three apertures
    // that end each joint material (a flag and eleven numbers each).
    auto cut = [&](size_t where, size_t bytes, std::initializer_list<size_t> lengths_at) {
        file.erase(where, bytes);
        for (size_t at_length : lengths_at) {
            std::uint64_t len = 0;
            std::memcpy(&len, &file[at_length], 8);
            len -= bytes;
            std::memcpy(&file[at_length], &len, 8);
        }
    };
    const size_t flow = file.rfind("FLOW");
    if (flow == std::string::npos || flow < blks) return "";
    cut(flow, file.size() - 8 - flow, {payload_length_at});
    const size_t jmat = file.find("JMAT", payload_length_at + 8);
    std::uint64_t n_jmat = 0;
    std::memcpy(&n_jmat, &file[jmat + 12], 8);
    for (std::uint64_t i = n_jmat; i-- > 0;) cut(jmat + 20 + i * 89 + 65, 24, {jmat + 4, payload_length_at});
    const size_t prof = file.find("PROF", payload_length_at + 8);
    std::int32_t stages = 0;
    std::memcpy(&stages, &file[prof + 12], 4);
    if (stages != static_cast<int>(odec::Stage::Count)) return "";
    cut(prof + 16 + 8 * (stages - 2), 16, {prof + 4, payload_length_at});
    stages -= 2;
    std::memcpy(&file[prof + 12], &stages, 4);
    // Formats 15 and 16 added adaptive damping's memory of the last step and its timestep, the
    // last 24 bytes of DAMP.
    const size_t damp = file.find("DAMP", payload_length_at + 8);
    if (damp == std::string::npos || damp > blks) return "";
    std::uint64_t damp_length = 0;
    std::memcpy(&damp_length, &file[damp + 4], 8);
    cut(damp + 12 + damp_length - 24, 24, {damp + 4, payload_length_at});
    const size_t cont = file.find("CONT", payload_length_at + 8);
    if (cont == std::string::npos) return "";
    // The section and the payload grow by `bytes` (an array widened or put back).
    auto grow_contacts = [&](size_t bytes) {
        for (size_t at_length : {cont + 4, payload_length_at}) {
            std::uint64_t len = 0;
            std::memcpy(&len, &file[at_length], 8);
            len += bytes;
            std::memcpy(&file[at_length], &len, 8);
        }
    };
    size_t from = cont;
    // Format 18 holds the normals as codes of 8 bytes (vectors before), each contact's gap as a
    // float (a double before) and its joint model as a byte (an int); format 17 dropped the
    // reference point of each contact's plane, an array after the normals (older files' are
    // read and left: zeros will do).
    {
        const std::uint64_t nc = cs.normal_code.size();
        std::string pattern(8 + 8 * nc, '\0');
        std::memcpy(&pattern[0], &nc, 8);
        if (nc > 0) std::memcpy(&pattern[8], cs.normal_code.data(), 8 * nc);
        std::string gaps(8 + 4 * nc, '\0');
        std::memcpy(&gaps[0], &nc, 8);
        if (nc > 0) std::memcpy(&gaps[8], cs.gap.data(), 4 * nc);
        std::string jmats(8 + 4 * nc, '\0');
        std::memcpy(&jmats[0], &nc, 8);
        std::string jconss(8 + nc, '\0');
        std::memcpy(&jconss[0], &nc, 8);
        for (std::uint64_t c = 0; c < nc; ++c) {
            const std::int32_t jm = cs.jmat(static_cast<int>(c));
            std::memcpy(&jmats[8 + 4 * c], &jm, 4);
            jconss[8 + c] = static_cast<char>(cs.jcons(static_cast<int>(c)));
        }
        const std::string old_part = pattern + gaps + jmats + jconss;
        const size_t at = file.find(old_part, from);
        if (at == std::string::npos) return "";
        std::string wide(8 + 24 * nc, '\0'), points(8 + 24 * nc, '\0'), wide_gaps(8 + 8 * nc, '\0'),
            wide_jcons(8 + 4 * nc, '\0');
        for (std::string* part : {&wide, &points, &wide_gaps, &wide_jcons}) std::memcpy(&(*part)[0], &nc, 8);
        for (std::uint64_t c = 0; c < nc; ++c) {
            const Eigen::Vector3d n = cs.normal(static_cast<int>(c));
            const double g = cs.gap[c];
            const std::int32_t j = cs.jcons(c);
            std::memcpy(&wide[8 + 24 * c], n.data(), 24);
            std::memcpy(&wide_gaps[8 + 8 * c], &g, 8);
            std::memcpy(&wide_jcons[8 + 4 * c], &j, 4);
        }
        const std::string new_part = wide + points + wide_gaps + jmats + wide_jcons;
        file.replace(at, old_part.size(), new_part);
        grow_contacts(new_part.size() - old_part.size());
        from = at + new_part.size();
        // Format 19 added whether open closures are held by reference (a byte) and each
        // contact's free motion, an array of ints, after the glued flags (a byte each): gone.
        const size_t motion_at = from + 8 + nc;
        std::uint64_t n_motion = 0;
        std::memcpy(&n_motion, &file[motion_at + 1], 8);
        if (n_motion != 0 && n_motion != nc) return "";
        const size_t bytes = 1 + 8 + 4 * n_motion;
        file.erase(motion_at, bytes);
        for (size_t at_length : {cont + 4, payload_length_at}) {
            std::uint64_t len = 0;
            std::memcpy(&len, &file[at_length], 8);
            len -= bytes;
            std::memcpy(&file[at_length], &len, 8);
        }
    }
    // Format 18 holds the sub-contacts' points as codes of 14 bytes (vectors before).
    {
        const std::uint64_t ns = cs.sub_point.size();
        std::string pattern(8 + 14 * ns, '\0');
        std::memcpy(&pattern[0], &ns, 8);
        for (std::uint64_t k = 0; k < ns; ++k) {
            const odec::PointCode p = odec::untagged_point(cs.sub_point[k]); // the file's code, without the flags
            std::memcpy(&pattern[8 + 14 * k], &p, 14);
        }
        const size_t at = file.find(pattern, from);
        if (at == std::string::npos) return "";
        std::string wide(8 + 24 * ns, '\0');
        std::memcpy(&wide[0], &ns, 8);
        for (std::uint64_t k = 0; k < ns; ++k) {
            const Eigen::Vector3d x = cs.sub_point_local(static_cast<int>(k));
            std::memcpy(&wide[8 + 24 * k], x.data(), 24);
        }
        file.replace(at, pattern.size(), wide);
        grow_contacts(wide.size() - pattern.size());
        from = at + wide.size();
    }
    auto widen = [&](const odec::PodArray<Eigen::Vector2d>& v, bool disp) {
        const std::uint64_t ns = v.size();
        std::string pattern(8 + 16 * ns, '\0');
        std::memcpy(&pattern[0], &ns, 8);
        if (ns > 0) std::memcpy(&pattern[8], v.data(), 16 * ns);
        const size_t at = file.find(pattern, from);
        if (at == std::string::npos) return false;
        std::string wide(8 + 24 * ns, '\0');
        std::memcpy(&wide[0], &ns, 8);
        for (int k = 0; k < static_cast<int>(ns); ++k) {
            const int c = cs.sub_owner(k);
            const Eigen::Vector3d w = disp ? cs.sub_shear_disp(c, k) : cs.sub_shear_stress(c, k);
            std::memcpy(&wide[8 + 24 * k], w.data(), 24);
        }
        // Before the shear displacements, format 17 had the normal stresses (read and left:
        // zeros will do; format 18 keeps none).
        std::string stresses;
        if (disp) {
            stresses.assign(8 + 8 * ns, '\0');
            std::memcpy(&stresses[0], &ns, 8);
        }
        file.replace(at, pattern.size(), stresses + wide);
        from = at + stresses.size() + wide.size();
        grow_contacts(8 * ns + stresses.size());
        return true;
    };
    if (!widen(cs.sub_us, true) || !widen(cs.sub_ss, false)) return "";
    const std::uint32_t format = 11;
    std::memcpy(&file[12], &format, 4);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i + 8 < file.size(); ++i) {
        h ^= static_cast<unsigned char>(file[i]);
        h *= 0x100000001b3ull;
    }
    std::memcpy(&file[file.size() - 8], &h, 8);
    return file;
}

} // namespace

// A file of the format before clumps restores as it was saved: the pieces are blocks of their
// own, glued across the faces between them (their joined joint set). A file of this format
// keeps its clumps, and cycles on to the same bits as the model that was never saved.
TEST(Clump, SaveFilesOldAndNew) {
    const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    const std::string base = dir + "/odec_clump_" + std::to_string(::getpid());
    Session a;
    ASSERT_TRUE(a.run("config dyn\ndamp off\npoly brick -1 3 -1 2 -1 0\n" + l_block(0, 0.001) +
                      "prop mat=1 dens=1000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40\ngrav 0 0 -10\nfix range z -1 0\n"
                      "step 50\nsave '" + base + "_new'"))
        << a.error();
    Session b;
    ASSERT_TRUE(b.run("restore '" + base + "_new'")) << b.error();
    EXPECT_EQ(b.model.blocks.clump, a.model.blocks.clump);
    ASSERT_TRUE(a.run("step 50")) << a.error();
    ASSERT_TRUE(b.run("step 50")) << b.error();
    for (int i = 0; i < a.model.blocks.size(); ++i) EXPECT_EQ(a.model.blocks.centroid[i], b.model.blocks.centroid[i]);

    // An old file: the same model as odec wrote it before clumps, its pieces glued by their
    // joined joint set (the clump ended by hand here), cycled, saved, its clump array taken out.
    Session d;
    ASSERT_TRUE(d.run("config dyn\ndamp off\npoly brick -1 3 -1 2 -1 0\n" + l_block(0, 0.001) +
                      "prop mat=1 dens=1000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40\ngrav 0 0 -10\nfix range z -1 0"))
        << d.error();
    d.model.blocks.clump.assign(d.model.blocks.size(), 0);
    ASSERT_TRUE(d.run("step 50\nsave '" + base + "_glued'")) << d.error();
    const std::string old = without_clumps(read_bytes(base + "_glued.sav"), d.model.blocks.clump, d.model.contacts);
    ASSERT_FALSE(old.empty()) << "the clump array was not found";
    write_bytes(base + "_old.sav", old);
    Session c;
    ASSERT_TRUE(c.run("restore '" + base + "_old'")) << c.error();
    EXPECT_TRUE(pieces_of_clump(c.model).empty());
    EXPECT_EQ(c.model.blocks.size(), d.model.blocks.size());
    // It cycles on as the model that wrote it, its pieces glued.
    ASSERT_TRUE(c.run("step 20")) << c.error();
    ASSERT_TRUE(d.run("step 20")) << d.error();
    for (int i = 0; i < c.model.blocks.size(); ++i) EXPECT_EQ(c.model.blocks.centroid[i], d.model.blocks.centroid[i]);
    int between = 0;
    for (int k = 0; k < c.model.contacts.size(); ++k) {
        const int x = c.model.contacts.block_a[k], y = c.model.contacts.block_b[k];
        if (!((c.model.blocks.flags[x] | c.model.blocks.flags[y]) & odec::kFixed)) {
            ++between;
            EXPECT_TRUE(c.model.contacts.joined(k));
        }
    }
    EXPECT_GE(between, 1);
    std::remove((base + "_glued.sav").c_str());
    std::remove((base + "_new.sav").c_str());
    std::remove((base + "_old.sav").c_str());
}

// Zoning a piece zones the whole clump and ends it: its pieces deform as one continuum (their
// gridpoints shared across the faces between them), as glued pieces did before clumps.
TEST(Clump, ZoningEndsTheClumpItsPiecesOneContinuum) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(l_block() + "prop mat=1 dens=1000 k=1e9 g=1e9\nprop jmat=1 jkn=1e10 jks=1e10 jfric=40")) << s.error();
    const int n = s.model.blocks.size();
    s.out.str("");
    ASSERT_TRUE(s.run("gen edge 0.5 range id 1")) << s.error();
    EXPECT_NE(s.out.str().find("zoning the other"), std::string::npos) << s.out.str();
    EXPECT_NE(s.out.str().find("zoned 1 clump"), std::string::npos) << s.out.str();
    EXPECT_TRUE(pieces_of_clump(s.model).empty());
    for (int b = 0; b < n; ++b) {
        EXPECT_TRUE(s.model.blocks.flags[b] & odec::kDeformable);
        EXPECT_EQ(s.model.blocks.body[b], s.model.blocks.body[0]);
    }
}

// 'excavate' and 'fill' take whole clumps: a rigid body does not lose a part.
TEST(Clump, ExcavateAndFillTakeTheWholeClump) {
    Session s;
    ASSERT_TRUE(s.run(l_block() + "poly brick 5 6 0 1 0 1\nprop mat=1 dens=1000\nexcavate range id 1")) << s.error();
    for (int b : pieces_of_clump(s.model)) EXPECT_TRUE(s.model.blocks.flags[b] & odec::kExcavated);
    EXPECT_FALSE(s.model.blocks.flags[s.model.blocks.size() - 1] & odec::kExcavated);
    ASSERT_TRUE(s.run("fill range id 2")) << s.error();
    for (int b = 0; b < s.model.blocks.size(); ++b) EXPECT_FALSE(s.model.blocks.flags[b] & odec::kExcavated);
}

// Spun about a pivot at its centroid, held there by a velocity boundary given to one piece:
// under gravity (acting at the centroid: no moment about it) it turns steadily in place, every
// piece's centroid on a circle about the pivot, the angle w t exactly.
TEST(Clump, SpinsInPlaceAboutItsHeldCentroid) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\ndamp off\n" + l_block() +
                      "prop mat=1 dens=1000\ngrav 0 0 -10\nset dt 1e-3\nbound xvel 0 yvel 0 zvel 0 range id 1\n"
                      "ini yrvel 1.5 range id 2\nstep 1000"))
        << s.error();
    const odec::Model& m = s.model;
    const std::vector<int> p = pieces_of_clump(m);
    const odec::ClumpBody body = odec::clump_body(m.blocks, p.data(), static_cast<int>(p.size()));
    EXPECT_LT((body.centroid - kCentroid).norm(), 1e-12);
    for (int b : p) {
        SCOPED_TRACE("piece " + std::to_string(m.blocks.id[b]));
        EXPECT_LT((odec::rotation_since_reset(m, b) - Vec3(0, 1.5, 0)).norm(), 1e-9);
        // Where the turn took its centroid, from where it was made (its displacement undone).
        const Vec3 start = m.blocks.centroid[b] - m.blocks.disp[b];
        EXPECT_LT((m.blocks.centroid[b] - (kCentroid + turn_y(start - kCentroid, 1.5))).norm(), 1e-9);
        EXPECT_LT((odec::spin_at_t(m, b) - Vec3(0, 1.5, 0)).norm(), 1e-12);
    }
}

// A tunnel cut through a piece ends the clump too.
TEST(Clump, ATunnelThroughAPieceEndsTheClump) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(l_block() + "prop mat=1 dens=1000")) << s.error();
    s.out.str("");
    ASSERT_TRUE(s.run("tunnel a (0.5,-1,2) b (0.5,2,2) radius 0.2 outer 0.4 nrad 1 nseg 1")) << s.error();
    EXPECT_NE(s.out.str().find("tunnel: the cut went through 1 clump"), std::string::npos) << s.out.str();
    EXPECT_TRUE(pieces_of_clump(s.model).empty());
}

// The stable timestep of a clump on its joints is that of one body: the stiffness of the springs
// on all its pieces over its mass, and their stiffness times the squared lever about its centroid
// over its least principal inertia.
TEST(Clump, ItsStableTimestepIsOneBodys) {
    Session s;
    ASSERT_TRUE(s.run("poly brick -1 3 -1 2 -1 0\n" + l_block() +
                      "prop mat=1 dens=1000\nprop jmat=1 jkn=1e9 jks=5e8 jfric=40\ngrav 0 0 -10\nfix range z -1 0\n"
                      "step 5"))
        << s.error();
    const odec::Model& m = s.model;
    const std::vector<int> p = pieces_of_clump(m);
    const odec::ClumpBody body = odec::clump_body(m.blocks, p.data(), static_cast<int>(p.size()));
    double kt = 0, kr = 0;
    const odec::ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const double ki = 1e9 * cs.sub_area[k];
            kt += ki;
            kr += ki * (odec::sub_point(m, c, k) - body.centroid).squaredNorm();
        }
    }
    ASSERT_GT(kt, 0);
    const double i_min = Eigen::SelfAdjointEigenSolver<odec::Mat3>(body.inertia).eigenvalues().minCoeff();
    const double expect = 2.0 / std::sqrt(std::max(kt / body.mass, kr / i_min));
    int worst = -1;
    const double limit = odec::stable_timestep_limit(m, &worst);
    EXPECT_NEAR(limit, std::max(expect, odec::contact_critical_timestep(m)), 1e-9 * expect);
    EXPECT_EQ(m.blocks.clump[worst], 2);
}
