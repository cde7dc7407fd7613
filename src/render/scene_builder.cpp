// Building scenes from the model. See scene_builder.h for the order of calls.
//
// Blocks are drawn face by face: each face a polygon carrying its block's value, so a block
// reads as one colour (a rigid block has one displacement) and the block edges show where
// joints cut the rock. Sections clip each convex block by the plane here, rather than in
// the backend, because a clipped block needs its cap (the cut face) and only the builder
// knows which polygons close a block.
#include "render/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "engine/blocks.h"
#include "render/scene_internal.h"

namespace odec::render {

namespace detail {

bool shown(const Model& m, int b) {
    return (m.blocks.flags[b] & (kHidden | kExcavated)) == 0;
}

std::vector<int> blocks_to_draw(const Model& m, const PlotOptions& opt) {
    std::vector<int> out;
    if (opt.blocks) {
        for (int b : *opt.blocks)
            if (b >= 0 && b < m.blocks.size() && shown(m, b)) out.push_back(b);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    } else {
        for (int b = 0; b < m.blocks.size(); ++b)
            if (shown(m, b)) out.push_back(b);
    }
    return out;
}

Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
    const double n = v.norm();
    return n > 0 ? Vec3(v / n) : fallback;
}

void plane_axes(const Vec3& n, Vec3& u, Vec3& v) {
    const Vec3 e = std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    u = n.cross(e).normalized();
    v = n.cross(u);
}

std::optional<Plane> cut_plane(const PlotOptions& opt) {
    if (!opt.cut) return std::nullopt;
    Plane p;
    p.n = unit_or(opt.cut->normal, Vec3(0, -1, 0));
    p.d = p.n.dot(opt.cut->origin);
    return p;
}

// Continuous scale over the values drawn. A quantity that takes both signs in them gets a
// diverging map centred at 0; one that takes one sign (a magnitude, or compressive joint
// stresses) a sequential map from 0 to its extreme.
ColourScale continuous_scale(const QuantityInfo& info, const std::vector<double>& values, const PlotOptions& opt) {
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
    const bool two_signs = info.is_signed && lo < 0 && hi > 0;
    s.map = opt.map ? *opt.map : (two_signs ? ColourMap::CoolWarm : ColourMap::Rainbow);
    if (s.map == ColourMap::Categorical) s.map = ColourMap::Rainbow;
    if (opt.limits) {
        lo = opt.limits->first;
        hi = opt.limits->second;
    } else if (two_signs && s.map == ColourMap::CoolWarm) {
        const double a = std::max(std::abs(lo), std::abs(hi));
        lo = -a;
        hi = a;
    } else if (hi <= 0 && lo < 0) {
        hi = 0;
    } else {
        lo = std::min(0.0, lo);
    }
    s.lo = lo;
    s.hi = hi;
    return s;
}

} // namespace detail

