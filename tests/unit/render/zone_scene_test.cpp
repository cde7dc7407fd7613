// Scenes and pictures of deformable blocks: what the zone plot items put into a Scene, and
// the pixels they give. The zones are made here on a regular grid (each cube of it cut into
// six tetrahedra), so that every count and area can be known in advance.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "render/scene_builder.h"
#include "render/scene_internal.h"
#include "render/vtk_backend.h"
#include "render_test_util.h"

using namespace odec;
using namespace odec::render;

namespace {

// The brick [0, size]^3 of block `b`, zoned on an n x n x n grid: 6 n^3 zones, each cube cut
// into the six tetrahedra around its main diagonal (neighbouring cubes' faces match).
void zone_brick(Model& m, int b, int n, double x0 = 0, double size = 1.0) {
    BlockMesh mesh;
    const double h = size / n;
    auto node = [&](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) mesh.nodes.push_back(Vec3(x0 + i * h, j * h, k * h));
    std::vector<std::array<int, 4>> tets;
    const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (const auto& p : axes) {
                    int c[3] = {i, j, k};
                    std::array<int, 4> t;
                    t[0] = node(c[0], c[1], c[2]);
                    for (int s = 0; s < 3; ++s) {
                        ++c[p[s]];
                        t[s + 1] = node(c[0], c[1], c[2]);
                    }
                    const Vec3 e1 = mesh.nodes[t[1]] - mesh.nodes[t[0]], e2 = mesh.nodes[t[2]] - mesh.nodes[t[0]],
                               e3 = mesh.nodes[t[3]] - mesh.nodes[t[0]];
                    if (e1.dot(e2.cross(e3)) < 0) std::swap(t[2], t[3]);
                    tets.push_back(t);
                }
    mesh.tets.push_back(tets);
    std::vector<int> corners;
    for (const Vec3& v : world_shape(m, b).vertices) {
        corners.push_back(node(static_cast<int>(std::lround((v.x() - x0) / h)), static_cast<int>(std::lround(v.y() / h)),
                               static_cast<int>(std::lround(v.z() / h))));
    }
    mesh.corner_node.push_back(corners);
    zone_blocks(m, {b}, {0}, mesh);
}

Model zoned_cube(int n) {
    Model m;
    m.title = "Zoned cube";
    add_block(m, make_brick(0, 1, 0, 1, 0, 1), 1, -1, 1);
    zone_brick(m, 0, n);
    return m;
}

Vec3 zone_centre(const Model& m, int z) { return zone_centroid(m, z); }

// szz varies with x, so that its extremes lie on the faces x = 0 and x = 1.
void stress_along_x(Model& m) {
    for (int z = 0; z < m.zones.size(); ++z) {
        const double x = zone_centre(m, z).x();
        m.zones.stress[z] = Sym6{-2e5, -3e5, -1e6 + 8e5 * x, 1e4, 0, 0};
    }
}

int n_polygons(const PolygonLayer& l) { return static_cast<int>(l.offsets.size()) - 1; }

Vec3 polygon_normal(const PolygonLayer& l, int f) {
    Vec3 n = Vec3::Zero();
    const int a = l.offsets[f], k = l.offsets[f + 1] - a;
    for (int j = 0; j < k; ++j) {
        const Vec3& p = l.points[l.indices[a + j]];
        const Vec3& q = l.points[l.indices[a + (j + 1) % k]];
        n += p.cross(q);
    }
    return 0.5 * n; // area times unit normal
}

Vec3 polygon_centre(const PolygonLayer& l, int f) {
    Vec3 c = Vec3::Zero();
    for (int i = l.offsets[f]; i < l.offsets[f + 1]; ++i) c += l.points[l.indices[i]];
    return c / (l.offsets[f + 1] - l.offsets[f]);
}

const PolygonLayer* layer_named(const Scene& s, const std::string& name) {
    for (const auto& l : s.polygons)
        if (l.name == name) return &l;
    return nullptr;
}

void bounds_of(const PolygonLayer& l, Vec3& lo, Vec3& hi) {
    lo = Vec3::Constant(1e300);
    hi = Vec3::Constant(-1e300);
    for (const Vec3& x : l.points) {
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
}

} // namespace

TEST(ZoneScene, SurfaceIsTheBoundaryFacesFacingOutwardAndTheScaleTheirRange) {
    Model m = zoned_cube(3);
    ASSERT_EQ(m.zones.size(), 6 * 27);
    stress_along_x(m);
    PlotOptions opt;
    opt.zone_item = true;
    Scene s = begin_scene(m, opt);
    const int n = add_zones(s, m, ZoneQuantity::SZZ, opt);
    const PolygonLayer* layer = layer_named(s, "zones");
    ASSERT_NE(layer, nullptr);
    // One polygon a boundary face: 6 sides x 9 squares x 2 triangles.
    const auto faces = boundary_faces(m);
    EXPECT_EQ(faces.size(), 108u);
    EXPECT_EQ(n, static_cast<int>(faces.size()));
    EXPECT_EQ(n_polygons(*layer), static_cast<int>(faces.size()));
    ASSERT_EQ(layer->cell_scalars.size(), faces.size());
    EXPECT_TRUE(layer->point_scalars.empty());
    EXPECT_TRUE(layer->closed);
    // Each polygon turns away from its zone, and they cover the cube's surface exactly.
    double area = 0;
    for (int f = 0; f < n; ++f) {
        const Vec3 normal = polygon_normal(*layer, f);
        area += normal.norm();
        EXPECT_GT(normal.dot(polygon_centre(*layer, f) - Vec3(0.5, 0.5, 0.5)), 0) << f;
    }
    EXPECT_NEAR(area, 6.0, 1e-9);
    // The scale runs from the lowest to the highest szz of the zones on the surface.
    double lo = 1e300, hi = -1e300;
    for (const auto& [z, corner] : faces) {
        lo = std::min(lo, m.zones.stress[z][2]);
        hi = std::max(hi, m.zones.stress[z][2]);
    }
    EXPECT_DOUBLE_EQ(layer->scale.lo, lo);
    EXPECT_DOUBLE_EQ(layer->scale.hi, hi);
    EXPECT_LT(lo, -0.8e6);
    EXPECT_GT(hi, -0.4e6);
    EXPECT_EQ(layer->scale.units, "Pa");
    EXPECT_NE(layer->scale.title.find("tension +"), std::string::npos);
    // Block edges: the 12 edges of the cube, 3 segments each.
    ASSERT_EQ(s.lines.size(), 1u);
    EXPECT_EQ(s.lines[0].segments.size(), 36u);
}

TEST(ZoneScene, PrincipalStressesOfTheZonesAndTheirOrder) {
    Model m = zoned_cube(2);
    for (auto& st : m.zones.stress) st = Sym6{-1e6, -3e6, 2e5, 0, 0, 0};
    PlotOptions opt;
    for (auto [q, expected] : {std::pair{ZoneQuantity::SMin, -3e6}, {ZoneQuantity::SMid, -1e6},
                               {ZoneQuantity::SMax, 2e5}, {ZoneQuantity::SXX, -1e6}, {ZoneQuantity::SYY, -3e6}}) {
        Scene s = begin_scene(m, opt);
        ASSERT_GT(add_zones(s, m, q, opt), 0);
        for (double v : s.polygons[0].cell_scalars) ASSERT_NEAR(v, expected, 1e-6) << static_cast<int>(q);
    }
}

TEST(ZoneScene, CutGivesAClosedSurfaceWhoseSectionFillsThePlane) {
    for (const double x_cut : {0.4, 0.5}) { // between gridpoints, and through them
        Model m = zoned_cube(4);
        stress_along_x(m);
        PlotOptions opt;
        opt.cut = CutPlane{Vec3(x_cut, 0.5, 0.5), Vec3(1, 0, 0)};
        Scene s = begin_scene(m, opt);
        ASSERT_GT(add_zones(s, m, ZoneQuantity::SZZ, opt), 0);
        const PolygonLayer& layer = *layer_named(s, "zones");
        for (const Vec3& x : layer.points) EXPECT_LE(x.x(), x_cut + 1e-12);
        // The polygons on the plane face the eye and make up the whole 1 x 1 section.
        double section = 0;
        std::map<std::pair<int, int>, int> edges;
        for (int f = 0; f < n_polygons(layer); ++f) {
            const Vec3 normal = polygon_normal(layer, f);
            bool on_plane = true;
            for (int i = layer.offsets[f]; i < layer.offsets[f + 1]; ++i)
                on_plane &= std::abs(layer.points[layer.indices[i]].x() - x_cut) < 1e-12;
            if (on_plane) {
                EXPECT_GT(normal.x(), 0) << f;
                section += normal.norm();
            }
            const int a = layer.offsets[f], k = layer.offsets[f + 1] - a;
            for (int j = 0; j < k; ++j) {
                const int p = layer.indices[a + j], q = layer.indices[a + (j + 1) % k];
                edges[{std::min(p, q), std::max(p, q)}]++;
            }
        }
        EXPECT_NEAR(section, 1.0, 1e-9) << x_cut;
        // No cracks: every edge is shared by exactly two polygons.
        int open = 0;
        for (const auto& [e, count] : edges) open += count != 2;
        EXPECT_EQ(open, 0) << x_cut;
        // The section's outline is the square's perimeter, drawn once.
        double outline = 0;
        for (const auto& l : s.lines) {
            for (const auto& seg : l.segments) {
                const Vec3 a = l.points[seg[0]], b = l.points[seg[1]];
                if (std::abs(a.x() - x_cut) < 1e-3 && std::abs(b.x() - x_cut) < 1e-3) outline += (a - b).norm();
            }
        }
        EXPECT_NEAR(outline, 4.0, 1e-6) << x_cut;
        // The scale of a section is that of the zones cut: those the plane meets in a polygon
        // (a zone with one corner above and three on the plane has that face for its polygon;
        // one that only touches the plane at an edge or a corner has none).
        double lo = 1e300, hi = -1e300;
        for (int z = 0; z < m.zones.size(); ++z) {
            const auto& q = m.zones.gp[z];
            std::set<std::pair<int, int>> crossings; // (a, b): on edge a-b; (g, g): at corner g
            for (int i = 0; i < 4; ++i)
                for (int j = i + 1; j < 4; ++j) {
                    int a = q[i], b = q[j];
                    const bool above_a = m.gridpoints.pos[a].x() > x_cut, above_b = m.gridpoints.pos[b].x() > x_cut;
                    if (above_a == above_b) continue;
                    if (above_b) std::swap(a, b);
                    if (m.gridpoints.pos[b].x() == x_cut) crossings.insert({b, b});
                    else crossings.insert({std::min(a, b), std::max(a, b)});
                }
            if (crossings.size() < 3) continue;
            lo = std::min(lo, m.zones.stress[z][2]);
            hi = std::max(hi, m.zones.stress[z][2]);
        }
        EXPECT_DOUBLE_EQ(layer.scale.lo, lo) << x_cut;
        EXPECT_DOUBLE_EQ(layer.scale.hi, hi) << x_cut;
    }
}

TEST(ZoneScene, DisplacementIsPerGridpointAndMagnifyMovesTheDrawnShape) {
    Model m = zoned_cube(3);
    // The top sinks in proportion to x: 1 mm at x = 1.
    for (int g = 0; g < m.gridpoints.size(); ++g) {
        const Vec3& r = m.gridpoints.ref[g];
        m.gridpoints.disp[g] = Vec3(0, 0, -1e-3 * r.x() * r.z());
        m.gridpoints.pos[g] = r + m.gridpoints.disp[g];
    }
    Vec3 lo, hi;
    auto drawn = [&](double magnify, ZoneQuantity q) {
        PlotOptions opt;
        opt.magnify = magnify;
        Scene s = begin_scene(m, opt);
        EXPECT_GT(add_zones(s, m, q, opt), 0);
        return s;
    };
    const Scene disp = drawn(1, ZoneQuantity::Disp);
    const PolygonLayer& layer = disp.polygons[0];
    EXPECT_TRUE(layer.cell_scalars.empty());
    ASSERT_EQ(layer.point_scalars.size(), layer.points.size());
    EXPECT_DOUBLE_EQ(layer.scale.lo, 0);
    EXPECT_NEAR(layer.scale.hi, 1e-3, 1e-15);
    bounds_of(layer, lo, hi);
    EXPECT_NEAR(lo.z(), 0, 1e-15);
    EXPECT_NEAR(hi.z(), 1, 1e-15);
    // magnify 0: the shape before; magnify 100: the corner at x = 1 sinks by 0.1 m.
    bounds_of(drawn(0, ZoneQuantity::SZZ).polygons[0], lo, hi);
    EXPECT_NEAR(hi.z(), 1.0, 1e-12);
    EXPECT_NEAR(lo.z(), 0.0, 1e-12);
    const Scene big = drawn(100, ZoneQuantity::SZZ);
    Vec3 lo100, hi100;
    bounds_of(big.polygons[0], lo100, hi100);
    double top_at_x1 = -1e300;
    for (const Vec3& x : big.polygons[0].points)
        if (std::abs(x.x() - 1) < 1e-9) top_at_x1 = std::max(top_at_x1, x.z());
    EXPECT_NEAR(top_at_x1, 0.9, 1e-9);
    EXPECT_NE(big.title.find("displacements magnified x100"), std::string::npos) << big.title;
    // Block pictures and outlines of a deformable block follow the same gridpoints.
    PlotOptions opt;
    opt.magnify = 100;
    Scene blocks = begin_scene(m, opt);
    add_blocks(blocks, m, BlockColour::Disp, opt);
    ASSERT_EQ(blocks.polygons.size(), 1u);
    EXPECT_EQ(n_polygons(blocks.polygons[0]), static_cast<int>(boundary_faces(m).size()));
    EXPECT_EQ(blocks.polygons[0].point_scalars.size(), blocks.polygons[0].points.size());
    EXPECT_TRUE(blocks.polygons[0].scale.legend);
    Vec3 blo, bhi;
    bounds_of(blocks.polygons[0], blo, bhi);
    EXPECT_NEAR(blo.z(), lo100.z(), 1e-12);
    Scene outline = begin_scene(m, opt);
    add_block_outline(outline, m, opt);
    ASSERT_EQ(outline.lines.size(), 1u);
    double top_at_x1_outline = -1e300;
    for (const Vec3& x : outline.lines[0].points)
        if (std::abs(x.x() - 1) < 1e-9) top_at_x1_outline = std::max(top_at_x1_outline, x.z());
    EXPECT_NEAR(top_at_x1_outline, 0.9, 1e-9);
}

TEST(ZoneScene, RigidBlocksMoveByMagnifiedDisplacement) {
    Model m = test::brick_model(2, 1, 1);
    m.blocks.disp[1] = Vec3(0, 0, -0.01);
    m.blocks.centroid[1] += m.blocks.disp[1];
    PlotOptions opt;
    opt.magnify = 50; // the second block is drawn 0.5 m down
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, BlockColour::Disp, opt);
    Vec3 lo, hi;
    bounds_of(s.polygons[0], lo, hi);
    EXPECT_NEAR(lo.z(), -0.5, 1e-12);
    EXPECT_NEAR(hi.z(), 1.0, 1e-12);
}

