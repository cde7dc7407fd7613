// An abstract picture, between the model and whatever draws it.
//
// Plot commands build a Scene from the model (scene_builder), and a backend turns
// it into pixels. Nothing here knows VTK: the only VTK user is the backend file.
// A Scene is a list of layers drawn in order; each carries its own geometry and,
// where it is coloured by a quantity, the scalar per cell or point and the
// colour map that turns it into colour (one legend per coloured layer).
//
// Zones of deformable blocks are one more PolygonLayer (the faces of their surface
// and of a section, coloured by a zone or gridpoint quantity) and one more GlyphLayer
// (principal stresses): a zone picture needs no new kind of layer.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec::render {

using Vec3 = Eigen::Vector3d;
using Rgb = std::array<double, 3>; // each 0..1

enum class ColourMap { Rainbow, CoolWarm, Viridis, Grey, Categorical };

// How a scalar becomes colour, and the legend that explains it.
struct ColourScale {
    std::string title;                 // e.g. "displacement magnitude"
    std::string units;                 // e.g. "m"
    double lo = 0, hi = 1;             // data range shown (lo == hi: a single colour)
    ColourMap map = ColourMap::Rainbow;
    std::vector<std::string> categories; // for Categorical: one name per integer value 0..n-1
    std::vector<Rgb> colours;          // for Categorical: colour of each category; empty: the palette
    bool legend = true;
};

// Planar polygons (block faces, zone faces, contact patches), each with one scalar per
// polygon or per point, or a flat colour when `scalars` is empty.
struct PolygonLayer {
    std::string name;                      // what it shows, e.g. "blocks" (for messages)
    std::vector<Vec3> points;              // (n_points) m
    std::vector<int> offsets;              // (n_polygons + 1) into indices
    std::vector<int> indices;              // point indices, CCW from outside
    std::vector<double> cell_scalars;      // (n_polygons) or empty
    std::vector<double> point_scalars;     // (n_points) or empty
    ColourScale scale;
    Rgb flat_colour{0.8, 0.8, 0.8};
    bool edges = true;                     // draw polygon outlines
    double opacity = 1.0;
    Rgb edge_colour{0.15, 0.15, 0.15};
    double edge_width = 1.0;
    // The polygons bound closed solids (blocks, zones), CCW from outside. Then a face that
    // two solids share, or that turns away from the eye, cannot be seen when the layer is
    // opaque, and the backend skips it (most of the faces of a jointed rock mass).
    bool closed = false;
    // Lit like solids (faces told apart by shading), or drawn in their true colour from
    // either side: patches lying in a plane (contacts) must read the same from both.
    bool lit = true;
    // The polygons are the faces of a mesh (zones): their edges are left out when the layer is
    // translucent, where the edges of the faces behind would show through as a thicket.
    bool mesh = false;
};

// Arrows or bars at points: velocity and displacement vectors, principal stresses.
struct GlyphLayer {
    enum class Shape { Arrow, Bar } shape = Shape::Arrow; // Bar: double-headed line, for stresses
    std::vector<Vec3> origins;             // (n_glyphs) m
    std::vector<Vec3> directions;          // (n_glyphs) vector whose length is scaled to `length`
    std::vector<double> scalars;           // (n_glyphs) colour value, or empty for flat
    double max_length = 0;                 // m drawn for the largest glyph; 0: chosen from the model
    ColourScale scale;
    Rgb flat_colour{0.1, 0.1, 0.1};
};

// Polylines in 3D (outlines, section traces).
struct LineLayer {
    std::vector<Vec3> points;
    std::vector<std::array<int, 2>> segments;
    Rgb colour{0, 0, 0};
    double width = 1.0;
};

// Text anchored at a 3D point.
struct Label {
    Vec3 at = Vec3::Zero();
    std::string text;
};

// A 2D line chart (histories).
struct ChartSeries {
    std::string name;
    std::vector<double> x, y;
};
struct Chart {
    std::string x_label, y_label;
    std::vector<ChartSeries> series;
    bool markers = false;              // a marker at every sample (few samples)
};

struct Camera {
    // Direction from the model towards the eye, and the up vector. The backend fits the
    // model's bounds into the frame.
    Vec3 eye_direction{1, -1, 0.8};
    Vec3 up{0, 0, 1};
    bool eye_given = false;   // `view eye x,y,z`: an eye point rather than a direction
    Vec3 eye_point = Vec3::Zero();
    bool parallel = false;    // orthographic projection (axis views, sections)
    double zoom = 1.0;        // > 1 magnifies after the bounds are fitted
};

struct Scene {
    std::string title;                 // model title, step and time
    std::vector<PolygonLayer> polygons;
    std::vector<GlyphLayer> glyphs;
    std::vector<LineLayer> lines;
    std::vector<Label> labels;
    Chart chart;                       // when non-empty series, the picture is a chart
    Camera camera;
    Rgb background{1, 1, 1};
    int width = 1024, height = 768;
    bool is_chart() const { return !chart.series.empty(); }
};

// Colour of a map at t in 0..1 (clamped); the backend and the tests share these tables.
Rgb colour_at(ColourMap map, double t);
// Colour of category k (0-based) of the Categorical map; repeats after a dozen.
Rgb category_colour(int k);
// Colour of category k of a scale: its own colour when it gives one, else the palette's.
Rgb category_colour(const ColourScale& scale, int k);
// The colour of value v under a scale (lo..hi; Categorical: v is the category number).
Rgb scale_colour(const ColourScale& scale, double v);

} // namespace odec::render