namespace {

using detail::blocks_to_draw;
using detail::continuous_scale;
using detail::plane_axes;
using detail::shown;
using detail::unit_or;

// A convex polyhedron kept on the side n.x <= d: its faces (each clipped) and the cap.
struct ClippedShape {
    std::vector<std::vector<Vec3>> faces;
    std::vector<Vec3> cap; // CCW seen from +n, empty when the plane does not cross
};

// Order points lying in a plane (normal n) counter-clockwise around their mean.
std::vector<Vec3> order_in_plane(std::vector<Vec3> pts, const Vec3& n, double tol) {
    // Merge near duplicates first (an edge crossing at a vertex gives the same point twice).
    std::vector<Vec3> unique;
    for (const Vec3& p : pts) {
        bool dup = false;
        for (const Vec3& q : unique)
            if ((p - q).norm() <= tol) {
                dup = true;
                break;
            }
        if (!dup) unique.push_back(p);
    }
    if (unique.size() < 3) return {};
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : unique) c += p;
    c /= static_cast<double>(unique.size());
    const Vec3 e = std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const Vec3 u = n.cross(e).normalized();
    const Vec3 v = n.cross(u);
    std::vector<std::pair<double, Vec3>> by_angle;
    for (const Vec3& p : unique) by_angle.push_back({std::atan2((p - c).dot(v), (p - c).dot(u)), p});
    std::sort(by_angle.begin(), by_angle.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Vec3> out;
    for (const auto& a : by_angle) out.push_back(a.second);
    return out;
}

// Returns false when nothing of the shape is left.
bool clip_convex(const Polyhedron& p, const Vec3& n, double d, double tol, ClippedShape& out) {
    std::vector<double> s(p.vertices.size());
    bool any_below = false, any_above = false;
    for (size_t i = 0; i < p.vertices.size(); ++i) {
        s[i] = n.dot(p.vertices[i]) - d;
        any_below |= s[i] < -tol;
        any_above |= s[i] > tol;
    }
    if (!any_below) return false;
    std::vector<Vec3> cap_points;
    for (int f = 0; f < p.n_faces(); ++f) {
        const int k = p.face_size(f);
        std::vector<Vec3> poly;
        for (int j = 0; j < k; ++j) {
            const int a = p.face_vertex(f, j), b = p.face_vertex(f, (j + 1) % k);
            const double sa = s[a], sb = s[b];
            if (sa <= tol) poly.push_back(p.vertices[a]);
            if (any_above && std::abs(sa) <= tol) cap_points.push_back(p.vertices[a]);
            if ((sa < -tol && sb > tol) || (sa > tol && sb < -tol)) {
                const double t = sa / (sa - sb);
                const Vec3 x = p.vertices[a] + t * (p.vertices[b] - p.vertices[a]);
                poly.push_back(x);
                cap_points.push_back(x);
            }
        }
        if (poly.size() >= 3) out.faces.push_back(std::move(poly));
    }
    if (any_above) out.cap = order_in_plane(cap_points, n, tol);
    return true;
}

double block_size(const Model& m, int b) { return std::cbrt(std::max(m.blocks.volume[b], 0.0)); }

double block_scalar(const Model& m, int b, BlockColour by) {
    const BlockSet& bs = m.blocks;
    switch (by) {
    case BlockColour::Disp: return bs.disp[b].norm();
    case BlockColour::XDis: return bs.disp[b].x();
    case BlockColour::YDis: return bs.disp[b].y();
    case BlockColour::ZDis: return bs.disp[b].z();
    case BlockColour::Vel: return velocity_at_t(m, b).norm();
    case BlockColour::XVel: return velocity_at_t(m, b).x();
    case BlockColour::YVel: return velocity_at_t(m, b).y();
    case BlockColour::ZVel: return velocity_at_t(m, b).z();
    case BlockColour::Group: return bs.group[b];
    case BlockColour::Material: return bs.material[b];
    case BlockColour::Region: return bs.region[b];
    // 0 free, 1 fixed, 2 moving with a given velocity (fixed or not).
    case BlockColour::Fixed: return bs.vel_bc[b] ? 2 : ((bs.flags[b] & kFixed) ? 1 : 0);
    case BlockColour::Flat: return 0;
    }
    return 0;
}

bool is_categorical(BlockColour by) {
    return by == BlockColour::Group || by == BlockColour::Material || by == BlockColour::Region ||
           by == BlockColour::Fixed;
}

// Categorical values (group, material, region numbers) become 0..n-1 with a name each.
ColourScale categorical_scale(const Model& m, BlockColour by, std::vector<double>& values) {
    ColourScale s;
    s.map = ColourMap::Categorical;
    s.title = block_colour_info(by).title;
    std::set<int> distinct;
    for (double v : values) distinct.insert(static_cast<int>(v));
    std::map<int, int> index;
    for (int v : distinct) {
        index[v] = static_cast<int>(s.categories.size());
        if (by == BlockColour::Group)
            s.categories.push_back(v >= 0 && v < static_cast<int>(m.group_names.size()) ? m.group_names[v]
                                                                                       : std::string("(none)"));
        else if (by == BlockColour::Fixed)
            s.categories.push_back(v == 0 ? "free" : v == 1 ? "fixed" : "velocity given");
        else
            s.categories.push_back(std::to_string(v));
    }
    for (double& v : values) v = index[static_cast<int>(v)];
    s.lo = 0;
    s.hi = std::max(0, static_cast<int>(s.categories.size()) - 1);
    return s;
}

void append_polygon(PolygonLayer& layer, const std::vector<Vec3>& poly, double scalar) {
    const int base = static_cast<int>(layer.points.size());
    for (size_t i = 0; i < poly.size(); ++i) {
        layer.points.push_back(poly[i]);
        layer.indices.push_back(base + static_cast<int>(i));
    }
    layer.offsets.push_back(static_cast<int>(layer.indices.size()));
    layer.cell_scalars.push_back(scalar);
}

} // namespace

namespace {

bool is_kinematic(BlockColour by) {
    switch (by) {
    case BlockColour::Disp: case BlockColour::XDis: case BlockColour::YDis: case BlockColour::ZDis:
    case BlockColour::Vel: case BlockColour::XVel: case BlockColour::YVel: case BlockColour::ZVel: return true;
    default: return false;
    }
}

// A kinematic quantity at gridpoint g (is_kinematic(by)).
double gridpoint_scalar(const Model& m, int g, BlockColour by) {
    switch (by) {
    case BlockColour::Disp: return m.gridpoints.disp[g].norm();
    case BlockColour::XDis: return m.gridpoints.disp[g].x();
    case BlockColour::YDis: return m.gridpoints.disp[g].y();
    case BlockColour::ZDis: return m.gridpoints.disp[g].z();
    case BlockColour::Vel: return gridpoint_velocity_at_t(m, g).norm();
    case BlockColour::XVel: return gridpoint_velocity_at_t(m, g).x();
    case BlockColour::YVel: return gridpoint_velocity_at_t(m, g).y();
    case BlockColour::ZVel: return gridpoint_velocity_at_t(m, g).z();
    default: return 0;
    }
}

// A rigid block as drawn: moved by (magnify - 1) times its displacement.
Polyhedron drawn_shape(const Model& m, int b, double magnify) {
    Polyhedron p = world_shape(m, b);
    if (is_deformable(m, b)) {
        const auto& corners = m.blocks.corner_gp[b];
        for (size_t v = 0; v < corners.size() && v < p.vertices.size(); ++v)
            if (corners[v] >= 0 && corners[v] < m.gridpoints.size())
                p.vertices[v] = detail::drawn_gridpoint(m, corners[v], magnify);
        return p;
    }
    if (magnify != 1.0) {
        const Vec3 shift = (magnify - 1.0) * m.blocks.disp[b];
        for (Vec3& v : p.vertices) v += shift;
    }
    return p;
}

// Where a block's label and arrow go: its centroid as drawn.
Vec3 drawn_centre(const Model& m, int b, double magnify) {
    if (is_deformable(m, b)) {
        const Polyhedron p = drawn_shape(m, b, magnify);
        Vec3 c = Vec3::Zero();
        for (const Vec3& v : p.vertices) c += v;
        return p.vertices.empty() ? m.blocks.centroid[b] : Vec3(c / static_cast<double>(p.vertices.size()));
    }
    return m.blocks.centroid[b] + (magnify - 1.0) * m.blocks.disp[b];
}

// Active zones of these blocks (a deformable block's picture).
std::vector<int> zones_of_blocks(const Model& m, const std::vector<int>& blocks) {
    if (blocks.empty()) return {};
    PlotOptions o;
    o.blocks = blocks;
    return zones_to_draw(m, o);
}

// The displacement note of a picture drawn with `magnify`.
std::string magnify_note(double magnify) {
    if (magnify == 0) return "    shape before the displacements";
    char note[96];
    std::snprintf(note, sizeof note, "    displacements magnified x%g", magnify);
    return note;
}

} // namespace

