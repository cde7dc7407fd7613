// Pictures drawn with no display: each kind of plot, read back and checked by its pixels.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "render/scene_builder.h"
#include "render/vtk_backend.h"
#include "render_test_util.h"
#include "../time_scale.h"

using namespace odec;
using namespace odec::render;
using odec::test::Picture;

namespace {

class NoDisplay : public ::testing::Environment {
public:
    void SetUp() override { unsetenv("DISPLAY"); }
    void TearDown() override { shutdown_renderer(); }
};
const auto* const kEnvironment = ::testing::AddGlobalTestEnvironment(new NoDisplay);

std::string out_path(const std::string& name) { return test::out_dir() + "/" + name; }

Picture draw(const Scene& s, const std::string& name) {
    std::string error;
    const std::string path = out_path(name);
    EXPECT_TRUE(render_png(s, path, error)) << error;
    Picture pic;
    EXPECT_TRUE(test::read_png(path, pic)) << path;
    return pic;
}

// Reddish: the high end of the rainbow map, lit or not.
bool is_red(const Rgb& p) { return p[0] > 0.4 && p[1] < 0.5 * p[0] && p[2] < 0.5 * p[0]; }

// A wall whose top front corner moved most: the corner is in view in the iso view.
Model displaced_wall() {
    Model m = test::brick_model(4, 3, 3);
    for (int b = 0; b < m.blocks.size(); ++b) {
        const Vec3 c = m.blocks.centroid[b];
        m.blocks.disp[b] = Vec3(0.001 * c.x(), -0.0005 * c.y(), -0.002 * c.z());
    }
    m.step = 1200;
    m.time = 0.0345;
    return m;
}

} // namespace

TEST(Render, BlockDisplacementPicture) {
    const Model m = displaced_wall();
    PlotOptions opt;
    opt.width = 640;
    opt.height = 480;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    ASSERT_EQ(s.polygons.size(), 1u);
    EXPECT_EQ(s.polygons[0].offsets.size(), 36u * 6 + 1); // 36 bricks, 6 faces each
    EXPECT_NE(s.title.find("Test wall"), std::string::npos);
    EXPECT_NE(s.title.find("step 1200"), std::string::npos);

    const Picture pic = draw(s, "block-disp.png");
    ASSERT_EQ(pic.width, 640);
    ASSERT_EQ(pic.height, 480);
    EXPECT_GT(pic.n_distinct_colours(), 50);
    // The model fills a good part of the frame, not all of it.
    const int n_background = pic.count_near({1, 1, 1}, 0.01);
    EXPECT_LT(n_background, 0.85 * 640 * 480);
    EXPECT_GT(n_background, 0.2 * 640 * 480);
    // The legend shows both ends of the map unlit; the most displaced block shows the high end.
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 1.0), 0.02), 30);
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 0.0), 0.02), 30);
    int red_in_model = 0;
    for (int y = 0; y < pic.height; ++y)
        for (int x = 0; x < pic.width * 2 / 3; ++x) // left of the legend column
            red_in_model += is_red(pic.at(x, y));
    EXPECT_GT(red_in_model, 100);
}

TEST(Render, SignedComponentUsesDivergingScale) {
    // Blocks moving up and down: a diverging map centred at 0.
    Model m = displaced_wall();
    for (int b = 0; b < m.blocks.size(); ++b) m.blocks.disp[b].z() = 0.002 * (m.blocks.centroid[b].z() - 1.0);
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::ZDis, opt);
    const ColourScale& sc = s.polygons[0].scale;
    EXPECT_EQ(sc.map, ColourMap::CoolWarm);
    EXPECT_DOUBLE_EQ(sc.lo, -sc.hi);
    EXPECT_NEAR(sc.hi, 0.002 * 1.5, 1e-12);
    const Picture pic = draw(s, "block-zdis.png");
    EXPECT_GT(pic.count_near(colour_at(ColourMap::CoolWarm, 0.0), 0.02), 30);
}

