// The contact set's normals in eight bytes (normal_code.h): close to the normal they were made
// from, unit vectors, the same code again from a decoded normal, and exact on the axes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/normal_code.h"

using odec::decode_normal;
using odec::encode_normal;
using odec::NormalCode;
using Vec3 = Eigen::Vector3d;

TEST(NormalCode, WithinTwoNanoradiansOfTheNormalEverywhere) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const Vec3 n = Vec3(g(rng), g(rng), g(rng)).normalized();
        const Vec3 d = decode_normal(encode_normal(n));
        EXPECT_NEAR(d.norm(), 1.0, 1e-15);
        worst = std::max(worst, std::atan2(n.cross(d).norm(), n.dot(d)));
    }
    EXPECT_LT(worst, 2e-9);
    EXPECT_GT(worst, 1e-11); // it is a code, not the normal itself
}

TEST(NormalCode, ADecodedNormalCodesToItsCodeAgain) {
    std::mt19937_64 rng(11);
    const std::int32_t lim = odec::kNormalCodeLimit;
    std::uniform_int_distribution<std::int32_t> any(-lim, lim);
    for (int i = 0; i < 200000; ++i) {
        NormalCode c{any(rng), any(rng)};
        if (i % 4 == 1) c.u = 0;
        if (i % 4 == 2) c.v = i % 8 < 4 ? lim : -lim;
        if (i % 16 == 3) c.u = c.v = i % 32 < 16 ? lim : -lim;
        const Vec3 n = decode_normal(c);
        NormalCode again = encode_normal(n);
        // On the fold (z = 0) or at the lower pole, one direction has two codes: the same normal.
        if (!(again == c)) {
            EXPECT_EQ(decode_normal(again), n) << c.u << " " << c.v;
            again = encode_normal(decode_normal(again));
            EXPECT_EQ(decode_normal(again), n);
        }
        EXPECT_EQ(encode_normal(decode_normal(again)), again) << c.u << " " << c.v;
    }
}

TEST(NormalCode, TheAxesAndTheirDiagonalsAreExact) {
    for (int axis = 0; axis < 3; ++axis) {
        for (double s : {1.0, -1.0}) {
            Vec3 n = Vec3::Zero();
            n[axis] = s;
            EXPECT_EQ(decode_normal(encode_normal(n)), n) << axis << " " << s;
        }
    }
    const Vec3 d = Vec3(1, -1, 0).normalized();
    EXPECT_NEAR((decode_normal(encode_normal(d)) - d).norm(), 0, 2e-16);
    // Not a direction: +z.
    EXPECT_EQ(decode_normal(encode_normal(Vec3::Zero())), Vec3::UnitZ());
    EXPECT_EQ(decode_normal(encode_normal(Vec3(NAN, 0, 1))), Vec3::UnitZ());
}
