// Pictures of deformable blocks, from their zones.
//
// What is drawn. A zoned block is a mesh of tetrahedra; its picture is the faces of the
// zones that lie on its surface, found as the faces that only one of the zones drawn has
// (so a range that keeps part of a block shows the inside where it stops), with each
// corner at its gridpoint. A section is the polygon in which the plane meets each
// tetrahedron it crosses (a triangle or a quadrilateral), together with the surface faces
// below the plane, clipped: the points where the plane crosses an edge are made once per
// edge and shared by every polygon that uses them, so the section and the clipped surface
// close without cracks. Everything is appended to flat arrays in one pass (no object per
// zone), which keeps a picture of a hundred thousand zones to a fraction of a second.
//
// Colour. A zone quantity (a stress) is one value per zone and colours its polygons flat,
// so the picture shows the discretization honestly; a gridpoint quantity (displacement) is a
// value per point, interpolated along an edge where a cut crosses it and across each polygon
// by the renderer, so it reads as smooth contours.
//
// Lines. Zone edges drawn on every face would turn a fine mesh black, so they are drawn only
// when the faces are few; the edges of the blocks (where two surface faces meet at an angle,
// or where two blocks meet) and the outline of each block's section are always drawn.
//
// Principal stresses are bars at zone centroids. A cube of 100,000 zones would give 300,000
// bars that hide one another, so at most about a thousand zones are taken, spread evenly
// (one per cell of a grid), and on a section those the plane crosses, their bars on it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_map>

#include "engine/blocks.h"
#include "render/scene_internal.h"

namespace odec::render {

namespace {

// Corners of the face of a zone opposite corner k, counter-clockwise seen from outside (a
// zone's corners have positive orientation: (x1 - x0) . ((x2 - x0) x (x3 - x0)) > 0).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

// Zone polygons draw their edges only when there are at most this many of them.
constexpr int kMaxPolygonsWithEdges = 5000;

std::uint64_t pair_key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

bool zone_usable(const Model& m, int z) {
    if (z < 0 || z >= m.zones.size()) return false;
    const int b = m.zones.block[z];
    if (b < 0 || b >= m.blocks.size() || !detail::shown(m, b)) return false;
    if (m.zones.model[z] == kZoneNull) return false;
    for (int g : m.zones.gp[z])
        if (g < 0 || g >= m.gridpoints.size()) return false;
    return true;
}

struct ZoneFace {
    int zone, corner;
};

// The faces of `zones` that no other of them has: the surface of what is drawn.
std::vector<ZoneFace> surface_faces(const Model& m, const std::vector<int>& zones) {
    struct Entry {
        std::array<int, 3> key;
        int zone, corner;
    };
    std::vector<Entry> all;
    all.reserve(4 * zones.size());
    for (int z : zones) {
        const auto& q = m.zones.gp[z];
        for (int k = 0; k < 4; ++k) {
            std::array<int, 3> f{q[kFace[k][0]], q[kFace[k][1]], q[kFace[k][2]]};
            std::sort(f.begin(), f.end());
            all.push_back({f, z, k});
        }
    }
    std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) {
        return a.key != b.key ? a.key < b.key : (a.zone != b.zone ? a.zone < b.zone : a.corner < b.corner);
    });
    std::vector<ZoneFace> out;
    for (size_t i = 0; i < all.size();) {
        size_t j = i + 1;
        while (j < all.size() && all[j].key == all[i].key) ++j;
        if (j == i + 1) out.push_back({all[i].zone, all[i].corner});
        i = j;
    }
    return out;
}

