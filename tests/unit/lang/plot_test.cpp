// `plot` and `export vtk` through the real interpreter: each picture read back as pixels,
// each exported file read back with VTK's own readers and compared with the model.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkCellData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkIdList.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "../render/render_test_util.h"
#include "plot_settings.h"
#include "render/contact_bridge.h"
#include "test_util.h"

using odec::test::Picture;
using odec::test::read_png;
using odec::test::Session;
using odec::render::ColourMap;
using odec::render::colour_at;

namespace fs = std::filesystem;

namespace {

// A fixed base, a block resting on it and a block falling onto it (still in the air after
// 300 steps): contacts with stress, and one block that moved much more than the others.
const char* kModel =
    "title 'Plot test'\n"
    "poly brick 0 4 0 2 0 1 region 1 group base\n"
    "poly brick 0.5 1.5 0.5 1.5 1 2 region 2 group top\n"
    "poly brick 2.5 3.5 0.5 1.5 1.5 2.5 region 3 group top\n"
    "prop mat=1 dens=2000\n"
    "prop jmat=1 jkn=1e8 jks=1e8 jfric=30\n"
    "grav 0 0 -10\n"
    "fix range region 1\n"
    "hist zdis 3,1,2\n"
    "hist time\n"
    "hist ncyc 10\n"
    "step 300\n";

// A fresh directory under /tmp for one test's files, removed when the tests end.
std::string temp_dir() {
    struct Made {
        std::vector<std::string> dirs;
        ~Made() {
            std::error_code ec;
            for (const auto& d : dirs) fs::remove_all(d, ec);
        }
    };
    static Made made;
    char name[] = "/tmp/odec-plot-test-XXXXXX";
    const char* dir = mkdtemp(name);
    if (!dir) return "/tmp";
    made.dirs.push_back(dir);
    return dir;
}

// A session with the model built, and its plot defaults back to the start when it ends
// (they are kept per interpreter, and a later session may sit at the same address).
struct PlotSession : Session {
    PlotSession() { EXPECT_TRUE(run(kModel)) << error(); }
    ~PlotSession() = default;
};

bool is_red(const odec::render::Rgb& c) { return c[0] > 0.6 && c[1] < 0.35 && c[2] < 0.35; }

Picture picture(const std::string& path) {
    Picture pic;
    EXPECT_TRUE(read_png(path, pic)) << path;
    return pic;
}

// The picture is drawn: the right size, many colours, and the model covering part of the
// frame but not all of it.
void expect_drawn(const Picture& pic, int width, int height, const odec::render::Rgb& background = {1, 1, 1}) {
    ASSERT_EQ(pic.width, width);
    ASSERT_EQ(pic.height, height);
    EXPECT_GT(pic.n_distinct_colours(), 20);
    const int n_background = pic.count_near(background, 0.01);
    EXPECT_LT(n_background, 0.95 * width * height);
    EXPECT_GT(n_background, 0.2 * width * height);
}

// Runs `text` in the working directory `dir`, then returns to where it was.
bool run_in(Session& s, const std::string& dir, const std::string& text) {
    const fs::path here = fs::current_path();
    fs::current_path(dir);
    const bool ok = s.run(text);
    fs::current_path(here);
    return ok;
}

} // namespace

TEST(Plot, BlockDispAloneGivesAGoodPicture) {
    PlotSession s;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("plot block file '" + dir + "/a.png' size 640 480")) << s.error();
    const Picture pic = picture(dir + "/a.png");
    expect_drawn(pic, 640, 480);
    // The falling block moved most: the high end of the map is in the model, not just the legend.
    int red_in_model = 0;
    for (int y = 0; y < pic.height; ++y)
        for (int x = 0; x < pic.width * 2 / 3; ++x) red_in_model += is_red(pic.at(x, y));
    EXPECT_GT(red_in_model, 200);
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 1.0), 0.02), 30);
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 0.0), 0.02), 30);
}

TEST(Plot, EveryBlockQuantityDraws) {
    PlotSession s;
    const std::string dir = temp_dir();
    for (const char* q : {"disp", "xdis", "ydis", "zdis", "vel", "xvel", "yvel", "zvel", "group", "material", "region"}) {
        const std::string path = dir + "/" + q + ".png";
        ASSERT_TRUE(s.run(std::string("plot block ") + q + " file '" + path + "' size 320 240")) << q << s.error();
        expect_drawn(picture(path), 320, 240);
    }
    // Groups are categories: one colour each.
    const Picture groups = picture(dir + "/group.png");
    EXPECT_GT(groups.count_near(odec::render::category_colour(0), 0.02), 30);
    EXPECT_GT(groups.count_near(odec::render::category_colour(1), 0.02), 30);
}