QuantityInfo block_colour_info(BlockColour by) {
    switch (by) {
    case BlockColour::Disp: return {"displacement magnitude", "m", false};
    case BlockColour::XDis: return {"x displacement", "m", true};
    case BlockColour::YDis: return {"y displacement", "m", true};
    case BlockColour::ZDis: return {"z displacement", "m", true};
    case BlockColour::Vel: return {"velocity magnitude", "m/s", false};
    case BlockColour::XVel: return {"x velocity", "m/s", true};
    case BlockColour::YVel: return {"y velocity", "m/s", true};
    case BlockColour::ZVel: return {"z velocity", "m/s", true};
    case BlockColour::Group: return {"group", "", false};
    case BlockColour::Material: return {"material", "", false};
    case BlockColour::Region: return {"region", "", false};
    case BlockColour::Fixed: return {"support", "", false};
    case BlockColour::Flat: return {"", "", false};
    }
    return {};
}

QuantityInfo contact_quantity_info(ContactQuantity q) {
    switch (q) {
    case ContactQuantity::NormalStress: return {"joint normal stress, compression +", "Pa", true};
    case ContactQuantity::ShearStress: return {"joint shear stress", "Pa", false};
    case ContactQuantity::NormalDisp: return {"joint normal closure, closing +", "m", true};
    case ContactQuantity::ShearDisp: return {"joint shear displacement", "m", false};
    case ContactQuantity::State: return {"contact state", "", false};
    case ContactQuantity::PorePressure: return {"joint pore pressure", "Pa", false};
    case ContactQuantity::Aperture: return {"joint hydraulic aperture", "m", false};
    }
    return {};
}

bool camera_for_view(const std::string& name, Camera& camera) {
    Camera c;
    if (name == "iso") {
        c.eye_direction = Vec3(1, -1, 0.8);
    } else if (name == "x" || name == "-x" || name == "y" || name == "-y" || name == "z" || name == "-z") {
        const double sign = name[0] == '-' ? -1.0 : 1.0;
        const char axis = name.back();
        c.eye_direction = axis == 'x' ? Vec3(sign, 0, 0) : axis == 'y' ? Vec3(0, sign, 0) : Vec3(0, 0, sign);
        c.up = axis == 'z' ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
        c.parallel = true; // axis views are read like drawings: no perspective
    } else {
        return false;
    }
    camera = c;
    return true;
}

Camera camera_for_eye(const Vec3& eye) {
    Camera c;
    c.eye_given = true;
    c.eye_point = eye;
    return c;
}

std::string scene_title(const Model& m) {
    char line[128];
    std::snprintf(line, sizeof line, "step %ld    time %.5g s", m.step, m.time);
    return (m.title.empty() ? std::string("odec") : m.title) + "\n" + line;
}

Scene begin_scene(const Model& m, const PlotOptions& opt) {
    Scene s;
    s.title = scene_title(m);
    s.width = opt.width;
    s.height = opt.height;
    s.background = opt.background;
    s.camera = opt.camera;
    if (opt.cut && !opt.view_given) {
        // Look straight at the section.
        const Vec3 n = unit_or(opt.cut->normal, Vec3(0, -1, 0));
        s.camera = Camera();
        s.camera.eye_direction = n;
        s.camera.up = std::abs(n.z()) > 0.9 ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
        s.camera.parallel = true;
    }
    if (opt.magnify != 1.0) s.title += magnify_note(opt.magnify);
    return s;
}