TEST(ZoneScene, StateIsOneOfFiveCategories) {
    Model m = zoned_cube(2);
    const std::uint8_t states[] = {0, kShearNow | kShearPast, kTensionNow | kTensionPast,
                                   kShearNow | kTensionNow | kShearPast, kShearPast};
    for (int z = 0; z < m.zones.size(); ++z) m.zones.state[z] = states[z % 5];
    PlotOptions opt;
    Scene s = begin_scene(m, opt);
    ASSERT_GT(add_zones(s, m, ZoneQuantity::State, opt), 0);
    const PolygonLayer& layer = s.polygons[0];
    EXPECT_EQ(layer.scale.map, ColourMap::Categorical);
    EXPECT_EQ(layer.scale.categories, zone_state_names());
    EXPECT_EQ(layer.scale.categories,
              (std::vector<std::string>{"elastic", "shear now", "tension now", "shear and tension now",
                                        "yielded in the past"}));
    // As many faces of each state as there are boundary faces of zones in it.
    const auto faces = boundary_faces(m);
    ASSERT_EQ(layer.cell_scalars.size(), faces.size());
    std::map<int, int> drawn, expected;
    for (double v : layer.cell_scalars) ++drawn[static_cast<int>(v)];
    for (const auto& [z, corner] : faces) ++expected[z % 5];
    EXPECT_EQ(drawn, expected);
    EXPECT_EQ(drawn.size(), 5u);
}