TEST(Plot, NumberedFilesInTheWorkingDirectory) {
    PlotSession s;
    s.interp.quiet = false;
    s.interp.echo = false;
    const std::string dir = temp_dir();
    // The next free number follows the highest one there, not the first gap.
    std::ofstream(dir + "/plot-0003.png") << "x";
    std::ofstream(dir + "/plot-notes.png") << "x";
    ASSERT_TRUE(run_in(s, dir, "plot size 200 150")) << s.error();
    EXPECT_NE(s.out.str().find("plot: wrote plot-0004.png\n"), std::string::npos) << s.out.str();
    ASSERT_TRUE(run_in(s, dir, "plot block vel size 200 150")) << s.error();
    EXPECT_NE(s.out.str().find("plot: wrote plot-0005.png\n"), std::string::npos) << s.out.str();
    expect_drawn(picture(dir + "/plot-0004.png"), 200, 150);
    expect_drawn(picture(dir + "/plot-0005.png"), 200, 150);
    EXPECT_FALSE(fs::exists(dir + "/plot-0001.png"));
}

TEST(Plot, EchoPrintsHowLongThePictureTook) {
    PlotSession s;
    s.interp.quiet = false;
    s.interp.echo = true;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("plot file '" + dir + "/t.png'")) << s.error();
    const std::string out = s.out.str();
    const auto at = out.find("plot: wrote " + dir + "/t.png in ");
    ASSERT_NE(at, std::string::npos) << out;
    EXPECT_NE(out.find(" ms (scene ", at), std::string::npos) << out;
    EXPECT_NE(out.find(" ms, render ", at), std::string::npos) << out;
}

TEST(Plot, ItemsLayerInOnePicture) {
    PlotSession s;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("plot block disp file '" + dir + "/blocks.png' size 480 360\n"
                      "plot block disp vector vel file '" + dir + "/both.png' size 480 360\n"
                      "plot vector vel block file '" + dir + "/other-order.png' size 480 360\n"
                      "plot vector file '" + dir + "/vectors.png' size 480 360"))
        << s.error();
    const Picture blocks = picture(dir + "/blocks.png"), both = picture(dir + "/both.png");
    expect_drawn(both, 480, 360);
    // Arrows over translucent blocks: the two pictures differ over a good part of the model.
    int n_different = 0;
    for (int y = 0; y < both.height; ++y)
        for (int x = 0; x < both.width; ++x) {
            const auto a = blocks.at(x, y), b = both.at(x, y);
            n_different += std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]) > 0.1;
        }
    EXPECT_GT(n_different, 2000);
    // The order typed does not matter: the same layers, the same pixels.
    const Picture other = picture(dir + "/other-order.png");
    EXPECT_EQ(other.rgb, both.rgb);
    expect_drawn(picture(dir + "/vectors.png"), 480, 360);
}

TEST(Plot, ContactItemsAndPrincipalStresses) {
    PlotSession s;
    const std::string dir = temp_dir();
    for (const char* q : {"nstress", "sstress", "ndis", "sdis", "state"}) {
        const std::string path = dir + "/contact-" + q + ".png";
        ASSERT_TRUE(s.run(std::string("plot contact ") + q + " file '" + path + "' size 400 300")) << q << s.error();
        const Picture pic = picture(path);
        ASSERT_EQ(pic.width, 400);
        EXPECT_GT(pic.count_near({1, 1, 1}, 0.01), 0.5 * 400 * 300) << q;
        EXPECT_GT(pic.n_distinct_colours(), 5) << q;
    }
    // The resting block presses on the base: the high end of the normal-stress scale shows.
    EXPECT_GT(picture(dir + "/contact-nstress.png").count_if(is_red), 100);
    // All sub-contacts of a block at rest are elastic: the first state colour (blue), in the
    // legend exactly and on the lit patch left of it.
    const Picture state = picture(dir + "/contact-state.png");
    EXPECT_GT(state.count_near(odec::render::category_colour(0), 0.02), 30);
    int blue_patch = 0;
    for (int y = 0; y < state.height; ++y)
        for (int x = 0; x < state.width * 2 / 3; ++x) {
            const auto c = state.at(x, y);
            blue_patch += c[2] > c[0] + 0.3 && c[2] > c[1] + 0.1;
        }
    EXPECT_GT(blue_patch, 500);
    ASSERT_TRUE(s.run("plot principal file '" + dir + "/principal.png' size 400 300\n"
                      "plot block material contact nstress file '" + dir + "/layered.png' size 400 300\n"
                      "plot contact range region 2 file '" + dir + "/range.png' size 400 300"))
        << s.error();
    // Compression is negative on principal bars, and only compression is drawn here: a
    // sequential map from the most compressive (its low end) to 0.
    EXPECT_GT(picture(dir + "/principal.png").count_near(colour_at(ColourMap::Rainbow, 0.0), 0.02), 30);
    expect_drawn(picture(dir + "/layered.png"), 400, 300);
    expect_drawn(picture(dir + "/range.png"), 400, 300);
}