void add_blocks(Scene& scene, const Model& m, BlockColour by, const PlotOptions& opt) {
    const std::vector<int> all_blocks = blocks_to_draw(m, opt);
    // Rigid blocks face by face; deformable ones from their zones (unless a zone item draws them).
    std::vector<int> blocks, deformable;
    for (int b : all_blocks) {
        if (!is_deformable(m, b)) blocks.push_back(b);
        else if (!opt.zone_item) deformable.push_back(b);
    }
    PolygonLayer layer;
    layer.name = "blocks";
    layer.edges = opt.edges;
    layer.closed = true;
    layer.offsets.push_back(0);
    LineLayer trace;
    trace.colour = {0.05, 0.05, 0.05};
    trace.width = 2.0;

    Vec3 cut_n = Vec3::Zero();
    double cut_d = 0;
    if (opt.cut) {
        cut_n = unit_or(opt.cut->normal, Vec3(0, -1, 0));
        cut_d = cut_n.dot(opt.cut->origin);
    }
    std::vector<int> coloured = blocks;
    coloured.insert(coloured.end(), deformable.begin(), deformable.end());
    std::vector<double> block_values;
    block_values.reserve(coloured.size());
    for (int b : coloured) block_values.push_back(block_scalar(m, b, by));

    ColourScale scale;
    if (is_categorical(by)) scale = categorical_scale(m, by, block_values);

    for (size_t i = 0; i < blocks.size(); ++i) {
        const int b = blocks[i];
        const Polyhedron shape = drawn_shape(m, b, opt.magnify);
        const double value = block_values[i];
        if (!opt.cut) {
            const int base = static_cast<int>(layer.points.size());
            layer.points.insert(layer.points.end(), shape.vertices.begin(), shape.vertices.end());
            for (int f = 0; f < shape.n_faces(); ++f) {
                for (int k = 0; k < shape.face_size(f); ++k) layer.indices.push_back(base + shape.face_vertex(f, k));
                layer.offsets.push_back(static_cast<int>(layer.indices.size()));
                layer.cell_scalars.push_back(value);
            }
            continue;
        }
        ClippedShape clipped;
        const double tol = 1e-9 * std::max(block_size(m, b), 1e-12);
        if (!clip_convex(shape, cut_n, cut_d, tol, clipped)) continue;
        for (const auto& face : clipped.faces) append_polygon(layer, face, value);
        if (!clipped.cap.empty()) {
            append_polygon(layer, clipped.cap, value);
            const int base = static_cast<int>(trace.points.size());
            const int k = static_cast<int>(clipped.cap.size());
            // Lift the trace a hair towards the eye so it is not buried in the cap.
            const Vec3 lift = cut_n * (1e-4 * block_size(m, b));
            for (const Vec3& x : clipped.cap) trace.points.push_back(x + lift);
            for (int j = 0; j < k; ++j) trace.segments.push_back({base + j, base + (j + 1) % k});
        }
    }

    // Deformable blocks: one layer of their own, coloured per gridpoint for displacements and
    // velocities, else by their block's value.
    PolygonLayer zoned;
    zoned.name = "blocks";
    zoned.closed = true;
    zoned.offsets.push_back(0);
    detail::ZoneLines zone_lines;
    zone_lines.edges.colour = {0.1, 0.1, 0.1};
    zone_lines.edges.width = 1.5;
    zone_lines.trace = trace;
    int n_zoned = 0;
    if (!deformable.empty()) {
        const std::vector<int> zones = zones_of_blocks(m, deformable);
        std::vector<double> by_zone, by_gp;
        detail::ZonePaint paint;
        if (is_kinematic(by)) {
            by_gp.resize(static_cast<size_t>(m.gridpoints.size()));
            for (int g = 0; g < m.gridpoints.size(); ++g) by_gp[g] = gridpoint_scalar(m, g, by);
            paint.gp_value = &by_gp;
        } else {
            by_zone.assign(static_cast<size_t>(m.zones.size()), 0.0);
            std::vector<double> of_block(static_cast<size_t>(m.blocks.size()), 0.0);
            for (size_t i = 0; i < deformable.size(); ++i) of_block[deformable[i]] = block_values[blocks.size() + i];
            for (int z : zones) by_zone[z] = of_block[m.zones.block[z]];
            paint.zone_value = &by_zone;
        }
        n_zoned = detail::append_zone_polygons(zoned, &zone_lines, m, zones, detail::drawn_gridpoints(m, opt.magnify),
                                               detail::cut_plane(opt), paint);
        trace = std::move(zone_lines.trace);
        // Zone edges make a fine mesh dark: only the block edges are drawn over many zones.
        zoned.edges = opt.edges && n_zoned <= 5000;
        zoned.edge_colour = {0.35, 0.35, 0.35};
        zoned.mesh = true;
    }

    if (by != BlockColour::Flat && !is_categorical(by)) {
        std::vector<double> values = layer.cell_scalars;
        values.insert(values.end(), zoned.cell_scalars.begin(), zoned.cell_scalars.end());
        values.insert(values.end(), zoned.point_scalars.begin(), zoned.point_scalars.end());
        scale = continuous_scale(block_colour_info(by), values, opt);
    }
    if (by == BlockColour::Flat) {
        layer.cell_scalars.clear();
        zoned.cell_scalars.clear();
        zoned.point_scalars.clear();
    } else {
        layer.scale = scale;
        zoned.scale = scale;
    }
    const bool have_rigid = layer.offsets.size() >= 2;
    if (!have_rigid && n_zoned == 0) return;
    if (have_rigid) scene.polygons.push_back(std::move(layer));
    if (n_zoned > 0) {
        zoned.scale.legend = !have_rigid; // one legend for the two layers of blocks
        scene.polygons.push_back(std::move(zoned));
        if (!zone_lines.edges.segments.empty()) scene.lines.push_back(std::move(zone_lines.edges));
    }
    if (!trace.segments.empty()) scene.lines.push_back(std::move(trace));
    if (opt.ids) {
        for (int b : coloured) {
            const Vec3 at = drawn_centre(m, b, opt.magnify);
            if (opt.cut && cut_n.dot(at) > cut_d) continue;
            scene.labels.push_back({at, std::to_string(m.blocks.id[b])});
        }
    }
}