TEST(ZoneScene, RangeHiddenBlocksAndNullZonesAreLeftOut) {
    Model m;
    add_block(m, make_brick(0, 1, 0, 1, 0, 1), 1, -1, 1);
    add_block(m, make_brick(2, 3, 0, 1, 0, 1), 1, -1, 1);
    add_block(m, make_brick(4, 5, 0, 1, 0, 1), 1, -1, 1);
    zone_brick(m, 0, 2, 0);
    zone_brick(m, 1, 2, 2);
    PlotOptions opt;
    EXPECT_EQ(zones_to_draw(m, opt).size(), 2u * 48);
    m.blocks.flags[1] |= kHidden;
    EXPECT_EQ(zones_to_draw(m, opt).size(), 48u);
    m.zones.model[3] = kZoneNull;
    EXPECT_EQ(zones_to_draw(m, opt).size(), 47u);
    // A range that keeps some zones: the surface of those alone, closed where they stop.
    std::vector<int> lower;
    for (int z = 0; z < 48; ++z)
        if (zone_centroid(m, z).z() < 0.5) lower.push_back(z);
    opt.zones = lower;
    Scene s = begin_scene(m, opt);
    ASSERT_GT(add_zones(s, m, ZoneQuantity::SXX, opt), 0);
    Vec3 lo, hi;
    bounds_of(s.polygons[0], lo, hi);
    EXPECT_NEAR(hi.z(), 0.5, 1e-12);
    EXPECT_NEAR(hi.x(), 1.0, 1e-12);
    // A rigid block beside zoned ones: zones leave it to add_blocks, and add_blocks leaves
    // the zoned ones to the zones when the picture has a zone item.
    PlotOptions with_zones;
    with_zones.zone_item = true;
    Scene both = begin_scene(m, with_zones);
    add_blocks(both, m, BlockColour::Group, with_zones);
    ASSERT_EQ(both.polygons.size(), 1u);
    EXPECT_EQ(n_polygons(both.polygons[0]), 6);
    Scene plain = begin_scene(m, PlotOptions());
    add_blocks(plain, m, BlockColour::Group, PlotOptions());
    ASSERT_EQ(plain.polygons.size(), 2u); // rigid faces, then the zoned block's surface
    EXPECT_TRUE(plain.polygons[0].scale.legend);
    EXPECT_FALSE(plain.polygons[1].scale.legend); // one legend for both
}

