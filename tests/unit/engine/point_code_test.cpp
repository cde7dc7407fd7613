// The sub-contacts' points in fourteen bytes (point_code.h): close to the point they were made
// from at every size, the same code again from a decoded point, and the origin and the extremes
// of the range held.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstring>
#include <random>
#include <vector>

#include "engine/point_code.h"

using odec::decode_point;
using odec::encode_point;
using odec::PointCode;
using Vec3 = Eigen::Vector3d;

TEST(PointCode, WithinHalfANanometrePerMetreAtEverySize) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> decade(-12, 12);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const Vec3 x = Vec3(g(rng), g(rng), g(rng)) * std::pow(10.0, decade(rng));
        const Vec3 y = decode_point(encode_point(x));
        worst = std::max(worst, (y - x).cwiseAbs().maxCoeff() / x.cwiseAbs().maxCoeff());
        EXPECT_EQ(encode_point(y), encode_point(x));
    }
    EXPECT_LT(worst, 4.7e-10); // half of 2^-31 of twice the largest coordinate
    EXPECT_GT(worst, 1e-12);   // it is a code, not the point itself
}

TEST(PointCode, ExactWhereTheCoordinatesAreFewBits) {
    for (const Vec3& x : {Vec3(0.5, -0.25, 1), Vec3(3, 0, 0), Vec3(-0.1875, 7, 0.125), Vec3(0, 0, 0)}) {
        EXPECT_EQ(decode_point(encode_point(x)), x);
    }
    // A coordinate that rounds up to the next power of two.
    const double below_one = std::nextafter(1.0, 0.0);
    EXPECT_EQ(decode_point(encode_point(Vec3(below_one, 0, 0))), Vec3(1, 0, 0));
}

TEST(PointCode, TheRangeOfTheModelIsHeldAndEveryCodeIsChecked) {
    const Vec3 far(1e100, -3e99, 2.5e-3);
    const PointCode p = encode_point(far);
    EXPECT_TRUE(odec::point_code_valid(p));
    EXPECT_NEAR((decode_point(p) - far).norm() / 1e100, 0, 1e-9);
    const double huge = std::numeric_limits<double>::max();
    const PointCode h = encode_point(Vec3(huge, -huge, 0));
    EXPECT_TRUE(odec::point_code_valid(h));
    EXPECT_TRUE(decode_point(h).allFinite());
    EXPECT_EQ(decode_point(encode_point(Vec3(1e-300, 0, 0))), Vec3::Zero()); // below 2^-900: the origin
    EXPECT_EQ(decode_point(encode_point(Vec3(NAN, 0, 0))), Vec3::Zero());
    PointCode bad;
    bad.m[1] = 5;
    bad.e = 2000;
    EXPECT_FALSE(odec::point_code_valid(bad));
    bad.e = 0;
    bad.m[1] = 0;
    EXPECT_TRUE(odec::point_code_valid(bad));
    bad.e = 4;
    EXPECT_FALSE(odec::point_code_valid(bad)); // the origin has one code
}

// A code with its holder's five bits (the contact set keeps a sub-contact's flags so): the same
// point whatever the bits, the bits whatever the point, and the bare code back whole, at the
// ends of the exponents' range too.
TEST(PointCode, FiveBitsBesideTheCodeLeaveThePointAlone) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> decade(-250, 300);
    std::vector<Vec3> points = {Vec3::Zero(), Vec3(1e-270, 0, -3e-271),
                                Vec3(std::numeric_limits<double>::max(), -1, 0)};
    for (int i = 0; i < 20000; ++i) points.push_back(Vec3(g(rng), g(rng), g(rng)) * std::pow(10.0, decade(rng)));
    for (const Vec3& x : points) {
        const PointCode p = encode_point(x);
        ASSERT_TRUE(odec::point_code_valid(p));
        for (unsigned tag : {0u, 1u, 17u, 31u}) {
            odec::TaggedPointCode t = odec::tagged_point(p, tag);
            EXPECT_EQ(odec::point_tag(t), tag);
            const PointCode back = odec::untagged_point(t);
            ASSERT_TRUE(back == p) << x.transpose() << " tag " << tag;
            const Vec3 d = decode_point(t), e = decode_point(p);
            ASSERT_EQ(std::memcmp(d.data(), e.data(), sizeof(double) * 3), 0);
            odec::set_point_tag(t, 31 - tag);
            EXPECT_EQ(odec::point_tag(t), 31 - tag);
            EXPECT_TRUE(odec::untagged_point(t) == p);
        }
    }
}