TEST(Render, OneSignedComponentUsesSequentialScale) {
    // Every block settles (zdis < 0): a sequential map from the largest settlement to 0,
    // so the whole scale shows the values drawn.
    const Model m = displaced_wall();
    PlotOptions opt;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::ZDis, opt);
    const ColourScale& sc = s.polygons[0].scale;
    EXPECT_EQ(sc.map, ColourMap::Rainbow);
    EXPECT_NEAR(sc.lo, -0.002 * 2.5, 1e-12);
    EXPECT_EQ(sc.hi, 0.0);
}

TEST(Render, GroupColoursAndLegend) {
    const Model m = test::brick_model(3, 2, 2);
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Group, opt);
    const ColourScale& sc = s.polygons[0].scale;
    ASSERT_EQ(sc.categories.size(), 2u);
    EXPECT_EQ(sc.categories[0], "rock");
    EXPECT_EQ(sc.categories[1], "fill");
    const Picture pic = draw(s, "block-group.png");
    EXPECT_GT(pic.count_near(category_colour(0), 0.02), 30);
    EXPECT_GT(pic.count_near(category_colour(1), 0.02), 30);
}

TEST(Render, VectorsOverBlocks) {
    const Model m = displaced_wall();
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    Scene s = begin_scene(m, opt);
    add_block_outline(s, m, opt);
    add_vectors(s, m, VectorKind::Disp, opt);
    ASSERT_EQ(s.glyphs.size(), 1u);
    EXPECT_EQ(s.glyphs[0].origins.size(), 36u);
    EXPECT_FALSE(s.glyphs[0].scalars.empty()); // the only coloured layer: coloured, with a legend
    const Picture pic = draw(s, "vector-disp.png");
    EXPECT_GT(pic.count_if(is_red), 20);

    // Over coloured blocks the arrows go dark and the blocks translucent.
    Scene t = begin_scene(m, opt);
    add_blocks(t, m, BlockColour::Disp, opt);
    add_vectors(t, m, VectorKind::Disp, opt);
    EXPECT_TRUE(t.glyphs[0].scalars.empty());
    EXPECT_LT(t.polygons[0].opacity, 1.0);
    draw(t, "block-and-vector.png");
}

TEST(Render, CutPlaneSection) {
    const Model m = displaced_wall();
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    opt.cut = CutPlane{Vec3(0, 1.5, 0), Vec3(0, -1, 0)}; // keep y >= 1.5, look from -y
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    ASSERT_FALSE(s.polygons.empty());
    for (const Vec3& x : s.polygons[0].points) EXPECT_GE(x.y(), 1.5 - 1e-9);
    // The middle row of 12 bricks is cut (6 faces each minus... clipped faces plus a cap), and
    // the cap traces are drawn as lines.
    ASSERT_EQ(s.lines.size(), 1u);
    EXPECT_EQ(s.lines[0].segments.size(), 12u * 4);
    EXPECT_TRUE(s.camera.parallel);
    EXPECT_NEAR(s.camera.eye_direction.y(), -1.0, 1e-12);
    const Picture pic = draw(s, "block-cut.png");
    EXPECT_GT(pic.count_if(is_red), 50);
}

namespace {

ContactView four_contacts() {
    ContactView v;
    ContactRows& r = v.contacts;
    for (int i = 0; i < 4; ++i) {
        r.centroid.push_back(Vec3(1.0 + i, 0.5, 1.0));
        r.normal.push_back(Vec3(0, 0, 1));
        r.area.push_back(0.8);
        r.block1.push_back(1 + i);
        r.block2.push_back(5 + i);
        r.normal_stress.push_back(1e6 * (i + 1));
        r.shear_stress.push_back(Vec3(2e5 * i, 0, 0));
        r.normal_disp.push_back(-1e-4 * i);
        r.shear_disp.push_back(Vec3(0, 1e-3 * i, 0));
        r.force.push_back(Vec3(0, 0, -8e5 * (i + 1)));
        r.state.push_back(i % 3);
    }
    v.state_names = {"elastic", "slipping", "tension failed"};
    return v;
}

} // namespace

