// The integration of a free rigid block at the edge of what the doubles hold.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "contact_test_util.h"
#include "engine/polyhedron.h"
#include "engine/stages.h"

using namespace odec;
using namespace odec::test;

// The smallest block odec makes (its least moment of inertia times its density just a normal
// double) falls under gravity without turning. Turned off the world axes, its body inertia has
// products, so its angular acceleration comes from the general solve, whose determinant (1/27 for
// a cube's tensor scaled to a trace of 1) must not be multiplied into the block's size: that
// product is below the least double here, and its reciprocal overflows to make 0 * inf.
TEST(Integrate, TheSmallestBlockFallsWithoutTurning) {
    Model m;
    set_material(m, 1, 1.0);
    set_joint(m, 1, 1e9, 1e9, 30);
    const double side = std::pow(2.4e-307, 0.2); // side^5 / 6 = 4e-308: just above the least normal double
    const Polyhedron cube = rotated(make_brick(0, side, 0, side, 0, side), Vec3::Constant(side / 2), Vec3(1, 2, 3), 0.4);
    const int b = add_block(m, cube, 0, -1, 1);
    ASSERT_GE(b, 0);
    const Mat3& ib = m.blocks.inertia_body[b];
    ASSERT_TRUE(ib(0, 1) != 0 || ib(0, 2) != 0 || ib(1, 2) != 0) << "the general solve is not reached";
    ASSERT_TRUE(std::isnormal(ib.diagonal().minCoeff()));
    ASSERT_LT(ib.trace(), 1e-306);
    m.gravity = Vec3(0, 0, -10);
    m.settings.dynamic = true;
    const CycleResult r = run_steps(m, 10);
    EXPECT_NE(r.reason, StopReason::BlowUp) << r.message;
    ASSERT_TRUE(r.message.empty()) << r.message;
    EXPECT_EQ(m.step, 10);
    EXPECT_TRUE(m.blocks.ang_vel[b].allFinite());
    EXPECT_EQ(m.blocks.ang_vel[b].norm(), 0.0);
    // (Local damping slows the fall; what matters is that it is a fall.)
    EXPECT_TRUE(m.blocks.vel[b].allFinite());
    EXPECT_LT(m.blocks.vel[b].z(), 0.0);
}

// The world vertices that each step's refresh makes, four at a time (blocks.cpp), are the bits of
// c + R v as Eigen writes it (world_shape), for blocks of 4 to 30 vertices (whole groups of four
// and the rest), turned every way.
TEST(WorldVertices, TheRefreshGivesTheBitsOfCentroidPlusRotatedVertex) {
    odec::Model m;
    std::mt19937_64 rng(23);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(-1, 1);
    int blocks = 0, vertices = 0;
    for (int i = 0; i < 61; ++i) {
        std::vector<Vec3> points;
        const int k = 4 + i % 27;
        for (int j = 0; j < k; ++j) points.push_back(Vec3(g(rng), g(rng), g(rng)).normalized() * (1 + 0.1 * u(rng)));
        odec::Polyhedron p;
        std::string error;
        ASSERT_TRUE(odec::make_convex_hull(points, 1e-9, p, error)) << error;
        p.translate(Vec3(10 * i, u(rng) * 1e3, u(rng)));
        const int b = odec::add_block(m, p, 0, -1, 0);
        m.blocks.orientation[b] = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
        ++blocks;
    }
    odec::refresh_world_vertices(m);
    for (int b = 0; b < m.blocks.size(); ++b) {
        // The rotation matrix too, the bits of Eigen's toRotationMatrix.
        const odec::Mat3 r = m.blocks.orientation[b].toRotationMatrix();
        ASSERT_EQ(std::memcmp(r.data(), m.blocks.rotation[b].data(), sizeof(double) * 9), 0) << "block " << b;
        const odec::Polyhedron w = odec::world_shape(m, b);
        ASSERT_EQ(static_cast<int>(w.vertices.size()), m.blocks.vertex_offset[b + 1] - m.blocks.vertex_offset[b]);
        for (size_t v = 0; v < w.vertices.size(); ++v) {
            const Vec3& x = m.blocks.world_vertices[m.blocks.vertex_offset[b] + v];
            ASSERT_EQ(std::memcmp(x.data(), w.vertices[v].data(), sizeof(double) * 3), 0)
                << "block " << b << " vertex " << v << ": " << x.transpose() << " against " << w.vertices[v].transpose();
            ++vertices;
        }
    }
    EXPECT_EQ(blocks, 61); // (fifteen groups of four and one more)
    EXPECT_GT(vertices, 600);
}