std::array<int, 3> face_corners(const Model& m, const ZoneFace& f) {
    const auto& q = m.zones.gp[f.zone];
    return {q[kFace[f.corner][0]], q[kFace[f.corner][1]], q[kFace[f.corner][2]]};
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

// Typical distance between neighbouring zone centroids, m.
double zone_spacing(const Model& m, const std::vector<int>& zones) {
    std::vector<double> v;
    v.reserve(zones.size());
    for (int z : zones)
        if (std::isfinite(m.zones.volume[z])) v.push_back(std::abs(m.zones.volume[z]));
    return 1.2 * std::cbrt(median(std::move(v)));
}

int zone_state_category(std::uint8_t s) {
    const bool shear = s & kShearNow, tension = s & kTensionNow;
    if (shear && tension) return 3;
    if (shear) return 1;
    if (tension) return 2;
    if (s & (kShearPast | kTensionPast)) return 4;
    return 0;
}

double zone_value(const Model& m, int z, ZoneQuantity q) {
    const Sym6& s = m.zones.stress[z];
    switch (q) {
    case ZoneQuantity::SXX: return s[0];
    case ZoneQuantity::SYY: return s[1];
    case ZoneQuantity::SZZ: return s[2];
    case ZoneQuantity::SXY: return s[3];
    case ZoneQuantity::SXZ: return s[4];
    case ZoneQuantity::SYZ: return s[5];
    case ZoneQuantity::SMin:
    case ZoneQuantity::SMid:
    case ZoneQuantity::SMax: {
        Vec3 p;
        principal_stresses(s, p);
        return p[q == ZoneQuantity::SMin ? 0 : q == ZoneQuantity::SMid ? 1 : 2];
    }
    case ZoneQuantity::State: return zone_state_category(m.zones.state[z]);
    case ZoneQuantity::Disp: return 0;
    }
    return 0;
}

// A stress field is shown over its own range, lowest to highest, so that its variation
// fills the map (a field in compression everywhere would otherwise use a corner of it);
// with the diverging map chosen, the range is centred on 0 so that white is no stress.
ColourScale stress_scale(const QuantityInfo& info, const std::vector<double>& values, const PlotOptions& opt) {
    ColourScale s;
    s.title = info.title;
    s.units = info.units;
    double lo = 0, hi = 0;
    bool first = true;
    for (double v : values) {
        if (!std::isfinite(v)) continue;
        if (first) lo = hi = v;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        first = false;
    }
    s.map = opt.map ? *opt.map : ColourMap::Rainbow;
    if (s.map == ColourMap::Categorical) s.map = ColourMap::Rainbow;
    if (opt.limits) {
        lo = opt.limits->first;
        hi = opt.limits->second;
    } else if (s.map == ColourMap::CoolWarm && lo < 0 && hi > 0) {
        const double a = std::max(-lo, hi);
        lo = -a;
        hi = a;
    }
    s.lo = lo;
    s.hi = hi;
    return s;
}

ColourScale state_scale() {
    ColourScale s;
    s.map = ColourMap::Categorical;
    s.title = "zone state";
    s.categories = zone_state_names();
    // Elastic zones recede; zones yielding now stand out, those that yielded before less so.
    s.colours = {{0.74, 0.78, 0.86}, {0.84, 0.15, 0.16}, {0.12, 0.42, 0.80}, {0.58, 0.30, 0.74}, {1.00, 0.76, 0.45}};
    s.lo = 0;
    s.hi = static_cast<double>(s.categories.size()) - 1;
    return s;
}

} // namespace