TEST(ZoneScene, PrincipalBarsAreThinnedSpreadAndColouredBySign) {
    Model m = zoned_cube(12); // 10,368 zones
    for (auto& st : m.zones.stress) st = Sym6{2e5, -5e5, -1e6, 0, 0, 0};
    PlotOptions opt;
    const PrincipalField f = principal_from_zones(m, opt, 300);
    EXPECT_EQ(f.n_sampled_from, m.zones.size());
    EXPECT_LE(f.points.size(), 300u);
    EXPECT_GE(f.points.size(), 100u);
    EXPECT_TRUE(f.by_sign);
    // Spread over the cube: every octant has some.
    int octants[8] = {};
    for (const Vec3& x : f.points) ++octants[(x.x() > 0.5) + 2 * (x.y() > 0.5) + 4 * (x.z() > 0.5)];
    for (int o : octants) EXPECT_GT(o, 5);
    for (size_t i = 0; i < f.points.size(); ++i) {
        EXPECT_NEAR(f.value[i][0], -1e6, 1e-6); // most compressive first, along z
        EXPECT_NEAR(std::abs(f.direction[i][0].z()), 1.0, 1e-12);
        EXPECT_NEAR(f.value[i][2], 2e5, 1e-6);
    }
    Scene s = begin_scene(m, opt);
    add_principal(s, f, opt);
    ASSERT_EQ(s.glyphs.size(), 1u);
    const GlyphLayer& g = s.glyphs[0];
    EXPECT_EQ(g.origins.size(), 3 * f.points.size());
    EXPECT_EQ(g.scale.categories, (std::vector<std::string>{"compression", "tension"}));
    int n_tension = 0;
    for (size_t i = 0; i < g.scalars.size(); ++i) {
        n_tension += g.scalars[i] == 1;
        EXPECT_EQ(g.scalars[i] == 1, std::abs(g.directions[i].normalized().x()) > 0.99) << i; // sxx in tension
    }
    EXPECT_EQ(n_tension, static_cast<int>(f.points.size()));
    EXPECT_NE(s.title.find("of 10368 zones"), std::string::npos) << s.title;
    // On a section, the zones the plane crosses, their bars on it.
    opt.cut = CutPlane{Vec3(0.5, 0.5, 0.5), Vec3(0, -1, 0)};
    const PrincipalField on_plane = principal_from_zones(m, opt, 300);
    EXPECT_GT(on_plane.points.size(), 50u);
    EXPECT_LT(on_plane.n_sampled_from, m.zones.size() / 5);
    for (const Vec3& x : on_plane.points) EXPECT_NEAR(x.y(), 0.5 - 0.06 * on_plane.typical_size, 1e-9);
}