TEST(Render, ContactStressAndState) {
    const ContactView v = four_contacts();
    Model m;
    m.title = "Contacts";
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    opt.camera.eye_direction = Vec3(0, 0, 1);
    opt.camera.up = Vec3(0, 1, 0);
    opt.view_given = true;
    Scene s = begin_scene(m, opt);
    std::string error;
    ASSERT_TRUE(add_contacts(s, v, ContactQuantity::NormalStress, opt, error)) << error;
    ASSERT_EQ(s.polygons.size(), 1u);
    EXPECT_EQ(s.polygons[0].offsets.size(), 5u);
    EXPECT_DOUBLE_EQ(s.polygons[0].scale.hi, 4e6);
    s.labels.push_back({Vec3(2.5, 1.6, 1.0), "joint 1"});
    Picture pic = draw(s, "contact-nstress.png");
    EXPECT_GT(pic.count_if(is_red), 100);

    Scene st = begin_scene(m, opt);
    ASSERT_TRUE(add_contacts(st, v, ContactQuantity::State, opt, error)) << error;
    EXPECT_EQ(st.polygons[0].scale.categories.size(), 3u);
    pic = draw(st, "contact-state.png");
    for (int k = 0; k < 3; ++k) EXPECT_GT(pic.count_near(category_colour(k), 0.02), 30) << k;

    // On a section across the joints (the plane y = 0.5 through the patches, seen from -y, the
    // joints edge-on): each patch the plane crosses is drawn as its trace too, a band in the plane.
    PlotOptions cut = opt;
    cut.cut = CutPlane{Vec3(0, 0.5, 0), Vec3(0, -1, 0)};
    cut.camera.eye_direction = Vec3(0, -1, 0);
    cut.camera.up = Vec3(0, 0, 1);
    Scene sc = begin_scene(m, cut);
    ASSERT_TRUE(add_contacts(sc, v, ContactQuantity::NormalStress, cut, error)) << error;
    ASSERT_EQ(sc.polygons.size(), 1u);
    EXPECT_EQ(sc.polygons[0].offsets.size(), 9u); // four patches and four traces
    int on_section = 0;
    const PolygonLayer& layer = sc.polygons[0];
    for (size_t k = 0; k + 1 < layer.offsets.size(); ++k) {
        bool flat = true;
        for (int i = layer.offsets[k]; i < layer.offsets[k + 1]; ++i) flat = flat && std::abs(layer.points[layer.indices[i]].y() - 0.5) < 0.05;
        on_section += flat;
    }
    EXPECT_EQ(on_section, 4) << "a trace lies on the section";
    pic = draw(sc, "contact-nstress-section.png");
    EXPECT_GT(pic.count_if(is_red), 30);

    ContactView bad = v;
    bad.contacts.area.pop_back();
    EXPECT_FALSE(add_contacts(st, bad, ContactQuantity::NormalStress, opt, error));
    EXPECT_NE(error.find("area"), std::string::npos);
}

TEST(Render, PrincipalBarsOnContacts) {
    const ContactView v = four_contacts();
    const PrincipalField f = principal_from_contacts(v);
    ASSERT_EQ(f.points.size(), 4u);
    EXPECT_DOUBLE_EQ(f.value[3][0], -4e6); // compression negative
    Model m;
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    Scene s = begin_scene(m, opt);
    add_principal(s, f, opt);
    ASSERT_EQ(s.glyphs.size(), 1u);
    EXPECT_EQ(s.glyphs[0].shape, GlyphLayer::Shape::Bar);
    EXPECT_EQ(s.glyphs[0].origins.size(), 4u + 3u); // 4 normal bars, 3 non-zero shear bars
    const Picture pic = draw(s, "principal-contacts.png");
    EXPECT_GT(pic.count_near(colour_at(ColourMap::CoolWarm, 0.0), 0.02), 30);
}

namespace {

HistorySet two_histories() {
    HistorySet h;
    History a, b;
    a.kind = HistoryKind::ZDis;
    a.block_id = 3;
    a.point = Vec3(0.5, 0.5, 2.5);
    b.kind = HistoryKind::ZDis;
    b.block_id = 7;
    b.point = Vec3(1.5, 0.5, 2.5);
    b.label = "crown";
    for (int i = 0; i <= 100; ++i) {
        h.sample_steps.push_back(10L * i);
        a.values.push_back(-0.01 * (1 - std::exp(-i / 20.0)));
        b.values.push_back(-0.006 * (1 - std::exp(-i / 35.0)) * (1 + 0.1 * std::sin(i / 3.0)));
    }
    h.items = {a, b};
    return h;
}

} // namespace