namespace detail {

std::vector<Vec3> drawn_gridpoints(const Model& m, double magnify) {
    const GridpointSet& g = m.gridpoints;
    std::vector<Vec3> out(g.pos.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = drawn_gridpoint(m, static_cast<int>(i), magnify);
    return out;
}

int append_zone_polygons(PolygonLayer& layer, ZoneLines* lines, const Model& m, const std::vector<int>& zones,
                         const std::vector<Vec3>& drawn, const std::optional<Plane>& cut, const ZonePaint& paint,
                         int* n_section) {
    const bool per_gp = paint.gp_value != nullptr;
    const int n_gp = m.gridpoints.size();
    if (layer.offsets.empty()) layer.offsets.push_back(0);
    const size_t n_before = layer.offsets.size();

    // The layer's point of each gridpoint, made when first used.
    std::vector<int> point_of(static_cast<size_t>(n_gp), -1);
    auto gp_point = [&](int g) {
        int& p = point_of[g];
        if (p < 0) {
            p = static_cast<int>(layer.points.size());
            layer.points.push_back(drawn[g]);
            if (per_gp) layer.point_scalars.push_back((*paint.gp_value)[g]);
        }
        return p;
    };
    // Signed distance of each gridpoint above the plane; > 0 is cut away.
    std::vector<double> s;
    if (cut) {
        s.resize(static_cast<size_t>(n_gp));
        for (int g = 0; g < n_gp; ++g) s[g] = cut->n.dot(drawn[g]) - cut->d;
    }
    auto above = [&](int g) { return s[g] > 0; };
    std::unordered_map<std::uint64_t, int> crossing_of;
    // The point where the plane crosses the edge from a (above) to b (below): made once per edge.
    auto crossing = [&](int a, int b) {
        if (s[b] == 0) return gp_point(b);
        const auto [it, fresh] = crossing_of.emplace(pair_key(a, b), 0);
        if (!fresh) return it->second;
        const double t = s[a] / (s[a] - s[b]);
        it->second = static_cast<int>(layer.points.size());
        layer.points.push_back(drawn[a] + t * (drawn[b] - drawn[a]));
        if (per_gp) {
            const double va = (*paint.gp_value)[a], vb = (*paint.gp_value)[b];
            layer.point_scalars.push_back(va + t * (vb - va));
        }
        return it->second;
    };
    auto end_polygon = [&](int zone) {
        layer.offsets.push_back(static_cast<int>(layer.indices.size()));
        if (!per_gp) layer.cell_scalars.push_back((*paint.zone_value)[zone]);
    };

    const std::vector<ZoneFace> faces = surface_faces(m, zones);
    std::vector<int> poly;
    for (const ZoneFace& f : faces) {
        const std::array<int, 3> c = face_corners(m, f);
        if (!cut) {
            for (int g : c) layer.indices.push_back(gp_point(g));
            end_polygon(f.zone);
            continue;
        }
        poly.clear();
        for (int j = 0; j < 3; ++j) {
            const int a = c[j], b = c[(j + 1) % 3];
            if (!above(a)) poly.push_back(gp_point(a));
            if (above(a) != above(b)) poly.push_back(above(a) ? crossing(a, b) : crossing(b, a));
        }
        poly.erase(std::unique(poly.begin(), poly.end()), poly.end());
        while (poly.size() > 1 && poly.front() == poly.back()) poly.pop_back();
        if (poly.size() < 3) continue;
        layer.indices.insert(layer.indices.end(), poly.begin(), poly.end());
        end_polygon(f.zone);
    }

    // Section edges (point pair, block) for the outline of each block's section.
    struct SectionEdge {
        int a, b, block;
        bool operator<(const SectionEdge& o) const {
            return a != o.a ? a < o.a : (b != o.b ? b < o.b : block < o.block);
        }
        bool operator==(const SectionEdge& o) const { return a == o.a && b == o.b && block == o.block; }
    };
    std::vector<SectionEdge> section_edges;
    const size_t n_surface = layer.offsets.size();
    if (cut) {
        Vec3 u, v;
        plane_axes(cut->n, u, v);
        std::vector<std::pair<double, int>> by_angle;
        for (int z : zones) {
            const auto& q = m.zones.gp[z];
            int n_above = 0;
            for (int g : q) n_above += above(g);
            if (n_above == 0 || n_above == 4) continue;
            poly.clear();
            for (const auto& e : kEdge) {
                const int a = q[e[0]], b = q[e[1]];
                if (above(a) == above(b)) continue;
                const int p = above(a) ? crossing(a, b) : crossing(b, a);
                if (std::find(poly.begin(), poly.end(), p) == poly.end()) poly.push_back(p);
            }
            if (poly.size() < 3) continue;
            Vec3 centre = Vec3::Zero();
            for (int p : poly) centre += layer.points[p];
            centre /= static_cast<double>(poly.size());
            if (!centre.allFinite()) continue; // a gridpoint gone astray: no order to sort by
            by_angle.clear();
            for (int p : poly) {
                const Vec3 r = layer.points[p] - centre;
                by_angle.push_back({std::atan2(r.dot(v), r.dot(u)), p});
            }
            std::sort(by_angle.begin(), by_angle.end());
            const int k = static_cast<int>(by_angle.size());
            for (int j = 0; j < k; ++j) {
                layer.indices.push_back(by_angle[j].second);
                if (lines) {
                    const int a = by_angle[j].second, b = by_angle[(j + 1) % k].second;
                    section_edges.push_back({std::min(a, b), std::max(a, b), m.zones.block[z]});
                }
            }
            end_polygon(z);
        }
    }
    const int n_added = static_cast<int>(layer.offsets.size() - n_before);
    if (n_section) *n_section = static_cast<int>(layer.offsets.size() - n_surface);
    if (!lines || n_added == 0) return n_added;

    // A hair towards the eye, so that lines on the section are not buried in it.
    double size = 0;
    {
        Eigen::AlignedBox3d box;
        for (size_t i = 0; i < layer.points.size(); ++i)
            if (layer.points[i].allFinite()) box.extend(layer.points[i]);
        if (!box.isEmpty()) size = box.diagonal().norm();
    }
    if (cut) {
        std::sort(section_edges.begin(), section_edges.end());
        const Vec3 lift = cut->n * (1e-4 * size);
        for (size_t i = 0; i < section_edges.size();) {
            size_t j = i + 1;
            while (j < section_edges.size() && section_edges[j] == section_edges[i]) ++j;
            if (j == i + 1) { // an edge one polygon of the block has: the outline of its section
                const int base = static_cast<int>(lines->trace.points.size());
                lines->trace.points.push_back(layer.points[section_edges[i].a] + lift);
                lines->trace.points.push_back(layer.points[section_edges[i].b] + lift);
                lines->trace.segments.push_back({base, base + 1});
            }
            i = j;
        }
    }

    // Block edges on the surface: a surface edge whose two faces meet at an angle (in the
    // geometry as zoned, so that a bent block keeps the edges it had) or belong to two blocks.
    struct SurfaceEdge {
        std::uint64_t key;
        int face;
    };
    std::vector<SurfaceEdge> edges;
    edges.reserve(3 * faces.size());
    for (size_t f = 0; f < faces.size(); ++f) {
        const std::array<int, 3> c = face_corners(m, faces[f]);
        for (int j = 0; j < 3; ++j) edges.push_back({pair_key(c[j], c[(j + 1) % 3]), static_cast<int>(f)});
    }
    std::sort(edges.begin(), edges.end(), [](const SurfaceEdge& a, const SurfaceEdge& b) {
        return a.key != b.key ? a.key < b.key : a.face < b.face;
    });
    const auto& ref = m.gridpoints.ref;
    auto ref_normal = [&](int f) {
        const std::array<int, 3> c = face_corners(m, faces[f]);
        return (ref[c[1]] - ref[c[0]]).cross(ref[c[2]] - ref[c[0]]).normalized();
    };
    const double flat = std::cos(10.0 * M_PI / 180.0);
    for (size_t i = 0; i < edges.size();) {
        size_t j = i + 1;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        bool feature = j != i + 2;
        if (!feature) {
            const int f1 = edges[i].face, f2 = edges[i + 1].face;
            feature = m.zones.block[faces[f1].zone] != m.zones.block[faces[f2].zone] ||
                      !(ref_normal(f1).dot(ref_normal(f2)) >= flat);
        }
        if (feature) {
            const int a = static_cast<int>(edges[i].key >> 32), b = static_cast<int>(edges[i].key & 0xffffffffu);
            Vec3 xa = drawn[a], xb = drawn[b];
            bool keep = true;
            if (cut) {
                if (above(a) && above(b)) keep = false;
                else if (above(a)) xa = layer.points[crossing(a, b)];
                else if (above(b)) xb = layer.points[crossing(b, a)];
            }
            if (keep) {
                const int base = static_cast<int>(lines->edges.points.size());
                lines->edges.points.push_back(xa);
                lines->edges.points.push_back(xb);
                lines->edges.segments.push_back({base, base + 1});
            }
        }
        i = j;
    }
    return n_added;
}

std::vector<int> thin_points(const std::vector<Vec3>& points, int max_points, double& spacing) {
    spacing = 0;
    std::vector<int> finite;
    finite.reserve(points.size());
    Eigen::AlignedBox3d box;
    for (size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) continue;
        finite.push_back(static_cast<int>(i));
        box.extend(points[i]);
    }
    if (max_points < 1) max_points = 1;
    if (static_cast<int>(finite.size()) <= max_points) return finite;
    const double diag = box.diagonal().norm();
    if (!(diag > 0) || !std::isfinite(diag)) return {finite.front()};
    const Vec3 lo = box.min();
    auto key_of = [&](const Vec3& x, double h, Vec3* centre) {
        std::int64_t c[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((x[k] - lo[k]) / h)), 0, (1 << 20) - 1);
            if (centre) (*centre)[k] = lo[k] + (static_cast<double>(c[k]) + 0.5) * h;
        }
        return static_cast<std::uint64_t>(c[0]) | static_cast<std::uint64_t>(c[1]) << 21 |
               static_cast<std::uint64_t>(c[2]) << 42;
    };
    // Grow the cells until they are few enough. They start at half the size that would suit
    // points filling the box, or its largest face (points on a plane), whichever is larger:
    // a few rounds at most, and the loop needs to know neither.
    const Vec3 e = box.sizes();
    const double n = static_cast<double>(max_points);
    const double face = std::max({e.x() * e.y(), e.y() * e.z(), e.z() * e.x()});
    double h = 0.5 * std::max({std::cbrt(e.prod() / n), std::sqrt(face / n), diag / n});
    std::unordered_map<std::uint64_t, std::pair<double, int>> best; // cell -> (distance to centre, point)
    best.reserve(finite.size());
    for (int round = 0; round < 60; ++round) {
        best.clear();
        for (int i : finite) {
            Vec3 centre;
            const std::uint64_t key = key_of(points[i], h, &centre);
            const double d = (points[i] - centre).squaredNorm();
            auto [it, fresh] = best.emplace(key, std::make_pair(d, i));
            if (!fresh && (d < it->second.first || (d == it->second.first && i < it->second.second)))
                it->second = {d, i};
        }
        if (static_cast<int>(best.size()) <= max_points) break;
        h *= 1.25;
    }
    spacing = h;
    std::vector<int> out;
    out.reserve(best.size());
    for (const auto& [key, v] : best) out.push_back(v.second);
    std::sort(out.begin(), out.end());
    return out;
}