TEST(Plot, HistoryChartsWithVs) {
    PlotSession s;
    const std::string dir = temp_dir();
    ASSERT_TRUE(run_in(s, dir,
                       "plot hist 1 file 'h1.png' size 640 420\n"
                       "plot hist 1 vs 2 file 'h2.png'\n"
                       "pl hist 2 v 1 file 'h3.png'\n"
                       "plot hist 1 2 background grey"))
        << s.error();
    const Picture pic = picture(dir + "/h1.png");
    ASSERT_EQ(pic.width, 640);
    ASSERT_EQ(pic.height, 420);
    EXPECT_GT(pic.count_near({0.122, 0.467, 0.706}, 0.03), 100); // the series line
    EXPECT_GT(pic.count_near({1, 1, 1}, 0.01), 0.5 * 640 * 420);
    for (const char* f : {"h2.png", "h3.png", "plot-0001.png"}) EXPECT_EQ(picture(dir + "/" + f).width, 1024) << f;
}

TEST(Plot, AHistoryMadeDuringTheRunIsDrawnFromItsFirstSample) {
    PlotSession s;
    const std::string dir = temp_dir();
    // History 3 made now has no sample yet: said, and left out; drawn once it has some.
    ASSERT_TRUE(run_in(s, dir, "hist zdis 3,1,2.2\nplot hist 1 3 file 'none.png' size 400 300")) << s.error();
    EXPECT_NE(s.error().find("t.dat:2:13: warning: history 3 has no samples yet: it is left out of the chart"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(picture(dir + "/none.png").width, 400);
    const size_t before = s.model.histories.sample_steps.size();
    ASSERT_TRUE(run_in(s, dir, "step 50\nplot hist 3 vs 1 file 'late.png' size 400 300")) << s.error();
    EXPECT_EQ(s.model.histories.items[2].first, static_cast<long>(before));
    EXPECT_GT(picture(dir + "/late.png").count_near({0.122, 0.467, 0.706}, 0.03), 20); // its line
}

TEST(Plot, SectionsAndViews) {
    PlotSession s;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("plot block group cut plane dip 90 dd 180 file '" + dir + "/cut.png' size 400 300\n"
                      "plot block cut plane dip 0 dd 0 origin 2,1,0.5 file '" + dir + "/plan.png' size 400 300\n"
                      "plot block view eye 10,-12,6 file '" + dir + "/eye.png' size 400 300\n"
                      "plot block view -x file '" + dir + "/side.png' size 400 300"))
        << s.error();
    for (const char* f : {"cut.png", "plan.png", "eye.png", "side.png"}) expect_drawn(picture(dir + "/" + f), 400, 300);
    // Seen from the south, the section shows the base and both top blocks in their group colours.
    const Picture cut = picture(dir + "/cut.png");
    EXPECT_GT(cut.count_near(odec::render::category_colour(0), 0.08), 5000);
    EXPECT_GT(cut.count_near(odec::render::category_colour(1), 0.08), 3000);
}

TEST(Plot, SetKeepsOptionsBetweenPlots) {
    PlotSession s;
    s.interp.quiet = false;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("plot set size 320 240 background black map viridis view -y")) << s.error();
    EXPECT_NE(s.out.str().find("plot defaults: size 320 240, view -y, background black, map viridis\n"),
              std::string::npos)
        << s.out.str();
    ASSERT_TRUE(s.run("plot file '" + dir + "/kept.png'\nplot file '" + dir + "/big.png' size 400 300")) << s.error();
    const Picture kept = picture(dir + "/kept.png");
    expect_drawn(kept, 320, 240, {0, 0, 0});
    EXPECT_GT(kept.count_near(colour_at(ColourMap::Viridis, 1.0), 0.08), 300); // the falling block
    expect_drawn(picture(dir + "/big.png"), 400, 300, {0, 0, 0}); // size for one picture, background kept
    // Options that belong to one picture do not go with 'set'.
    EXPECT_FALSE(s.run("plot set file 'x.png'"));
    EXPECT_NE(s.error().find("error: 'file' cannot go with 'set'"), std::string::npos) << s.error();
}