TEST(Render, HistoryChartOfTwoHistories) {
    const HistorySet h = two_histories();
    Model m;
    m.title = "Tunnel crown";
    m.step = 1000;
    PlotOptions opt;
    opt.width = 640;
    opt.height = 420;
    Scene s = begin_scene(m, opt);
    std::string error;
    ASSERT_TRUE(add_history_chart(s, h, {1, 2}, 0, error)) << error;
    ASSERT_TRUE(s.is_chart());
    EXPECT_EQ(s.chart.series.size(), 2u);
    EXPECT_EQ(s.chart.x_label, "step");
    EXPECT_EQ(s.chart.y_label, "z displacement (m)");
    EXPECT_EQ(s.chart.series[1].name, "2: crown");
    EXPECT_EQ(s.chart.series[0].name.rfind("1: zdis", 0), 0u);
    const Picture pic = draw(s, "hist-chart.png");
    EXPECT_EQ(pic.width, 640);
    EXPECT_EQ(pic.height, 420);
    // Both series colours are drawn (the first two of the chart palette).
    EXPECT_GT(pic.count_near({0.122, 0.467, 0.706}, 0.03), 100);
    EXPECT_GT(pic.count_near({0.839, 0.153, 0.157}, 0.03), 100);
    EXPECT_GT(pic.count_near({1, 1, 1}, 0.01), 0.5 * 640 * 420);

    Scene vs = begin_scene(m, opt);
    ASSERT_TRUE(add_history_chart(vs, h, {2}, 1, error)) << error;
    EXPECT_EQ(vs.chart.x_label, "1: zdis (0.5,0.5,2.5) block 3 (m)"); // with its unit
    draw(vs, "hist-vs.png");

    EXPECT_FALSE(add_history_chart(vs, h, {3}, 0, error));
    EXPECT_EQ(error, "history 3 does not exist (there are 2 histories)");
    HistorySet empty = h;
    empty.clear_values();
    EXPECT_FALSE(add_history_chart(vs, empty, {1}, 0, error));
}

