// What the scene builders share (scene_builder.cpp for blocks, contacts and charts,
// zone_scene.cpp for deformable blocks): not for plot commands, which use scene_builder.h.
#pragma once

#include <optional>
#include <vector>

#include "render/scene_builder.h"

namespace odec::render::detail {

// A block that pictures show: not hidden, not excavated.
bool shown(const Model& m, int b);
// Shown blocks within opt.blocks (all shown blocks when none), sorted.
std::vector<int> blocks_to_draw(const Model& m, const PlotOptions& opt);

// Continuous scale over `values` for a quantity (see scene_builder.cpp: diverging about 0
// for a signed quantity of both signs, else from 0 to the extreme).
ColourScale continuous_scale(const QuantityInfo& info, const std::vector<double>& values, const PlotOptions& opt);

Vec3 unit_or(const Vec3& v, const Vec3& fallback);
// Two unit vectors spanning the plane normal to n, with (u, v, n) right-handed.
void plane_axes(const Vec3& n, Vec3& u, Vec3& v);

// The cut as a unit normal and offset: what has n.x > d is cut away.
struct Plane {
    Vec3 n = Vec3(0, -1, 0);
    double d = 0;
};
std::optional<Plane> cut_plane(const PlotOptions& opt);

// Where gridpoint g is drawn: its original place plus `magnify` times its displacement.
inline Vec3 drawn_gridpoint(const Model& m, int g, double magnify) {
    return m.gridpoints.pos[g] + (magnify - 1.0) * m.gridpoints.disp[g];
}

// How zone polygons get their colour: one value per zone (cell scalars) or one per gridpoint
// (point scalars, interpolated along edges where a cut crosses them). Exactly one is given.
struct ZonePaint {
    const std::vector<double>* zone_value = nullptr; // (n_zones) by zone index
    const std::vector<double>* gp_value = nullptr;   // (n_gridpoints)
};

// Lines drawn over zone polygons: the block edges on the surface and, on a section, the
// outline of each block's section.
struct ZoneLines {
    LineLayer edges;
    LineLayer trace;
};

// Appends to `layer` the faces of `zones` (zone indices) that no other of them shares, at
// the drawn gridpoint positions `drawn`, and with a cut, what of them lies below the plane
// and the polygon in which the plane meets each tetrahedron it crosses (CCW seen from the
// side the plane's normal points to). Point scalars go to layer.point_scalars when the paint
// is per gridpoint, else cell scalars to layer.cell_scalars. Returns the polygons added, the
// section polygons last (`n_section` of them).
int append_zone_polygons(PolygonLayer& layer, ZoneLines* lines, const Model& m, const std::vector<int>& zones,
                         const std::vector<Vec3>& drawn, const std::optional<Plane>& cut, const ZonePaint& paint,
                         int* n_section = nullptr);

// The drawn positions of all gridpoints.
std::vector<Vec3> drawn_gridpoints(const Model& m, double magnify);

// Points at which to draw vectors of deformable blocks, and the spacing between them (m):
// the surface gridpoints of `zones`, or with a cut, points on the section, with the
// gridpoint vectors `gp_vector` there; thinned to about max_points.
struct VectorSamples {
    std::vector<Vec3> points;
    std::vector<Vec3> vectors;
    double spacing = 0;
};
VectorSamples zone_vector_samples(const Model& m, const std::vector<int>& zones, const std::vector<Vec3>& drawn,
                                  const std::vector<Vec3>& gp_vector, const std::optional<Plane>& cut,
                                  int max_points);

// Of `points`, about `max_points` spread evenly (one per cell of a regular grid, the one
// nearest its centre), as indices into `points`, sorted; all of them when there are few.
// `spacing` is the grid's cell size (0 when all were kept).
std::vector<int> thin_points(const std::vector<Vec3>& points, int max_points, double& spacing);

} // namespace odec::render::detail