VectorSamples zone_vector_samples(const Model& m, const std::vector<int>& zones, const std::vector<Vec3>& drawn,
                                  const std::vector<Vec3>& gp_vector, const std::optional<Plane>& cut,
                                  int max_points) {
    VectorSamples all;
    if (zones.empty()) return all;
    if (!cut) {
        std::vector<char> on_surface(drawn.size(), 0);
        for (const ZoneFace& f : surface_faces(m, zones))
            for (int g : face_corners(m, f)) on_surface[g] = 1;
        for (size_t g = 0; g < drawn.size(); ++g) {
            if (!on_surface[g]) continue;
            all.points.push_back(drawn[g]);
            all.vectors.push_back(gp_vector[g]);
        }
    } else {
        // One point a zone the plane crosses: the mean of where it crosses the zone's edges.
        for (int z : zones) {
            const auto& q = m.zones.gp[z];
            double s[4];
            for (int k = 0; k < 4; ++k) s[k] = cut->n.dot(drawn[q[k]]) - cut->d;
            Vec3 x = Vec3::Zero(), v = Vec3::Zero();
            int n = 0;
            for (const auto& e : kEdge) {
                const double sa = s[e[0]], sb = s[e[1]];
                if ((sa > 0) == (sb > 0)) continue;
                const double t = sa / (sa - sb);
                x += drawn[q[e[0]]] + t * (drawn[q[e[1]]] - drawn[q[e[0]]]);
                v += gp_vector[q[e[0]]] + t * (gp_vector[q[e[1]]] - gp_vector[q[e[0]]]);
                ++n;
            }
            if (n < 3) continue;
            all.points.push_back(x / n);
            all.vectors.push_back(v / n);
        }
    }
    VectorSamples out;
    const std::vector<int> keep = thin_points(all.points, max_points, out.spacing);
    for (int i : keep) {
        out.points.push_back(all.points[i]);
        out.vectors.push_back(all.vectors[i]);
    }
    if (out.spacing == 0) out.spacing = 1.5 * zone_spacing(m, zones) / 1.2;
    return out;
}

} // namespace detail