TEST(Render, SameSceneSamePixels) {
    const Model m = displaced_wall();
    const Scene s = build_block_scene(m, BlockColour::Disp, {});
    std::string error;
    const std::string a = out_path("same-a.png"), b = out_path("same-b.png");
    ASSERT_TRUE(render_png(s, a, error)) << error;
    // Something else in between must not change the next picture.
    Scene other = build_block_scene(m, BlockColour::Group, {0, 1, 2});
    other.width = 300;
    other.height = 200;
    ASSERT_TRUE(render_png(other, out_path("same-other.png"), error)) << error;
    ASSERT_TRUE(render_png(s, b, error)) << error;
    std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
    const std::string da((std::istreambuf_iterator<char>(fa)), {}), db((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_FALSE(da.empty());
    EXPECT_TRUE(da == db);
}

TEST(Render, ErrorsLeaveNoFile) {
    const Model m = displaced_wall();
    Scene s = build_block_scene(m, BlockColour::Disp, {});
    std::string error;
    EXPECT_FALSE(render_png(s, "/nonexistent-dir/x.png", error));
    EXPECT_NE(error.find("cannot write"), std::string::npos);
    Scene empty;
    EXPECT_FALSE(render_png(empty, out_path("empty.png"), error));
    EXPECT_NE(error.find("nothing to draw"), std::string::npos);
    EXPECT_NE(access(out_path("empty.png").c_str(), F_OK), 0);
    s.width = 5;
    EXPECT_FALSE(render_png(s, out_path("tiny.png"), error));
    EXPECT_NE(error.find("picture size"), std::string::npos);
}

TEST(Render, ViewPresets) {
    Camera c;
    ASSERT_TRUE(camera_for_view("-x", c));
    EXPECT_EQ(c.eye_direction, Vec3(-1, 0, 0));
    EXPECT_TRUE(c.parallel);
    ASSERT_TRUE(camera_for_view("z", c));
    EXPECT_EQ(c.up, Vec3(0, 1, 0));
    EXPECT_FALSE(camera_for_view("sideways", c));
    const Model m = displaced_wall();
    PlotOptions opt;
    opt.width = 400;
    opt.height = 300;
    for (const char* v : {"x", "-y", "z"}) {
        ASSERT_TRUE(camera_for_view(v, opt.camera));
        Scene s = begin_scene(m, opt);
        add_blocks(s, m, BlockColour::Disp, opt);
        const Picture pic = draw(s, std::string("view") + v + ".png");
        EXPECT_GT(pic.count_if(is_red), 20) << v;
    }
    opt.camera = camera_for_eye(Vec3(10, -8, 6));
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    const Picture pic = draw(s, "view-eye.png");
    EXPECT_GT(pic.count_if(is_red), 20);
}

TEST(Render, TenThousandBlocksUnderOneSecond) {
    const Model m = test::brick_model(25, 20, 20, 1.0); // 10,000 bricks
    ASSERT_EQ(m.blocks.size(), 10000);
    Model moved = m;
    for (int b = 0; b < moved.blocks.size(); ++b) moved.blocks.disp[b] = Vec3(0, 0, -1e-3 * moved.blocks.centroid[b].z());
    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    const Scene s = build_block_scene(moved, BlockColour::Disp, {});
    const double build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(render_png(s, out_path("ten-thousand-1.png"), error)) << error;
    const RenderTimes first = last_render_times();
    ASSERT_TRUE(render_png(s, out_path("ten-thousand-2.png"), error)) << error;
    const RenderTimes warm = last_render_times();
    std::printf("10,000 blocks at %dx%d: scene %.0f ms; first picture %.0f ms (context %.0f, draw %.0f, png %.0f); "
                "warm %.0f ms (build %.0f, draw %.0f, png %.0f)\n  %s\n",
                s.width, s.height, build_ms, first.total_ms, first.context_ms, first.draw_ms, first.write_ms,
                warm.total_ms, warm.build_ms, warm.draw_ms, warm.write_ms, renderer_description().c_str());
    // One second on an idle machine: the limit scales as every time limit of the tests.
    EXPECT_LT(build_ms + warm.total_ms, 1000.0 * test::time_scale());
    Picture pic;
    ASSERT_TRUE(test::read_png(out_path("ten-thousand-2.png"), pic));
    EXPECT_EQ(pic.width, 1024);
    EXPECT_EQ(pic.height, 768);
}

TEST(Render, EglContextDrawsTooWhereAvailable) {
    std::string error;
    auto probe = create_egl_context(error);
    if (!probe) GTEST_SKIP() << "no EGL here: " << error;
    probe.reset();
    set_gl_context_kind(GlContextKind::Egl);
    const Model m = displaced_wall();
    PlotOptions opt;
    opt.width = 400;
    opt.height = 300;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    const bool ok = render_png(s, out_path("egl.png"), error);
    const std::string description = renderer_description();
    set_gl_context_kind(GlContextKind::OSMesa);
    ASSERT_TRUE(ok) << error;
    EXPECT_EQ(description.rfind("EGL", 0), 0u) << description;
    Picture pic;
    ASSERT_TRUE(test::read_png(out_path("egl.png"), pic));
    EXPECT_GT(pic.count_if(is_red), 20);
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 1.0), 0.02), 10);
}