int add_cables(Scene& scene, const Model& m, const PlotOptions& opt) {
    const CableSet& cs = m.cables;
    if (cs.n_segments() == 0) return 0;
    auto at = [&](int i) { return Vec3(cs.pos[i] + (opt.magnify - 1.0) * cs.disp[i]); };
    // The tube's width: a small fraction of what the picture holds (blocks and cables).
    Eigen::AlignedBox3d box;
    for (int i = 0; i < cs.n_nodes(); ++i) box.extend(at(i));
    for (const Vec3& v : m.blocks.world_vertices) box.extend(v);
    const double width = std::max(0.004 * box.diagonal().norm(), 1e-6);
    PolygonLayer layer;
    layer.name = "cables";
    layer.edges = false;
    layer.closed = true;
    for (int c = 0; c < cs.size(); ++c) {
        for (int k = 0; k < cs.segments_of(c); ++k) {
            const int i = cs.node_offset[c] + k;
            const Vec3 a = at(i), b = at(i + 1);
            const Vec3 axis = detail::unit_or(b - a, Vec3(1, 0, 0));
            Vec3 u, v;
            detail::plane_axes(axis, u, v);
            u *= 0.5 * width;
            v *= 0.5 * width;
            const Vec3 corner[4] = {u + v, -u + v, -u - v, u - v};
            const int base = static_cast<int>(layer.points.size());
            for (const Vec3& p : corner) layer.points.push_back(a + p);
            for (const Vec3& p : corner) layer.points.push_back(b + p);
            // The four sides, counter-clockwise seen from outside.
            for (int q = 0; q < 4; ++q) {
                const int q1 = (q + 1) % 4;
                for (int idx : {base + q, base + 4 + q, base + 4 + q1, base + q1}) layer.indices.push_back(idx);
                if (layer.offsets.empty()) layer.offsets.push_back(0);
                layer.offsets.push_back(static_cast<int>(layer.indices.size()));
                layer.cell_scalars.push_back(cs.axial[cs.first_segment(c) + k]);
            }
        }
    }
    QuantityInfo info;
    info.title = "cable axial force, tension +";
    info.units = "N";
    info.is_signed = true;
    layer.scale = detail::continuous_scale(info, layer.cell_scalars, opt);
    const int n = cs.n_segments();
    scene.polygons.push_back(std::move(layer));
    return n;
}

int add_liners(Scene& scene, const Model& m, const PlotOptions& opt) {
    const LinerSet& ls = m.liners;
    if (ls.n_elements() == 0) return 0;
    auto at = [&](int i) { return Vec3(ls.pos[i] + (opt.magnify - 1.0) * ls.disp[i]); };
    PolygonLayer layer;
    layer.name = "liners";
    layer.edges = true;
    layer.closed = false;
    for (int e = 0; e < ls.n_elements(); ++e) {
        const int base = static_cast<int>(layer.points.size());
        for (int i : ls.elem[e]) layer.points.push_back(at(i));
        for (int k = 0; k < 3; ++k) layer.indices.push_back(base + k);
        if (layer.offsets.empty()) layer.offsets.push_back(0);
        layer.offsets.push_back(static_cast<int>(layer.indices.size()));
        layer.cell_scalars.push_back(liner_resultants(ls, e).nx);
    }
    QuantityInfo info;
    info.title = "liner n_x, tension +";
    info.units = "N/m";
    info.is_signed = true;
    layer.scale = detail::continuous_scale(info, layer.cell_scalars, opt);
    scene.polygons.push_back(std::move(layer));
    return ls.n_elements();
}

void add_block_outline(Scene& scene, const Model& m, const PlotOptions& opt) {
    LineLayer lines;
    lines.colour = {0.55, 0.55, 0.55};
    lines.width = 1.0;
    std::vector<int> deformable;
    for (int b : blocks_to_draw(m, opt)) {
        if (is_deformable(m, b)) {
            deformable.push_back(b);
            continue;
        }
        const Polyhedron shape = drawn_shape(m, b, opt.magnify);
        const int base = static_cast<int>(lines.points.size());
        lines.points.insert(lines.points.end(), shape.vertices.begin(), shape.vertices.end());
        std::set<std::pair<int, int>> edges; // each edge is shared by two faces: draw it once
        for (int f = 0; f < shape.n_faces(); ++f) {
            const int k = shape.face_size(f);
            for (int j = 0; j < k; ++j) {
                int a = shape.face_vertex(f, j), c = shape.face_vertex(f, (j + 1) % k);
                if (a > c) std::swap(a, c);
                if (edges.insert({a, c}).second) lines.segments.push_back({base + a, base + c});
            }
        }
    }
    if (!deformable.empty()) {
        // The block edges of the zoned surface, which follow the gridpoints as they move.
        PolygonLayer scratch;
        std::vector<double> none(static_cast<size_t>(m.zones.size()), 0.0);
        detail::ZonePaint paint;
        paint.zone_value = &none;
        detail::ZoneLines zone_lines;
        detail::append_zone_polygons(scratch, &zone_lines, m, zones_of_blocks(m, deformable),
                                     detail::drawn_gridpoints(m, opt.magnify), std::nullopt, paint);
        const int base = static_cast<int>(lines.points.size());
        lines.points.insert(lines.points.end(), zone_lines.edges.points.begin(), zone_lines.edges.points.end());
        for (const auto& s : zone_lines.edges.segments) lines.segments.push_back({base + s[0], base + s[1]});
    }
    if (!lines.segments.empty()) scene.lines.push_back(std::move(lines));
}