TEST(PlotErrors, HistoryThatDoesNotExist) {
    PlotSession s;
    EXPECT_FALSE(s.run("plot hist 1 vs 7"));
    EXPECT_EQ(s.error(),
              "t.dat:1:16: error: there is no history 7 (there are 2)\n"
              "    plot hist 1 vs 7\n"
              "                   ^\n"
              "  make histories with 'hist', e.g. 'hist zdis 0,0,1'\n"
              "  see 'help plot'\n");
}

TEST(PlotErrors, NothingToPlot) {
    Session s;
    EXPECT_FALSE(s.run("plot block zdis"));
    EXPECT_EQ(s.error(),
              "t.dat:1:1: error: there are no blocks to plot\n"
              "    plot block zdis\n"
              "    ^~~~\n"
              "  make blocks first, e.g. 'poly brick 0 1 0 1 0 1'\n"
              "  see 'help plot'\n");
    s.interp.plot = odec::PlotSettings();
}

TEST(PlotErrors, FileNotWritableAndUnknownItem) {
    PlotSession s;
    EXPECT_FALSE(s.run("plot file '/no/such/dir/a.png'"));
    EXPECT_NE(s.error().find("t.dat:1:11: error: cannot write '/no/such/dir/a.png': there is no directory "
                             "'/no/such/dir'\n"),
              std::string::npos)
        << s.error();
    Session t;
    EXPECT_FALSE(t.run("plot stress sxx"));
    EXPECT_NE(t.error().find("error: unknown keyword 'stress' for 'plot'"), std::string::npos) << t.error();
    EXPECT_NE(t.error().find("see 'help plot'"), std::string::npos) << t.error();
    Session u;
    EXPECT_FALSE(u.run("poly brick 0 1 0 1 0 1\nplot contact"));
    EXPECT_NE(u.error().find("error: there are no contacts to plot"), std::string::npos) << u.error();
    Session v;
    EXPECT_FALSE(v.run("poly brick 0 1 0 1 0 1\nplot view eye"));
    EXPECT_NE(v.error().find("error: 'view eye' needs the eye point x,y,z"), std::string::npos) << v.error();
}

// A deformable cube zoned by 'gen edge', the west half of its top pressed down (the brief's
// model, coarser): stresses that vary, and a top that sinks where it is pressed.
const char* kZoneModel =
    "title 'Zone plot test'\n"
    "poly brick 0 1 0 1 0 1\n"
    "prop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
    "gen edge 0.2\n"
    "bound zvel 0 range z -0.001 0.001\n"
    "bound xvel 0 range x -0.001 0.001\n"
    "bound yvel 0 range y -0.001 0.001\n"
    "bound stress 0 0 -1e6 0 0 0 range z 0.999 1.001 x 0 0.5\n"
    "step 300\n";

struct ZoneSession : Session {
    ZoneSession() { EXPECT_TRUE(run(kZoneModel)) << error(); }
};

bool bluish(const odec::render::Rgb& c) { return c[2] > 0.4 && c[0] < 0.35 * c[2] && c[1] < 0.35 * c[2]; }

// Pixels that differ between two pictures of the same size.
int n_different(const Picture& a, const Picture& b) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const auto p = a.at(x, y), q = b.at(x, y);
            n += std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) > 0.1;
        }
    return n;
}

