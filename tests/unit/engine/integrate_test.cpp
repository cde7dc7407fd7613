// The integration of a free rigid block at the edge of what the doubles hold.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "contact_test_util.h"
#include "engine/polyhedron.h"

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
    for (int i = 0; i < 60; ++i) {
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
        const odec::Polyhedron w = odec::world_shape(m, b);
        ASSERT_EQ(static_cast<int>(w.vertices.size()), m.blocks.vertex_offset[b + 1] - m.blocks.vertex_offset[b]);
        for (size_t v = 0; v < w.vertices.size(); ++v) {
            const Vec3& x = m.blocks.world_vertices[m.blocks.vertex_offset[b] + v];
            ASSERT_EQ(std::memcmp(x.data(), w.vertices[v].data(), sizeof(double) * 3), 0)
                << "block " << b << " vertex " << v << ": " << x.transpose() << " against " << w.vertices[v].transpose();
            ++vertices;
        }
    }
    EXPECT_EQ(blocks, 60);
    EXPECT_GT(vertices, 600);
}