void add_vectors(Scene& scene, const Model& m, VectorKind kind, const PlotOptions& opt) {
    GlyphLayer g;
    g.shape = GlyphLayer::Shape::Arrow;
    std::vector<double> sizes;
    Vec3 cut_n = Vec3::Zero();
    double cut_d = 0;
    if (opt.cut) {
        cut_n = unit_or(opt.cut->normal, Vec3(0, -1, 0));
        cut_d = cut_n.dot(opt.cut->origin);
    }
    for (int b : blocks_to_draw(m, opt)) {
        if (is_deformable(m, b)) continue;
        const Vec3 at = drawn_centre(m, b, opt.magnify);
        if (opt.cut && cut_n.dot(at) > cut_d) continue;
        const Vec3 v = kind == VectorKind::Disp ? m.blocks.disp[b] : velocity_at_t(m, b);
        g.origins.push_back(at);
        g.directions.push_back(v);
        g.scalars.push_back(v.norm());
        sizes.push_back(block_size(m, b));
    }
    // Deformable blocks: arrows at their surface gridpoints, or on the section, thinned out.
    const std::vector<int> zones = opt.zone_item ? zones_to_draw(m, opt) : zones_of_blocks(m, blocks_to_draw(m, opt));
    if (!zones.empty()) {
        std::vector<Vec3> gp_vector(static_cast<size_t>(m.gridpoints.size()));
        for (int k = 0; k < m.gridpoints.size(); ++k)
            gp_vector[k] = kind == VectorKind::Disp ? m.gridpoints.disp[k] : gridpoint_velocity_at_t(m, k);
        const detail::VectorSamples samples = detail::zone_vector_samples(
            m, zones, detail::drawn_gridpoints(m, opt.magnify), gp_vector, detail::cut_plane(opt), 1500);
        for (size_t i = 0; i < samples.points.size(); ++i) {
            g.origins.push_back(samples.points[i]);
            g.directions.push_back(samples.vectors[i]);
            g.scalars.push_back(samples.vectors[i].norm());
            sizes.push_back(samples.spacing);
        }
    }
    if (g.origins.empty()) return;
    // The longest arrow about one typical block (or the distance between arrows) long: long
    // enough to read, short enough not to cross the picture.
    std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
    g.max_length = sizes[sizes.size() / 2];
    bool coloured_already = false;
    for (auto& layer : scene.polygons) {
        if (!layer.cell_scalars.empty() || !layer.point_scalars.empty()) coloured_already = true;
        if (layer.name == "blocks") layer.opacity = std::min(layer.opacity, 0.35);
        if (layer.name == "zones") layer.opacity = std::min(layer.opacity, 0.45);
    }
    const QuantityInfo info = kind == VectorKind::Disp ? QuantityInfo{"displacement magnitude", "m", false}
                                                       : QuantityInfo{"velocity magnitude", "m/s", false};
    if (coloured_already) {
        g.scalars.clear();
    } else {
        g.scale = continuous_scale(info, g.scalars, opt);
    }
    // The arrow scale: what the longest arrow stands for.
    double longest = 0;
    for (const Vec3& d : g.directions) longest = std::max(longest, d.norm());
    char note[160];
    std::snprintf(note, sizeof note, "    arrows: %s, the longest %.3g %s", kind == VectorKind::Disp ? "displacement" : "velocity",
                  longest, kind == VectorKind::Disp ? "m" : "m/s");
    scene.title += note;
    scene.glyphs.push_back(std::move(g));
}

bool add_contacts(Scene& scene, const ContactView& view, ContactQuantity q, const PlotOptions& opt,
                  std::string& error) {
    const ContactRows& rows = view.sub_contacts.size() > 0 ? view.sub_contacts : view.contacts;
    if (!contact_rows_valid(rows, error)) return false;
    const int n = rows.size();
    auto need = [&](size_t size, const char* what) {
        if (n > 0 && size == 0) {
            error = std::string("the contacts carry no ") + what;
            return false;
        }
        return true;
    };
    switch (q) {
    case ContactQuantity::NormalStress: if (!need(rows.normal_stress.size(), "normal stress")) return false; break;
    case ContactQuantity::ShearStress: if (!need(rows.shear_stress.size(), "shear stress")) return false; break;
    case ContactQuantity::NormalDisp: if (!need(rows.normal_disp.size(), "normal displacement")) return false; break;
    case ContactQuantity::ShearDisp: if (!need(rows.shear_disp.size(), "shear displacement")) return false; break;
    case ContactQuantity::State: if (!need(rows.state.size(), "state")) return false; break;
    case ContactQuantity::PorePressure: if (!need(rows.pore_pressure.size(), "pore pressure (fluid flow: 'config flow')")) return false; break;
    case ContactQuantity::Aperture: if (!need(rows.aperture.size(), "hydraulic aperture (fluid flow: 'config flow')")) return false; break;
    }
    Vec3 cut_n = Vec3::Zero();
    double cut_d = 0;
    if (opt.cut) {
        cut_n = unit_or(opt.cut->normal, Vec3(0, -1, 0));
        cut_d = cut_n.dot(opt.cut->origin);
    }
    PolygonLayer layer;
    layer.name = "contacts";
    layer.offsets.push_back(0);
    layer.edges = false;
    layer.lit = false;
    std::vector<double> values;
    for (int i = 0; i < n; ++i) {
        const Vec3 nrm = unit_or(rows.normal[i], Vec3(0, 0, 1));
        const double h = 0.5 * std::sqrt(std::max(rows.area[i], 0.0));
        const Vec3& c = rows.centroid[i];
        // On a section, a patch the cut plane crosses is drawn as its trace on the plane too: a band
        // along the line where the joint meets the section, so that joints seen edge-on there show
        // their colour.
        Vec3 trace[4];
        bool traced = false;
        if (opt.cut) {
            const double dist = cut_n.dot(c) - cut_d;
            const Vec3 along = cut_n - cut_n.dot(nrm) * nrm; // the way across the patch toward the plane
            const double s2 = along.squaredNorm();
            if (s2 > 1e-6 && std::abs(dist) <= h * std::sqrt(s2) + 1e-12) {
                const Vec3 p = c - dist * along / s2; // on the joint's plane and on the section
                const double off = (p - c).norm();
                const double half = h * std::sqrt(std::max(1.0 - off * off / (4 * h * h), 0.5)) * 1.2;
                const Vec3 t = nrm.cross(cut_n).normalized(), b = cut_n.cross(t);
                const double width = 0.5 * h;
                const Vec3 lift = cut_n * (0.05 * h); // over the cut faces of the blocks
                trace[0] = p - half * t - width * b + lift;
                trace[1] = p + half * t - width * b + lift;
                trace[2] = p + half * t + width * b + lift;
                trace[3] = p - half * t + width * b + lift;
                traced = true;
            }
        }
        if (opt.cut && cut_n.dot(c) > cut_d && !traced) continue;
        double v = 0;
        switch (q) {
        case ContactQuantity::NormalStress: v = rows.normal_stress[i]; break;
        case ContactQuantity::ShearStress: v = rows.shear_stress[i].norm(); break;
        case ContactQuantity::NormalDisp: v = rows.normal_disp[i]; break;
        case ContactQuantity::ShearDisp: v = rows.shear_disp[i].norm(); break;
        case ContactQuantity::State: v = rows.state[i]; break;
        case ContactQuantity::PorePressure: v = rows.pore_pressure[i]; break;
        case ContactQuantity::Aperture: v = rows.aperture[i]; break;
        }
        if (!opt.cut || cut_n.dot(c) <= cut_d) {
            Vec3 u, w;
            plane_axes(nrm, u, w);
            append_polygon(layer, {c - h * u - h * w, c + h * u - h * w, c + h * u + h * w, c - h * u + h * w}, v);
            values.push_back(v);
        }
        if (traced) {
            append_polygon(layer, {trace[0], trace[1], trace[2], trace[3]}, v);
            values.push_back(v);
        }
    }
    if (layer.offsets.size() < 2) return true; // nothing to show is not an error
    if (q == ContactQuantity::State) {
        layer.scale.map = ColourMap::Categorical;
        layer.scale.title = "contact state";
        int max_state = 0;
        for (double v : values) max_state = std::max(max_state, static_cast<int>(v));
        for (int k = 0; k <= max_state || k < static_cast<int>(view.state_names.size()); ++k)
            layer.scale.categories.push_back(k < static_cast<int>(view.state_names.size()) ? view.state_names[k]
                                                                                         : std::to_string(k));
        layer.scale.lo = 0;
        layer.scale.hi = static_cast<double>(layer.scale.categories.size()) - 1;
    } else {
        layer.scale = continuous_scale(contact_quantity_info(q), values, opt);
    }
    scene.polygons.push_back(std::move(layer));
    return true;
}