TEST(PlotZones, EveryZoneQuantityAndItemDraws) {
    ZoneSession s;
    ASSERT_GT(s.model.zones.size(), 300);
    const std::string dir = temp_dir();
    for (const char* q : {"sxx", "syy", "szz", "sxy", "sxz", "syz", "smin", "smid", "smax", "state", "disp"}) {
        const std::string path = dir + "/" + q + ".png";
        ASSERT_TRUE(s.run(std::string("plot zone ") + q + " file '" + path + "' size 320 240")) << q << s.error();
        expect_drawn(picture(path), 320, 240);
    }
    for (const char* items : {"zone szz cut plane dip 90 dd 180", "zone smin principal cut plane dip 90 dd 90",
                              "principal", "zone state principal", "block disp magnify 1000 vector disp",
                              "block group", "vector vel cut plane dip 0 dd 0 origin 0.5,0.5,0.5",
                              "zone disp range x 0 0.5 magnify 500", "zone sxz block vector"}) {
        const std::string path = dir + "/items.png";
        ASSERT_TRUE(s.run(std::string("plot ") + items + " file '" + path + "' size 320 240")) << items << s.error();
        expect_drawn(picture(path), 320, 240);
    }
}

TEST(PlotZones, PressedHalfIsTheCompressedEndOfTheScale) {
    ZoneSession s;
    const std::string dir = temp_dir();
    // Seen from the south with x across: the pressed west half (left) is the most compressive,
    // the blue end of the map; the east half (right) the least, the red end.
    ASSERT_TRUE(s.run("plot zone szz view -y file '" + dir + "/szz.png' size 640 480")) << s.error();
    const Picture pic = picture(dir + "/szz.png");
    int blue_left = 0, blue_right = 0, red_left = 0, red_right = 0;
    for (int y = 0; y < pic.height; ++y)
        for (int x = 0; x < pic.width * 7 / 10; ++x) {
            const auto c = pic.at(x, y);
            (x < pic.width * 35 / 100 ? blue_left : blue_right) += bluish(c);
            (x < pic.width * 35 / 100 ? red_left : red_right) += is_red(c);
        }
    EXPECT_GT(blue_left, 2000);
    EXPECT_GT(blue_left, 5 * blue_right);
    EXPECT_GT(red_right, 2000);
    EXPECT_GT(red_right, 5 * red_left);
    // A section shows the same: the plane through the middle, seen from the south.
    ASSERT_TRUE(s.run("plot zone szz cut plane dip 90 dd 180 file '" + dir + "/cut.png' size 640 480")) << s.error();
    EXPECT_GT(picture(dir + "/cut.png").count_if(bluish), 2000);
}

TEST(PlotZones, MagnifyChangesTheDrawnShape) {
    ZoneSession s;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("plot zone disp view -y magnify 0 file '" + dir + "/m0.png' size 480 360\n"
                      "plot zone disp view -y file '" + dir + "/m1.png' size 480 360\n"
                      "plot zone disp view -y magnify 3000 file '" + dir + "/m3000.png' size 480 360"))
        << s.error();
    const Picture m0 = picture(dir + "/m0.png"), m1 = picture(dir + "/m1.png"), m3000 = picture(dir + "/m3000.png");
    // The displacements are a fraction of a millimetre: at true scale the shape is the
    // original one but for the title; magnified, the pressed half of the top sinks visibly.
    EXPECT_GT(n_different(m0, m3000), 2000);
    EXPECT_GT(n_different(m1, m3000), 2000);
    // The top edge of the drawing, west (left) and east: level before, lower in the west after.
    auto top_row = [](const Picture& p, int x) {
        for (int y = p.height - 1; y >= 0; --y) {
            const auto c = p.at(x, y);
            if (c[0] + c[1] + c[2] < 2.7 && y < p.height * 85 / 100) return y;
        }
        return -1;
    };
    const int west = m0.width / 6, east = m0.width * 9 / 20;
    EXPECT_NEAR(top_row(m0, west), top_row(m0, east), 2);
    EXPECT_LT(top_row(m3000, west), top_row(m3000, east) - 5);
}