const std::vector<std::string>& zone_state_names() {
    static const std::vector<std::string> names = {"elastic", "shear now", "tension now", "shear and tension now",
                                                   "yielded in the past"};
    return names;
}

QuantityInfo zone_quantity_info(ZoneQuantity q) {
    switch (q) {
    case ZoneQuantity::SXX: return {"zone stress xx, tension +", "Pa", true};
    case ZoneQuantity::SYY: return {"zone stress yy, tension +", "Pa", true};
    case ZoneQuantity::SZZ: return {"zone stress zz, tension +", "Pa", true};
    case ZoneQuantity::SXY: return {"zone stress xy", "Pa", true};
    case ZoneQuantity::SXZ: return {"zone stress xz", "Pa", true};
    case ZoneQuantity::SYZ: return {"zone stress yz", "Pa", true};
    case ZoneQuantity::SMin: return {"minimum principal stress, tension +", "Pa", true};
    case ZoneQuantity::SMid: return {"intermediate principal stress, tension +", "Pa", true};
    case ZoneQuantity::SMax: return {"maximum principal stress, tension +", "Pa", true};
    case ZoneQuantity::State: return {"zone state", "", false};
    case ZoneQuantity::Disp: return {"displacement magnitude", "m", false};
    }
    return {};
}

std::vector<int> zones_to_draw(const Model& m, const PlotOptions& opt) {
    std::vector<int> out;
    if (opt.zones) {
        for (int z : *opt.zones)
            if (zone_usable(m, z)) out.push_back(z);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }
    std::vector<char> drawn_block(static_cast<size_t>(m.blocks.size()), 0);
    for (int b : detail::blocks_to_draw(m, opt)) drawn_block[b] = 1;
    for (int z = 0; z < m.zones.size(); ++z) {
        const int b = m.zones.block[z];
        if (b >= 0 && b < m.blocks.size() && drawn_block[b] && zone_usable(m, z)) out.push_back(z);
    }
    return out;
}