// Within a cycle the rigid blocks' world vertices wait for what reads them (blocks.h,
// refresh_block_rotations): the catch-up gives the bits of the full refresh, and nothing outside
// the stages sees them behind: a function called at every step, a contact's history, the
// commands after the cycle.
TEST(WorldVertices, BehindOnlyWithinTheStages) {
    auto in_step = [](const Model& m) {
        if (m.blocks.vertices_behind) return false;
        for (int b = 0; b < m.blocks.size(); ++b) {
            const odec::Polyhedron w = odec::world_shape(m, b);
            for (size_t v = 0; v < w.vertices.size(); ++v) {
                const Vec3& x = m.blocks.world_vertices[m.blocks.vertex_offset[b] + v];
                if (std::memcmp(x.data(), w.vertices[v].data(), sizeof(double) * 3) != 0) return false;
            }
        }
        return true;
    };
    Model m;
    set_material(m, 1, 2700);
    set_joint(m, 1, 1e9, 1e9, 30);
    m.gravity = Vec3(0, 0, -10);
    m.damping.mode = odec::DampingMode::Off;
    m.settings.dyn_configured = true;
    m.settings.dynamic = true;
    m.settings.dt_fixed = 2e-5;
    add_fixed(m, odec::make_brick(-1, 6, -1, 2, -1, 0));
    for (int i = 0; i < 5; ++i) {
        const int b = odec::add_block(m, odec::make_brick(i * 1.1, i * 1.1 + 1, 0, 1, 0.001, 1.001), 0, -1, 1);
        m.blocks.ang_vel[b] = Vec3(0.3 * i, -0.2, 0.1);
    }
    ASSERT_TRUE(odec::prepare_cycle(m).empty());
    // The catch-up's bits are the refresh's.
    {
        Model y = m;
        odec::refresh_block_rotations(y);
        EXPECT_TRUE(y.blocks.vertices_behind);
        y.blocks.orientation[3] = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
        y.blocks.centroid[3] += Vec3(0.01, 0, 0);
        odec::refresh_block_rotations(y);
        EXPECT_FALSE(in_step(y));
        odec::catch_up_world_vertices(y);
        EXPECT_TRUE(in_step(y));
    }
    // A function at every step sees them in step.
    odec::CycleLimits lim;
    lim.max_steps = 400;
    int calls = 0, behind = 0;
    lim.each_step = [&](Model& x) {
        ++calls;
        if (!in_step(x)) ++behind;
        return std::string();
    };
    const odec::CycleResult r = odec::cycle(m, lim);
    EXPECT_EQ(r.reason, odec::StopReason::Steps) << r.message;
    EXPECT_EQ(calls, 400);
    EXPECT_EQ(behind, 0);
    // So do the commands after it, without a function too.
    EXPECT_TRUE(in_step(m));
    EXPECT_EQ(run_steps(m, 300).reason, odec::StopReason::Steps);
    EXPECT_TRUE(in_step(m));
    // They moved, so the test could fail.
    double turned = 0;
    for (int b = 1; b < m.blocks.size(); ++b) turned = std::max(turned, m.blocks.orientation[b].vec().norm());
    EXPECT_GT(turned, 1e-4);
}