TEST(PlotErrors, ZonesOnAModelWithoutThem) {
    Session s;
    EXPECT_FALSE(s.run("poly brick 0 1 0 1 0 1\nplot zone szz"));
    EXPECT_EQ(s.error(),
              "t.dat:2:6: error: there are no zones to plot: 'zone' draws the zones of deformable blocks\n"
              "    plot zone szz\n"
              "         ^~~~\n"
              "  divide blocks into zones with 'gen edge e'\n"
              "  see 'help plot'\n");
    ZoneSession hidden;
    EXPECT_FALSE(hidden.run("hide\nplot zone"));
    EXPECT_NE(hidden.error().find("t.dat:2:6: error: there are no zones to plot: their blocks are hidden"),
              std::string::npos)
        << hidden.error();
    // 'principal' with a range that keeps no zones falls back on contacts, and there are none.
    Session p;
    EXPECT_FALSE(p.run("poly brick 0 1 0 1 0 1\npoly brick 2 3 0 1 0 1\ngen edge 0.3 range x 0 1\n"
                       "plot principal range x 2 3"));
    EXPECT_NE(p.error().find("t.dat:4:16: error: the range selects no zones or contacts for 'principal'"),
              std::string::npos)
        << p.error();
    ZoneSession z;
    EXPECT_FALSE(z.run("plot zone range z 5 6"));
    EXPECT_NE(z.error().find("error: the range selects no zones to plot"), std::string::npos) << z.error();
    ZoneSession h;
    EXPECT_FALSE(h.run("hist time\nstep 10\nplot hist 1 magnify 10"));
    EXPECT_NE(h.error().find("error: 'magnify' cannot go with 'history'"), std::string::npos) << h.error();
    ZoneSession m;
    EXPECT_FALSE(m.run("plot zone magnify -1"));
    EXPECT_NE(m.error().find("t.dat:1:19: error: "), std::string::npos) << m.error();
    EXPECT_NE(m.error().find("magnify"), std::string::npos) << m.error();
    ZoneSession q;
    EXPECT_FALSE(q.run("plot zone sigma"));
    EXPECT_NE(q.error().find("t.dat:1:11: error: "), std::string::npos) << q.error();
}

// The bridge gives the contact engine's state in the view's terms.
TEST(ContactBridge, ViewAgreesWithTheContactEngine) {
    PlotSession s;
    const odec::Model& m = s.model;
    ASSERT_GT(m.contacts.size(), 0);
    const odec::ContactView view = odec::make_contact_view(m);
    std::string error;
    ASSERT_TRUE(odec::contact_rows_valid(view.contacts, error)) << error;
    ASSERT_TRUE(odec::contact_rows_valid(view.sub_contacts, error)) << error;
    ASSERT_EQ(view.contacts.size(), m.contacts.size());
    ASSERT_EQ(view.sub_contacts.size(), m.contacts.n_subs());
    EXPECT_EQ(view.state_names, (std::vector<std::string>{"elastic", "slipping", "open", "failed"}));
    double weight = 0;
    for (int c = 0; c < view.contacts.size(); ++c) {
        const odec::ContactInfo info = odec::contact_info(m, c);
        EXPECT_EQ(view.contacts.block1[c], m.blocks.id[info.block_a]);
        EXPECT_EQ(view.contacts.block2[c], m.blocks.id[info.block_b]);
        EXPECT_DOUBLE_EQ(view.contacts.normal_stress[c], info.normal_stress);
        EXPECT_DOUBLE_EQ(view.contacts.normal_disp[c], info.normal_disp); // closure positive everywhere
        double area = 0;
        odec::Vec3 force = odec::Vec3::Zero();
        for (int k = 0; k < view.sub_contacts.size(); ++k) {
            if (view.sub_contacts.parent[k] != c) continue;
            area += view.sub_contacts.area[k];
            force += view.sub_contacts.force[k];
        }
        EXPECT_NEAR(area, view.contacts.area[c], 1e-12 * (1 + area));
        EXPECT_LT((force - view.contacts.force[c]).norm(), 1e-9 * (1 + force.norm()));
        // The force on block2 (above) from block1 (below) holds it up.
        if (info.normal_stress > 0) {
            EXPECT_GT(view.contacts.force[c].dot(info.normal), 0);
        }
        weight += view.contacts.force[c].z();
    }
    // The resting block's weight (2000 kg/m^3, 1 m^3, g = 10) is carried by its contact.
    EXPECT_NEAR(weight, 2000 * 10.0, 0.05 * 20000);
    // Only the contacts asked for, with their sub-contacts.
    const std::vector<int> first = {0};
    const odec::ContactView one = odec::make_contact_view(m, &first);
    EXPECT_EQ(one.contacts.size(), 1);
    EXPECT_EQ(one.sub_contacts.size(), m.contacts.sub_offset[1] - m.contacts.sub_offset[0]);
}