PrincipalField principal_from_contacts(const ContactView& view) {
    PrincipalField f;
    const ContactRows& rows = view.sub_contacts.size() > 0 ? view.sub_contacts : view.contacts;
    std::string error;
    if (!contact_rows_valid(rows, error)) return f;
    for (int i = 0; i < rows.size(); ++i) {
        const Vec3 n = unit_or(rows.normal[i], Vec3(0, 0, 1));
        Vec3 u, w;
        plane_axes(n, u, w);
        const double sn = rows.normal_stress.empty() ? 0.0 : rows.normal_stress[i];
        const Vec3 tau = rows.shear_stress.empty() ? Vec3::Zero() : rows.shear_stress[i];
        f.points.push_back(rows.centroid[i]);
        // Compression negative, as for zone stresses.
        f.value.push_back({-sn, tau.norm(), 0.0});
        f.direction.push_back({n, unit_or(tau, u), w});
    }
    // The largest bar about as long as a typical contact patch is wide.
    std::vector<double> sides;
    for (double a : rows.area) sides.push_back(std::sqrt(std::max(a, 0.0)));
    if (!sides.empty()) {
        std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
        f.typical_size = sides[sides.size() / 2];
    }
    return f;
}

void add_principal(Scene& scene, const PrincipalField& field, const PlotOptions& opt) {
    GlyphLayer g;
    g.shape = GlyphLayer::Shape::Bar;
    for (size_t i = 0; i < field.points.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double v = field.value[i][k];
            if (v == 0) continue;
            g.origins.push_back(field.points[i]);
            g.directions.push_back(field.direction[i][k] * std::abs(v));
            g.scalars.push_back(v);
        }
    }
    if (g.origins.empty()) return;
    g.max_length = field.typical_size;
    if (!field.by_sign) {
        g.scale = continuous_scale({"principal stress at contacts, tension +", "Pa", true}, g.scalars, opt);
        scene.glyphs.push_back(std::move(g));
        return;
    }
    double longest = 0;
    for (double& v : g.scalars) {
        longest = std::max(longest, std::abs(v));
        v = v < 0 ? 0 : 1;
    }
    g.scale.map = ColourMap::Categorical;
    g.scale.title = "principal stress";
    g.scale.categories = {"compression", "tension"};
    // Black and magenta: neither is in the colour maps, so the bars read over any contours.
    g.scale.colours = {{0.05, 0.05, 0.05}, {0.90, 0.05, 0.85}};
    g.scale.lo = 0;
    g.scale.hi = 1;
    char note[160];
    if (static_cast<int>(field.points.size()) < field.n_sampled_from)
        std::snprintf(note, sizeof note, "    bars: principal stresses of %d of %d zones, the longest %.3g Pa",
                      static_cast<int>(field.points.size()), field.n_sampled_from, longest);
    else
        std::snprintf(note, sizeof note, "    bars: principal stresses, the longest %.3g Pa", longest);
    scene.title += note;
    scene.glyphs.push_back(std::move(g));
}

Scene build_block_scene(const Model& m, BlockColour by, const std::vector<int>& block_indices) {
    PlotOptions opt;
    if (!block_indices.empty()) opt.blocks = block_indices;
    Scene s = begin_scene(m, opt);
    add_blocks(s, m, by, opt);
    return s;
}