TEST(ZoneScene, ThinningKeepsAllOfFewPointsAndSpreadsMany) {
    std::vector<Vec3> points{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(NAN, 0, 0)};
    double spacing = -1;
    EXPECT_EQ(detail::thin_points(points, 10, spacing), (std::vector<int>{0, 1, 2})); // not the NaN
    EXPECT_EQ(spacing, 0);
    // A 100 x 100 grid in a plane, thinned to at most 400: evenly, in both directions.
    points.clear();
    for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i) points.push_back(Vec3(0.01 * i, 0.3, 0.01 * j));
    const std::vector<int> kept = detail::thin_points(points, 400, spacing);
    EXPECT_LE(kept.size(), 400u);
    EXPECT_GE(kept.size(), 150u);
    EXPECT_GT(spacing, 0.04);
    EXPECT_LT(spacing, 0.09);
    int quadrants[4] = {};
    for (int k : kept) ++quadrants[(points[k].x() > 0.5) + 2 * (points[k].z() > 0.5)];
    for (int q : quadrants) EXPECT_GT(q, static_cast<int>(kept.size()) / 6);
}

TEST(ZoneScene, AGridpointGoneAstrayDrawsTheRest) {
    Model m = zoned_cube(3);
    stress_along_x(m);
    m.gridpoints.pos[5] = Vec3(NAN, 0, INFINITY);
    m.gridpoints.disp[7] = Vec3(NAN, NAN, NAN);
    m.zones.stress[2][0] = NAN;
    m.zones.volume[4] = NAN;
    for (const bool with_cut : {false, true}) {
        PlotOptions opt;
        opt.magnify = 10;
        if (with_cut) opt.cut = CutPlane{Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 1)};
        Scene s = begin_scene(m, opt);
        EXPECT_GT(add_zones(s, m, ZoneQuantity::SXX, opt), 0);
        add_blocks(s, m, BlockColour::Disp, opt);
        add_principal(s, principal_from_zones(m, opt, 50), opt);
        add_vectors(s, m, VectorKind::Disp, opt);
        EXPECT_TRUE(std::isfinite(s.polygons[0].scale.lo) && std::isfinite(s.polygons[0].scale.hi));
    }
}

