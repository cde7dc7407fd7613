#include <gtest/gtest.h>

#include "engine/polyhedron.h"

using namespace odec;

TEST(MassProperties, UnitBrick) {
    const MassProperties mp = mass_properties(make_brick(0, 1, 0, 1, 0, 1));
    EXPECT_NEAR(mp.volume, 1.0, 1e-14);
    EXPECT_NEAR((mp.centroid - Vec3(0.5, 0.5, 0.5)).norm(), 0.0, 1e-14);
    // Cube of side a: I = a^5/6 per unit density about each centroidal axis, no products.
    EXPECT_NEAR(mp.inertia(0, 0), 1.0 / 6.0, 1e-14);
    EXPECT_NEAR(mp.inertia(1, 1), 1.0 / 6.0, 1e-14);
    EXPECT_NEAR(mp.inertia(2, 2), 1.0 / 6.0, 1e-14);
    EXPECT_NEAR(mp.inertia(0, 1), 0.0, 1e-14);
}

TEST(MassProperties, OffsetRectangularBrick) {
    // 2 x 3 x 4 box far from the origin: I_xx = V (b^2 + c^2) / 12 per unit density.
    const MassProperties mp = mass_properties(make_brick(100, 102, -50, -47, 7, 11));
    const double v = 24.0;
    EXPECT_NEAR(mp.volume, v, 1e-10);
    EXPECT_NEAR((mp.centroid - Vec3(101, -48.5, 9)).norm(), 0.0, 1e-10);
    EXPECT_NEAR(mp.inertia(0, 0), v * (9 + 16) / 12.0, 1e-9);
    EXPECT_NEAR(mp.inertia(1, 1), v * (4 + 16) / 12.0, 1e-9);
    EXPECT_NEAR(mp.inertia(2, 2), v * (4 + 9) / 12.0, 1e-9);
    EXPECT_NEAR(mp.inertia(1, 2), 0.0, 1e-9);
}