int add_zones(Scene& scene, const Model& m, ZoneQuantity q, const PlotOptions& opt) {
    const std::vector<int> zones = zones_to_draw(m, opt);
    if (zones.empty()) return 0;
    const std::vector<Vec3> drawn = detail::drawn_gridpoints(m, opt.magnify);
    PolygonLayer layer;
    layer.name = "zones";
    layer.closed = true;
    layer.offsets.push_back(0);
    std::vector<double> by_zone, by_gp;
    detail::ZonePaint paint;
    if (q == ZoneQuantity::Disp) {
        by_gp.resize(static_cast<size_t>(m.gridpoints.size()));
        for (int g = 0; g < m.gridpoints.size(); ++g) by_gp[g] = m.gridpoints.disp[g].norm();
        paint.gp_value = &by_gp;
    } else {
        by_zone.assign(static_cast<size_t>(m.zones.size()), 0.0);
        for (int z : zones) by_zone[z] = zone_value(m, z, q);
        paint.zone_value = &by_zone;
    }
    detail::ZoneLines lines;
    lines.edges.colour = {0.05, 0.05, 0.05};
    lines.edges.width = 1.5;
    lines.trace.colour = {0.05, 0.05, 0.05};
    lines.trace.width = 2.0;
    int n_section = 0;
    const int n =
        detail::append_zone_polygons(layer, &lines, m, zones, drawn, detail::cut_plane(opt), paint, &n_section);
    if (n == 0) return 0;
    if (q == ZoneQuantity::State) {
        layer.scale = state_scale();
    } else if (q == ZoneQuantity::Disp) {
        layer.scale = detail::continuous_scale(zone_quantity_info(q), layer.point_scalars, opt);
    } else {
        // On a section the scale is that of the section: the surface below it is seen edge on,
        // if at all, and its extremes would squeeze what the picture is for.
        const std::vector<double> section(layer.cell_scalars.end() - n_section, layer.cell_scalars.end());
        layer.scale = stress_scale(zone_quantity_info(q), n_section > 0 ? section : layer.cell_scalars, opt);
    }
    layer.edges = opt.edges && n <= kMaxPolygonsWithEdges;
    layer.edge_colour = {0.3, 0.3, 0.3};
    layer.mesh = true;
    scene.polygons.push_back(std::move(layer));
    if (!lines.edges.segments.empty()) scene.lines.push_back(std::move(lines.edges));
    if (!lines.trace.segments.empty()) scene.lines.push_back(std::move(lines.trace));
    return n;
}