// The pictures in manual/images (copied from render-test-output by hand when they change).
TEST(Render, ManualPictures) {
    // A stepped slope of blocks, its face toppling outwards.
    Model m;
    m.title = "Stepped slope";
    const int rock = m.group_index("rock", true);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 2; ++j)
            for (int k = 0; k < 6 - i; ++k) add_block(m, make_brick(i, i + 1, 2 * j, 2 * j + 2, k, k + 1), 1, rock, 1);
    for (int b = 0; b < m.blocks.size(); ++b) {
        const Vec3 c = m.blocks.centroid[b];
        // The columns near the slope face lean out, most at their tops.
        const double w = std::max(0.0, c.x() + c.z() - 3.0) / 3.0;
        m.blocks.disp[b] = Vec3(0.012 * w * (0.4 + c.z() / 6), 0, -0.004 * w);
    }
    m.step = 24000;
    m.time = 0.96;
    PlotOptions opt;
    opt.width = 800;
    opt.height = 500;
    opt.camera.eye_direction = Vec3(1.2, -1, 0.7);
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    const Picture pic = draw(s, "manual-block-disp.png");
    EXPECT_GT(pic.count_if(is_red), 100);

    Scene v = begin_scene(m, opt);
    add_block_outline(v, m, opt);
    add_vectors(v, m, VectorKind::Disp, opt);
    draw(v, "manual-vector-disp.png");

    Model h;
    h.title = "Stepped slope";
    h.step = 24000;
    h.time = 0.96;
    HistorySet hs;
    History crest, toe;
    crest.kind = toe.kind = HistoryKind::XDis;
    crest.label = "crest x displacement";
    toe.label = "toe x displacement";
    for (int i = 0; i <= 120; ++i) {
        const double t = i / 120.0;
        hs.sample_steps.push_back(200L * i);
        crest.values.push_back(0.065 * (1 - std::exp(-4 * t)) + 0.004 * std::sin(18 * t) * std::exp(-3 * t));
        toe.values.push_back(0.018 * (1 - std::exp(-6 * t)));
    }
    hs.items = {crest, toe};
    PlotOptions copt;
    copt.width = 720;
    copt.height = 420;
    Scene c = begin_scene(h, copt);
    std::string error;
    ASSERT_TRUE(add_history_chart(c, hs, {1, 2}, 0, error)) << error;
    draw(c, "manual-hist.png");
}

TEST(Render, ContactPatchesAreUnlitWithAScaleFromTheirValues) {
    // Joint normal stresses of a model at rest are all compressive: a sequential scale
    // from 0 to the largest drawn, and patches that read the same from either side.
    ContactView view;
    for (int i = 0; i < 3; ++i) {
        view.contacts.centroid.push_back(Vec3(i, 0, 0));
        view.contacts.normal.push_back(Vec3(0, 0, 1));
        view.contacts.area.push_back(0.25);
        view.contacts.block1.push_back(1);
        view.contacts.block2.push_back(2 + i);
        view.contacts.normal_stress.push_back(1e5 * (i + 1));
        view.contacts.shear_stress.push_back(Vec3::Zero());
        view.contacts.normal_disp.push_back(1e-5 * (i + 1));
        view.contacts.shear_disp.push_back(Vec3::Zero());
        view.contacts.force.push_back(Vec3::Zero());
        view.contacts.state.push_back(0);
    }
    Model m = test::brick_model(3, 1, 1);
    PlotOptions opt;
    Scene s = begin_scene(m, opt);
    std::string error;
    ASSERT_TRUE(add_contacts(s, view, ContactQuantity::NormalStress, opt, error)) << error;
    ASSERT_EQ(s.polygons.size(), 1u);
    EXPECT_FALSE(s.polygons[0].lit);
    EXPECT_EQ(s.polygons[0].scale.map, ColourMap::Rainbow);
    EXPECT_EQ(s.polygons[0].scale.lo, 0.0);
    EXPECT_EQ(s.polygons[0].scale.hi, 3e5);
    EXPECT_NE(s.polygons[0].scale.title.find("compression +"), std::string::npos);
}

TEST(Render, SupportColoursAndIdLabels) {
    // Fixed, free and velocity-driven blocks each get their own category, and ids label
    // every block drawn.
    Model m = test::brick_model(3, 1, 1);
    m.blocks.flags[0] |= kFixed;
    m.blocks.vel_bc[2] = 1;
    PlotOptions opt;
    opt.ids = true;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Fixed, opt);
    const ColourScale& sc = s.polygons[0].scale;
    ASSERT_EQ(sc.categories.size(), 3u);
    EXPECT_EQ(sc.categories[0], "free");
    EXPECT_EQ(sc.categories[1], "fixed");
    EXPECT_EQ(sc.categories[2], "velocity given");
    ASSERT_EQ(s.labels.size(), 3u);
    EXPECT_EQ(s.labels[1].text, std::to_string(m.blocks.id[1]));
    const Picture pic = draw(s, "support.png");
    EXPECT_GT(pic.count_near(category_colour(1), 0.02), 100); // the fixed block shows
}