namespace {

test::Picture draw_zones(const Scene& s, const std::string& name) {
    std::string error;
    const std::string path = test::out_dir() + "/" + name;
    EXPECT_TRUE(render_png(s, path, error)) << error;
    test::Picture pic;
    EXPECT_TRUE(test::read_png(path, pic)) << path;
    return pic;
}

// Pixels of the model (left of the legend) that pass `pred`.
template <class Pred>
int in_model(const test::Picture& pic, Pred pred) {
    int n = 0;
    for (int y = 0; y < pic.height; ++y)
        for (int x = 0; x < pic.width * 7 / 10; ++x) n += pred(pic.at(x, y));
    return n;
}

bool reddish(const Rgb& p) { return p[0] > 0.4 && p[1] < 0.35 * p[0] && p[2] < 0.35 * p[0]; }
bool bluish(const Rgb& p) { return p[2] > 0.4 && p[0] < 0.35 * p[2] && p[1] < 0.35 * p[2]; }

} // namespace

TEST(ZonePicture, StressContoursShowBothEndsOfTheScale) {
    Model m = zoned_cube(6);
    stress_along_x(m);
    PlotOptions opt;
    opt.width = 640;
    opt.height = 480;
    camera_for_view("-y", opt.camera); // the face y = 0, x across
    Scene s = begin_scene(m, opt);
    ASSERT_GT(add_zones(s, m, ZoneQuantity::SZZ, opt), 0);
    const test::Picture pic = draw_zones(s, "zone-szz.png");
    ASSERT_EQ(pic.width, 640);
    // The lowest szz (x = 0, left) in the blue end of the map, the highest (x = 1) in the red.
    EXPECT_GT(in_model(pic, bluish), 1500);
    EXPECT_GT(in_model(pic, reddish), 1500);
    int left_blue = 0, right_red = 0;
    for (int y = 0; y < pic.height; ++y)
        for (int x = 0; x < pic.width * 7 / 10; ++x) {
            left_blue += x < pic.width / 4 && bluish(pic.at(x, y));
            right_red += x > pic.width / 2 && reddish(pic.at(x, y));
        }
    EXPECT_GT(left_blue, 1000);
    EXPECT_GT(right_red, 1000);
    // The legend carries the two ends exactly.
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 0.0), 0.02), 30);
    EXPECT_GT(pic.count_near(colour_at(ColourMap::Rainbow, 1.0), 0.02), 30);
}

