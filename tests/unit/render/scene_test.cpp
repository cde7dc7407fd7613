#include <gtest/gtest.h>

#include "render/scene.h"

TEST(Scene, DefaultIsNotAChart) {
    odec::render::Scene s;
    EXPECT_FALSE(s.is_chart());
    EXPECT_EQ(s.width, 1024);
}