TEST(Export, VtkFilesReadBackWithTheModelsValues) {
    PlotSession s;
    s.interp.quiet = false;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("export vtk '" + dir + "/model'")) << s.error();
    const std::string step = "000300";
    const std::string vtu = dir + "/model-blocks-" + step + ".vtu", vtp = dir + "/model-contacts-" + step + ".vtp",
                      sub = dir + "/model-subcontacts-" + step + ".vtp";
    EXPECT_NE(s.out.str().find("export: wrote " + vtu + ", " + vtp + ", " + sub + ", " + dir + "/model.pvd\n"),
              std::string::npos)
        << s.out.str();
    const odec::Model& m = s.model;

    vtkNew<vtkXMLUnstructuredGridReader> blocks;
    blocks->SetFileName(vtu.c_str());
    blocks->Update();
    vtkUnstructuredGrid* grid = blocks->GetOutput();
    ASSERT_EQ(grid->GetNumberOfCells(), m.blocks.size());
    vtkDataArray* id = grid->GetCellData()->GetArray("block_id");
    vtkDataArray* disp = grid->GetCellData()->GetArray("displacement");
    vtkDataArray* group = grid->GetCellData()->GetArray("group");
    ASSERT_TRUE(id && disp && group);
    for (int b = 0; b < m.blocks.size(); ++b) {
        EXPECT_EQ(id->GetTuple1(b), m.blocks.id[b]);
        for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(disp->GetComponent(b, k), m.blocks.disp[b][k]);
    }
    EXPECT_LT(m.blocks.disp[2].z(), -0.01); // the falling block did move

    const odec::ContactView view = odec::make_contact_view(m);
    vtkNew<vtkXMLPolyDataReader> contacts;
    contacts->SetFileName(vtp.c_str());
    contacts->Update();
    vtkPolyData* poly = contacts->GetOutput();
    // A patch a contact, as plot contact draws them, with the values print contact gives.
    ASSERT_EQ(poly->GetNumberOfPolys(), m.contacts.size());
    vtkDataArray* sn = poly->GetCellData()->GetArray("normal_stress");
    vtkDataArray* ndis = poly->GetCellData()->GetArray("normal_closure");
    vtkDataArray* force = poly->GetCellData()->GetArray("force");
    vtkDataArray* b1 = poly->GetCellData()->GetArray("block1");
    ASSERT_TRUE(sn && ndis && force && b1);
    for (int c = 0; c < m.contacts.size(); ++c) {
        const odec::ContactInfo info = odec::contact_info(m, c);
        EXPECT_DOUBLE_EQ(sn->GetTuple1(c), info.normal_stress);
        EXPECT_DOUBLE_EQ(ndis->GetTuple1(c), info.normal_disp);
        EXPECT_GT(info.normal_stress, 0);
        EXPECT_EQ(b1->GetTuple1(c), m.blocks.id[info.block_a]);
        for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(force->GetComponent(c, k), view.contacts.force[c][k]);
        // The patch lies in the contact plane, around its centroid, with the contact's area.
        vtkNew<vtkIdList> ids;
        poly->GetCellPoints(c, ids);
        ASSERT_GE(ids->GetNumberOfIds(), 3);
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (vtkIdType j = 0; j < ids->GetNumberOfIds(); ++j) {
            double p[3];
            poly->GetPoint(ids->GetId(j), p);
            const Eigen::Vector3d x(p[0], p[1], p[2]);
            EXPECT_NEAR(info.normal.dot(x - info.centroid), 0.0, 1e-6);
            mean += x;
        }
        mean /= static_cast<double>(ids->GetNumberOfIds());
        EXPECT_LT((mean - info.centroid).norm(), 0.5);
    }
    // The group names travel with the block file.
    EXPECT_NE(blocks->GetOutput()->GetFieldData()->GetAbstractArray("group_names"), nullptr);

    vtkNew<vtkXMLPolyDataReader> subs;
    subs->SetFileName(sub.c_str());
    subs->Update();
    vtkPolyData* sp = subs->GetOutput();
    ASSERT_EQ(sp->GetNumberOfPoints(), m.contacts.n_subs());
    vtkDataArray* ssn = sp->GetPointData()->GetArray("normal_stress");
    vtkDataArray* sss = sp->GetPointData()->GetArray("shear_stress");
    vtkDataArray* parent = sp->GetPointData()->GetArray("contact");
    ASSERT_TRUE(ssn && sss && parent);
    for (int k = 0; k < m.contacts.n_subs(); ++k) {
        EXPECT_DOUBLE_EQ(ssn->GetTuple1(k), odec::sub_normal_stress(m, k));
        const Eigen::Vector3d ss = m.contacts.sub_shear_stress(m.contacts.sub_owner(k), k);
        for (int j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(sss->GetComponent(k, j), ss[j]);
        EXPECT_EQ(parent->GetTuple1(k), m.contacts.sub_owner(k));
    }
}