namespace {

std::string history_axis_title(HistoryKind k) {
    switch (k) {
    case HistoryKind::Unbalanced: return "unbalanced force (N)";
    case HistoryKind::Time: return "time (s)";
    case HistoryKind::Step: return "step";
    case HistoryKind::XDis: return "x displacement (m)";
    case HistoryKind::YDis: return "y displacement (m)";
    case HistoryKind::ZDis: return "z displacement (m)";
    case HistoryKind::XVel: return "x velocity (m/s)";
    case HistoryKind::YVel: return "y velocity (m/s)";
    case HistoryKind::ZVel: return "z velocity (m/s)";
    case HistoryKind::Ratio: return "unbalanced force ratio";
    case HistoryKind::NStress: return "joint normal stress (Pa)";
    case HistoryKind::SStress: return "joint shear stress (Pa)";
    case HistoryKind::NDis: return "joint normal closure (m)";
    case HistoryKind::SDis: return "joint shear displacement (m)";
    case HistoryKind::SXX: return "zone stress xx, tension + (Pa)";
    case HistoryKind::SYY: return "zone stress yy, tension + (Pa)";
    case HistoryKind::SZZ: return "zone stress zz, tension + (Pa)";
    case HistoryKind::SXY: return "zone stress xy (Pa)";
    case HistoryKind::SXZ: return "zone stress xz (Pa)";
    case HistoryKind::SYZ: return "zone stress yz (Pa)";
    case HistoryKind::XReaction: return "x reaction (N)";
    case HistoryKind::YReaction: return "y reaction (N)";
    case HistoryKind::ZReaction: return "z reaction (N)";
    case HistoryKind::NForce: return "joint normal force, compression + (N)";
    case HistoryKind::SForce: return "joint shear force (N)";
    case HistoryKind::XAcc: return "x acceleration (m/s2)";
    case HistoryKind::YAcc: return "y acceleration (m/s2)";
    case HistoryKind::ZAcc: return "z acceleration (m/s2)";
    case HistoryKind::Damp: return "damping coefficient (1/s)";
    case HistoryKind::Fish: return "FISH value";
    case HistoryKind::Energy: return "energy (J)";
    case HistoryKind::CableForce: return "cable axial force, tension + (N)";
    case HistoryKind::CableGrout: return "cable grout force (N)";
    case HistoryKind::PorePressure: return "pore pressure (Pa)";
    case HistoryKind::Aperture: return "hydraulic aperture (m)";
    case HistoryKind::FlowRate: return "flow rate (m3/s)";
    case HistoryKind::LinerNx: return "liner n_x, tension + (N/m)";
    case HistoryKind::LinerMx: return "liner m_x, void side in tension + (N m/m)";
    }
    return "value";
}

std::string history_name(const HistorySet& h, int number) {
    const History& item = h.items[number - 1];
    return std::to_string(number) + ": " + (item.label.empty() ? history_default_label(item) : item.label);
}

} // namespace

bool add_history_chart(Scene& scene, const HistorySet& h, const std::vector<int>& numbers, int vs,
                       std::string& error) {
    const int n_items = static_cast<int>(h.items.size());
    if (numbers.empty()) {
        error = "no history numbers given";
        return false;
    }
    for (int k : numbers) {
        if (k < 1 || k > n_items) {
            error = "history " + std::to_string(k) + " does not exist (there " +
                    (n_items == 1 ? std::string("is 1 history") : "are " + std::to_string(n_items) + " histories") + ")";
            return false;
        }
    }
    if (vs != 0 && (vs < 1 || vs > n_items)) {
        error = "history " + std::to_string(vs) + " (after vs) does not exist";
        return false;
    }
    const size_t n_samples = h.sample_steps.size();
    if (n_samples == 0) {
        error = "the histories have no samples yet (take some steps first)";
        return false;
    }
    Chart chart;
    // The x of each sample: its step, or the value of history vs (none before vs was made).
    std::vector<const double*> x(n_samples);
    std::vector<double> steps(n_samples);
    if (vs > 0) {
        const History& xh = h.items[vs - 1];
        for (size_t i = 0; i < n_samples; ++i) x[i] = xh.at(i);
        // The name of the history, then its unit (time in s, displacement in m, ...).
        chart.x_label = history_name(h, vs);
        const std::string axis = history_axis_title(xh.kind);
        const size_t open = axis.rfind(" (");
        if (open != std::string::npos && chart.x_label.find(axis.substr(open)) == std::string::npos) {
            chart.x_label += axis.substr(open);
        }
    } else {
        for (size_t i = 0; i < n_samples; ++i) {
            steps[i] = static_cast<double>(h.sample_steps[i]);
            x[i] = &steps[i];
        }
        chart.x_label = "step";
    }
    bool same_kind = true;
    for (int k : numbers) same_kind &= h.items[k - 1].kind == h.items[numbers[0] - 1].kind;
    chart.y_label = same_kind ? history_axis_title(h.items[numbers[0] - 1].kind) : std::string("value");
    for (int k : numbers) {
        const History& item = h.items[k - 1];
        ChartSeries s;
        s.name = history_name(h, k);
        // Each history from its own first sample (one made during the run starts later).
        for (size_t i = 0; i < n_samples; ++i) {
            const double* y = item.at(i);
            if (!x[i] || !y) continue;
            s.x.push_back(*x[i]);
            s.y.push_back(*y);
        }
        chart.series.push_back(std::move(s));
    }
    chart.markers = n_samples <= 20;
    scene.chart = std::move(chart);
    // A chart's title is one line: the model title and where it stands.
    const auto nl = scene.title.find('\n');
    if (nl != std::string::npos) scene.title = scene.title.substr(0, nl) + "   (" + scene.title.substr(nl + 1) + ")";
    return true;
}

Scene build_history_chart(const HistorySet& h, const std::vector<int>& numbers, int vs) {
    Scene s;
    s.title = "histories";
    std::string error;
    add_history_chart(s, h, numbers, vs, error);
    return s;
}

} // namespace odec::render
