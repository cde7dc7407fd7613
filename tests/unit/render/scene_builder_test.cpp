// Scene building without drawing: what the plot items put into a Scene.
#include <gtest/gtest.h>

#include <fstream>

#include "io/csv.h"
#include "render/scene_builder.h"
#include "render_test_util.h"

using namespace odec;
using namespace odec::render;

TEST(SceneBuilder, RangeAndHiddenBlocksAreLeftOut) {
    Model m = test::brick_model(3, 1, 1);
    m.blocks.flags[1] |= kHidden;
    PlotOptions opt;
    Scene all = begin_scene(m, opt);
    add_blocks(all, m, BlockColour::Flat, opt);
    ASSERT_EQ(all.polygons.size(), 1u);
    EXPECT_EQ(all.polygons[0].offsets.size(), 2u * 6 + 1); // block 1 hidden
    EXPECT_TRUE(all.polygons[0].cell_scalars.empty());       // flat colour, no legend
    EXPECT_TRUE(all.polygons[0].closed);

    opt.blocks = std::vector<int>{0, 1};
    Scene some = begin_scene(m, opt);
    add_blocks(some, m, BlockColour::Material, opt);
    EXPECT_EQ(some.polygons[0].offsets.size(), 6u + 1);
}

TEST(SceneBuilder, InclinedCutKeepsTheBackAndClosesEachBlock) {
    const Model m = test::brick_model(4, 4, 4);
    PlotOptions opt;
    const Vec3 n = Vec3(1, -1, 0.5).normalized();
    opt.cut = CutPlane{Vec3(2, 2, 2), n};
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    ASSERT_EQ(s.polygons.size(), 1u);
    const PolygonLayer& layer = s.polygons[0];
    const double d = n.dot(Vec3(2, 2, 2));
    for (const Vec3& x : layer.points) EXPECT_LE(n.dot(x), d + 1e-9);
    // Caps lie on the plane and face the eye (their normal is +n).
    ASSERT_EQ(s.lines.size(), 1u);
    int n_caps = 0;
    for (size_t f = 0; f + 1 < layer.offsets.size(); ++f) {
        const int a = layer.indices[layer.offsets[f]], b = layer.indices[layer.offsets[f] + 1],
                  c = layer.indices[layer.offsets[f] + 2];
        bool on_plane = true;
        for (int i = layer.offsets[f]; i < layer.offsets[f + 1]; ++i)
            on_plane &= std::abs(n.dot(layer.points[layer.indices[i]]) - d) < 1e-9;
        if (!on_plane) continue;
        ++n_caps;
        const Vec3 normal = (layer.points[b] - layer.points[a]).cross(layer.points[c] - layer.points[a]);
        EXPECT_GT(normal.dot(n), 0);
    }
    EXPECT_GT(n_caps, 8);
    EXPECT_NEAR(s.camera.eye_direction.dot(n), 1.0, 1e-12);
}

TEST(SceneBuilder, PlottedHistoriesCanAlsoBeWrittenAsCsv) {
    HistorySet h;
    History a, b;
    a.kind = HistoryKind::Unbalanced;
    b.kind = HistoryKind::Time;
    for (int i = 0; i < 5; ++i) {
        h.sample_steps.push_back(i * 10);
        a.values.push_back(1.0 / (i + 1));
        b.values.push_back(0.1 * i);
    }
    h.items = {a, b};
    Scene s;
    std::string error;
    ASSERT_TRUE(add_history_chart(s, h, {1}, 2, error)) << error;
    EXPECT_EQ(s.chart.series[0].x, b.values);
    const std::string path = test::out_dir() + "/hist.csv";
    ASSERT_TRUE(write_histories_csv(h, {1}, 2, path, error)) << error;
    std::ifstream f(path);
    std::string line;
    int n_lines = 0;
    while (std::getline(f, line)) ++n_lines;
    EXPECT_EQ(n_lines, 6);
}

TEST(SceneBuilder, TitleCarriesModelTitleStepAndTime) {
    Model m;
    EXPECT_EQ(scene_title(m), "odec\nstep 0    time 0 s");
    m.title = "Cavern";
    m.step = 42;
    m.time = 1.5e-3;
    EXPECT_EQ(scene_title(m), "Cavern\nstep 42    time 0.0015 s");
}