// Integration steps the plain blocks four at a time (integrate.cpp, integrate_plain_blocks): the
// bits of the block-by-block loop, for bricks (a diagonal tensor) and hulls of any shape (the
// adjugate), at rest, landing, tumbling, under local damping and none.
TEST(BatchedBlocks, SteppingFourBlocksAtATimeGivesTheSameBits) {
    auto build = [](Model& m, odec::DampingMode mode) {
        set_material(m, 1, 2700);
        set_joint(m, 1, 1e9, 1e9, 30);
        m.gravity = Vec3(0, 0, -10);
        m.damping.mode = mode;
        m.damping.local = 0.8;
        m.settings.dyn_configured = true;
        m.settings.dynamic = true;
        m.settings.dt_fixed = 2e-5;
        add_fixed(m, odec::make_brick(-1, 12, -1, 4, -1, 0));
        std::mt19937_64 rng(31);
        std::normal_distribution<double> g;
        for (int i = 0; i < 11; ++i) {
            const double x0 = i * 1.05;
            if (i % 3 == 0) {
                odec::add_block(m, odec::make_brick(x0, x0 + 1, 0, 1, 0.001, 1.001), 0, -1, 1);
                continue;
            }
            std::vector<Vec3> points;
            for (int j = 0; j < 6 + i; ++j) points.push_back(Vec3(g(rng), g(rng), g(rng)).normalized() * 0.45);
            odec::Polyhedron p;
            std::string error;
            ASSERT_TRUE(odec::make_convex_hull(points, 1e-9, p, error)) << error;
            p.translate(Vec3(x0 + 0.5, 0.5, 0.6 + 0.1 * i));
            const int b = odec::add_block(m, p, 0, -1, 1);
            m.blocks.ang_vel[b] = Vec3(g(rng), g(rng), g(rng));
        }
    };
    for (const odec::DampingMode mode : {odec::DampingMode::Local, odec::DampingMode::Off}) {
        Model x, y;
        build(x, mode);
        build(y, mode);
        ASSERT_TRUE(odec::prepare_cycle(x).empty());
        ASSERT_TRUE(odec::prepare_cycle(y).empty());
        const bool was = odec::batched_blocks();
        odec::set_batched_blocks(true);
        const odec::CycleResult rx = run_steps(x, 3000);
        odec::set_batched_blocks(false);
        const odec::CycleResult ry = run_steps(y, 3000);
        odec::set_batched_blocks(was);
        EXPECT_EQ(rx.reason, odec::StopReason::Steps) << rx.message;
        EXPECT_EQ(ry.reason, odec::StopReason::Steps) << ry.message;
        auto same = [](const auto& a, const auto& b) {
            return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(a[0]) * a.size()) == 0;
        };
        EXPECT_TRUE(same(x.blocks.centroid, y.blocks.centroid));
        EXPECT_TRUE(same(x.blocks.orientation, y.blocks.orientation));
        EXPECT_TRUE(same(x.blocks.vel, y.blocks.vel));
        EXPECT_TRUE(same(x.blocks.ang_vel, y.blocks.ang_vel));
        EXPECT_TRUE(same(x.blocks.accel, y.blocks.accel));
        EXPECT_TRUE(same(x.blocks.ang_accel, y.blocks.ang_accel));
        // They fell, landed and turned.
        double turned = 0;
        for (int b = 1; b < x.blocks.size(); ++b) turned = std::max(turned, x.blocks.orientation[b].vec().norm());
        EXPECT_GT(turned, 0.05);
        EXPECT_LT(x.blocks.centroid[2].z(), 0.6 + 0.2);
    }
}