TEST(ZonePicture, StatesInTheirColours) {
    Model m = zoned_cube(4);
    // Shear now in the upper half, elastic below.
    for (int z = 0; z < m.zones.size(); ++z)
        m.zones.state[z] = zone_centroid(m, z).z() > 0.5 ? (kShearNow | kShearPast) : 0;
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    Scene s = begin_scene(m, opt);
    ASSERT_GT(add_zones(s, m, ZoneQuantity::State, opt), 0);
    const test::Picture pic = draw_zones(s, "zone-state.png");
    EXPECT_GT(in_model(pic, reddish), 3000);
    // Elastic zones are a pale grey blue: lit, a little darker or lighter, never saturated.
    const int pale = in_model(pic, [](const Rgb& p) {
        return p[2] > p[0] + 0.03 && p[2] > 0.35 && p[2] - p[0] < 0.25 && p[1] > 0.3;
    });
    EXPECT_GT(pale, 3000);
    // The legend shows every state's swatch.
    for (int k = 0; k < 5; ++k) EXPECT_GT(pic.count_near(category_colour(s.polygons[0].scale, k), 0.02), 50) << k;
}

TEST(ZonePicture, PrincipalStressesInCompressionAndTension) {
    Model m = zoned_cube(8);
    for (auto& st : m.zones.stress) st = Sym6{5e5, 0, -1e6, 0, 0, 0};
    PlotOptions opt;
    opt.width = 480;
    opt.height = 360;
    opt.cut = CutPlane{Vec3(0.5, 0.5, 0.5), Vec3(0, -1, 0)};
    auto dark = [](const Rgb& p) { return p[0] < 0.2 && p[1] < 0.2 && p[2] < 0.2; };
    auto magenta = [](const Rgb& p) { return p[0] > 0.5 && p[2] > 0.5 && p[1] < 0.3; };
    // Over the block edges: vertical black bars (compression along z) and horizontal
    // magenta ones (tension along x), half as long.
    Scene bare = begin_scene(m, opt);
    add_block_outline(bare, m, opt);
    add_principal(bare, principal_from_zones(m, opt), opt);
    const test::Picture alone = draw_zones(bare, "zone-principal.png");
    const int n_dark = in_model(alone, dark), n_magenta = in_model(alone, magenta);
    EXPECT_GT(n_magenta, 300);
    EXPECT_GT(n_dark, n_magenta);
    EXPECT_EQ(in_model(alone, reddish), 0);
    // Over contours they still show.
    stress_along_x(m);
    for (auto& st : m.zones.stress) st[0] = 5e5;
    Scene over = begin_scene(m, opt);
    ASSERT_GT(add_zones(over, m, ZoneQuantity::SZZ, opt), 0);
    add_principal(over, principal_from_zones(m, opt), opt);
    const test::Picture both = draw_zones(over, "zone-principal-contours.png");
    EXPECT_GT(in_model(both, magenta), n_magenta / 4); // the picture is smaller beside a legend
    EXPECT_GT(in_model(both, dark), n_dark / 4);
}