PrincipalField principal_from_zones(const Model& m, const PlotOptions& opt, int max_points) {
    PrincipalField f;
    f.by_sign = true;
    const std::vector<int> zones = zones_to_draw(m, opt);
    if (zones.empty()) return f;
    const std::vector<Vec3> drawn = detail::drawn_gridpoints(m, opt.magnify);
    const std::optional<detail::Plane> cut = detail::cut_plane(opt);
    std::vector<int> candidates;
    std::vector<Vec3> points;
    for (int z : zones) {
        const auto& q = m.zones.gp[z];
        const Vec3 c = 0.25 * (drawn[q[0]] + drawn[q[1]] + drawn[q[2]] + drawn[q[3]]);
        if (cut) {
            int n_above = 0;
            for (int g : q) n_above += cut->n.dot(drawn[g]) - cut->d > 0;
            if (n_above == 0 || n_above == 4) continue;
            points.push_back(c - (cut->n.dot(c) - cut->d) * cut->n);
        } else {
            points.push_back(c);
        }
        candidates.push_back(z);
    }
    f.n_sampled_from = static_cast<int>(candidates.size());
    double spacing = 0;
    const std::vector<int> keep = detail::thin_points(points, max_points, spacing);
    std::vector<int> kept_zones;
    for (int i : keep) kept_zones.push_back(candidates[i]);
    // The longest bar a little shorter than the distance between the zones drawn.
    f.typical_size = 0.9 * std::max(spacing, zone_spacing(m, kept_zones.empty() ? zones : kept_zones));
    // On a section the bars lie on the plane, lifted by their radius so that they show whole.
    const Vec3 lift = cut ? Vec3(cut->n * 0.06 * f.typical_size) : Vec3::Zero();
    for (int i : keep) {
        const int z = candidates[i];
        Vec3 values;
        Mat3 directions;
        principal_stresses(m.zones.stress[z], values, &directions);
        if (!values.allFinite() || !directions.allFinite()) continue;
        f.points.push_back(points[i] + lift);
        f.value.push_back({values[0], values[1], values[2]});
        f.direction.push_back({Vec3(directions.col(0)), Vec3(directions.col(1)), Vec3(directions.col(2))});
    }
    return f;
}

} // namespace odec::render