TEST(Export, BadNameFails) {
    PlotSession s;
    EXPECT_FALSE(s.run("export vtk '/no/such/dir/model'"));
    EXPECT_NE(s.error().find("t.dat:1:12: error: "), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("see 'help export'"), std::string::npos) << s.error();
}

TEST(Export, ZonesOfDeformableBlocksReadBack) {
    Session s;
    s.interp.quiet = false;
    const std::string dir = temp_dir();
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\n"
                      "prop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
                      "gen edge 0.4\n"
                      "insitu stress -1e6 -2e6 -3e6 1e5 2e5 3e5\n"
                      "export vtk '" + dir + "/zoned'"))
        << s.error();
    const odec::Model& m = s.model;
    const std::string zones = dir + "/zoned-zones-000000.vtu";
    EXPECT_NE(s.out.str().find("export: wrote " + dir + "/zoned-blocks-000000.vtu, " + zones + ", "), std::string::npos)
        << s.out.str();
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(zones.c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_GT(m.zones.size(), 5);
    ASSERT_EQ(grid->GetNumberOfCells(), m.zones.size());
    ASSERT_EQ(grid->GetNumberOfPoints(), m.gridpoints.size());
    vtkDataArray* stress = grid->GetCellData()->GetArray("stress");
    ASSERT_TRUE(stress);
    ASSERT_EQ(stress->GetNumberOfComponents(), 6);
    // What 'insitu' set (sxx syy szz sxy sxz syz), in VTK's order xx yy zz xy yz xz.
    const double expected[6] = {-1e6, -2e6, -3e6, 1e5, 3e5, 2e5};
    for (int c = 0; c < m.zones.size(); ++c) {
        for (int k = 0; k < 6; ++k) ASSERT_EQ(stress->GetComponent(c, k), expected[k]) << "zone " << c + 1;
    }

    // After some steps on a held base (the zones' stresses, out of balance with the load on
    // the top, move it), the displacement of the gridpoint nearest the top centre is the one
    // the model holds.
    ASSERT_TRUE(s.run("grav 0 0 -10\nbound zvel 0 range z -0.001 0.001\n"
                      "bound stress 0 0 -1e6 0 0 0 range z 0.999 1.001\nstep 100\nexport vtk '" + dir + "/zoned'"))
        << s.error();
    const int top = odec::find_gridpoint_near(m, Eigen::Vector3d(0.5, 0.5, 1));
    ASSERT_GE(top, 0);
    EXPECT_GT(std::abs(m.gridpoints.disp[top].z()), 1e-6);
    vtkNew<vtkXMLUnstructuredGridReader> later;
    later->SetFileName((dir + "/zoned-zones-000100.vtu").c_str());
    later->Update();
    vtkUnstructuredGrid* g = later->GetOutput();
    vtkDataArray* number = g->GetPointData()->GetArray("gridpoint");
    vtkDataArray* disp = g->GetPointData()->GetArray("displacement");
    ASSERT_TRUE(number && disp);
    int found = 0;
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i) {
        if (static_cast<int>(number->GetTuple1(i)) != top + 1) continue;
        ++found;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(disp->GetComponent(i, k), m.gridpoints.disp[top][k]);
        double p[3];
        g->GetPoint(i, p);
        EXPECT_EQ(Eigen::Vector3d(p[0], p[1], p[2]), m.gridpoints.pos[top]);
    }
    EXPECT_EQ(found, 1);
    // The stresses moved on from what was set: the cell data is the current state.
    EXPECT_NE(g->GetCellData()->GetArray("stress")->GetComponent(0, 2), -3e6);
}