// The energy watch takes four plain blocks' kinetic energies and weights' work at a time
// (checks.cpp, plain_energies4): the bits of kinetic_energy and of (m g) . (c - start).
TEST(BatchedBlocks, FourBlocksEnergiesAreTheBitsOfKineticEnergy) {
    Model m;
    set_material(m, 1, 2700);
    std::mt19937_64 rng(37);
    std::normal_distribution<double> g;
    for (int i = 0; i < 16; ++i) {
        std::vector<Vec3> points;
        for (int j = 0; j < 8 + i; ++j) points.push_back(Vec3(g(rng), g(rng), g(rng)).normalized());
        odec::Polyhedron p;
        std::string error;
        ASSERT_TRUE(odec::make_convex_hull(points, 1e-9, p, error)) << error;
        p.translate(Vec3(3 * i, g(rng), g(rng)));
        const int b = i % 5 == 0 ? odec::add_block(m, odec::make_brick(3 * i, 3 * i + 1, 0, 2, 0, 0.5), 0, -1, 1)
                                 : odec::add_block(m, p, 0, -1, 1);
        m.blocks.orientation[b] = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
        m.blocks.vel[b] = Vec3(g(rng), g(rng), g(rng));
        m.blocks.ang_vel[b] = Vec3(g(rng), g(rng), g(rng)) * 3;
        if (i % 4 == 1) m.blocks.inertial_mass[b] *= 2.5; // scaled, not real
    }
    const Vec3 gravity(0.3, -1, -9.81);
    std::vector<Vec3> start = m.blocks.centroid;
    for (Vec3& c : start) c += Vec3(g(rng), g(rng), g(rng));
    int compared = 0;
    for (int b = 0; b + 4 <= m.blocks.size(); b += 4) {
        ASSERT_TRUE(odec::plain_for_energy(m.blocks, b));
        double e[4], work[4];
        ASSERT_TRUE(odec::plain_energies4(m.blocks, b, gravity, start.data(), e, work));
        for (int l = 0; l < 4; ++l) {
            const int x = b + l;
            const double want_e = odec::kinetic_energy(m.blocks, x);
            const double want_w = (m.blocks.mass[x] * gravity).dot(m.blocks.centroid[x] - start[x]);
            EXPECT_EQ(std::memcmp(&e[l], &want_e, sizeof(double)), 0) << "block " << x << ": " << e[l] << " " << want_e;
            EXPECT_EQ(std::memcmp(&work[l], &want_w, sizeof(double)), 0) << "block " << x;
            EXPECT_GT(want_e, 0);
            ++compared;
        }
    }
    EXPECT_EQ(compared, 16);
    // A block held, or moving at a speed that is not a number, is not taken four at a time.
    m.blocks.vel[5][1] = std::numeric_limits<double>::quiet_NaN();
    double e[4], work[4];
    EXPECT_FALSE(odec::plain_energies4(m.blocks, 4, gravity, start.data(), e, work));
    m.blocks.vel[5][1] = 0;
    m.blocks.ang_vel[6][2] = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(odec::plain_energies4(m.blocks, 4, gravity, start.data(), e, work));
    m.blocks.ang_vel[6][2] = 0;
    EXPECT_TRUE(odec::plain_energies4(m.blocks, 4, gravity, start.data(), e, work));
    m.blocks.vel_bc[6] = 1;
    EXPECT_FALSE(odec::plain_for_energy(m.blocks, 4));
}

// Detection's bound on how far a block can have moved since its references, four blocks at a
// time (contact_detect.cpp): the bits of the one-by-one bound, for turns from none to half a turn
// (the series and the arcsine) and moves from none to metres.
TEST(BatchedBlocks, FourBlocksMovementsAreTheBitsOfTheOneByOne) {
    Model m;
    set_material(m, 1, 2700);
    std::mt19937_64 rng(43);
    std::normal_distribution<double> g;
    const int n = 64;
    for (int i = 0; i < n; ++i) odec::add_block(m, odec::make_brick(2 * i, 2 * i + 1, 0, 1, 0, 1 + 0.1 * (i % 5)), 0, -1, 1);
    odec::ContactSet cs;
    cs.radius.assign(n, 0);
    std::vector<Vec3> ref_c(n);
    std::vector<odec::Quat> ref_q(n);
    int series = 0, arcsine = 0;
    for (int b = 0; b < n; ++b) {
        cs.radius[b] = 0.5 + 0.01 * b;
        const double scale = b % 3 == 0 ? 1e-9 : b % 3 == 1 ? 1e-4 : 1.0;
        ref_c[b] = m.blocks.centroid[b] + Vec3(g(rng), g(rng), g(rng)) * scale;
        m.blocks.orientation[b] = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
        const Vec3 turn = Vec3(g(rng), g(rng), g(rng)) * (b % 4 == 0 ? 0.0 : scale);
        ref_q[b] = (Eigen::Quaterniond(Eigen::AngleAxisd(turn.norm(), turn.norm() > 0 ? Vec3(turn.normalized()) : Vec3::UnitX())) *
                    m.blocks.orientation[b])
                       .normalized();
        const double sin_half = (m.blocks.orientation[b] * ref_q[b].conjugate()).vec().norm();
        (sin_half < 1e-3 ? series : arcsine) += 1;
    }
    for (int b = 0; b + 4 <= n; b += 4) {
        double four[4], one[4];
        odec::block_movements_for_test(cs, m.blocks, b, ref_c, ref_q, four, one);
        for (int l = 0; l < 4; ++l) {
            EXPECT_EQ(std::memcmp(&four[l], &one[l], sizeof(double)), 0) << "block " << b + l << ": " << four[l] << " " << one[l];
        }
    }
    EXPECT_GT(series, 20);
    EXPECT_GT(arcsine, 10);
}
