// From the model to a Scene: what the `plot` command calls. No VTK here.
//
// A picture is built in three moves: begin_scene() sets the frame (size, view, background,
// title with the model title, step and time); each plot item adds its layers (add_blocks,
// add_zones, add_vectors, add_contacts, add_principal, add_block_outline, add_history_chart); the
// backend draws the result (vtk_backend.h: render_png). Items layer in the order they are
// added, and every coloured layer brings its own legend. One PlotOptions serves all items of
// one picture; `set plot` keeps one between plots.
//
//   PlotOptions opt;                       // defaults: 1024x768, iso view, white, all blocks
//   Scene s = begin_scene(m, opt);
//   add_blocks(s, m, BlockColour::Disp, opt);
//   add_vectors(s, m, VectorKind::Disp, opt);
//   render_png(s, "plot-0001.png", error);
//
// Deformable blocks are drawn from their zones (zone_scene.cpp): the faces of the zones on
// the surface of the blocks drawn, at the gridpoints' positions, and where a cut crosses them
// the polygon in which the plane meets each tetrahedron. `plot block` draws them so (coloured
// by gridpoint values for displacements and velocities), `plot zone` colours the same faces by
// a zone quantity, and their principal stresses are a PrincipalField for add_principal.
// `magnify m` draws every point at its original place plus m times its displacement.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "engine/history.h"
#include "engine/model.h"
#include "render/contact_view.h"
#include "render/scene.h"

namespace odec::render {

// What colours the blocks (`plot block <quantity>`).
enum class BlockColour { Flat, Disp, XDis, YDis, ZDis, Vel, XVel, YVel, ZVel, Group, Material, Region, Fixed };
// `plot vector disp|vel`.
enum class VectorKind { Disp, Vel };
// `plot contact nstress|sstress|ndis|sdis|state|pp|aperture`.
enum class ContactQuantity { NormalStress, ShearStress, NormalDisp, ShearDisp, State, PorePressure, Aperture };
// `plot zone sxx|syy|szz|sxy|sxz|syz|smin|smid|smax|state|disp`: stress components and
// principal stresses (Pa, tension positive; smin the most compressive), the plastic state, and
// the gridpoints' displacement magnitude.
enum class ZoneQuantity { SXX, SYY, SZZ, SXY, SXZ, SYZ, SMin, SMid, SMax, State, Disp };

// A section (`cut plane origin x,y,z normal nx,ny,nz`): what lies on the side the normal
// points to is cut away, so the eye, looking against the normal, sees the cut faces.
struct CutPlane {
    Vec3 origin = Vec3::Zero();
    Vec3 normal{0, -1, 0};
};

struct PlotOptions {
    int width = 1024, height = 768;             // `size w h`, pixels
    Camera camera;                              // `view ...` (see camera_for_view); iso by default
    bool view_given = false;                    // false: a cut looks straight at its face
    Rgb background{1, 1, 1};
    std::optional<ColourMap> map;               // none: rainbow for magnitudes, cool-warm for signed
    std::optional<std::vector<int>> blocks;     // block indices from `range ...`; none: all shown
    std::optional<CutPlane> cut;                // `cut plane ...`
    std::optional<std::pair<double, double>> limits; // fixed colour scale lo, hi (`set plot scale`)
    bool edges = true;                          // draw block edges
    bool ids = false;                           // label each block drawn with its id
    // Zones from `range ...` (indices); none: every zone of the blocks drawn.
    std::optional<std::vector<int>> zones;
    // The picture has a zone item: add_blocks leaves the deformable blocks to it.
    bool zone_item = false;
    // Points drawn at their original place plus `magnify` times their displacement (1: where
    // they are). Rigid blocks are moved by their displacement so, not turned.
    double magnify = 1.0;
};

// Camera for a view name: "iso", "x", "-x", "y", "-y", "z", "-z" (the eye on that axis,
// looking at the model). Returns false for another name.
bool camera_for_view(const std::string& name, Camera& camera);
// Camera for `view eye x,y,z`.
Camera camera_for_eye(const Vec3& eye);

// "<model title>\nstep <n>   time <t> s" (the title line is "odec" when the model has none).
std::string scene_title(const Model& m);

// An empty picture framed by the options: size, view, background, title.
Scene begin_scene(const Model& m, const PlotOptions& opt);

// Blocks (not hidden, not excavated; within opt.blocks), coloured by `by`, clipped by
// opt.cut with their cut faces outlined. Deformable blocks are drawn from their zones, their
// displacements and velocities from the gridpoints (then the layer has point scalars).
void add_blocks(Scene& scene, const Model& m, BlockColour by, const PlotOptions& opt);

// The zones drawn: active zones (not null, not excavated) of shown blocks within opt.blocks,
// or the indices of opt.zones that are such zones; sorted.
std::vector<int> zones_to_draw(const Model& m, const PlotOptions& opt);

// Zones coloured by `q` (one value per zone; `disp` per gridpoint, interpolated): the faces on
// the surface of the zones drawn, or with opt.cut those below the plane and the section
// polygons, as one closed layer named "zones", with block outlines over it. Returns the number
// of zone polygons added (0: nothing drawn).
int add_zones(Scene& scene, const Model& m, ZoneQuantity q, const PlotOptions& opt);

// Block edges as thin lines: context for vectors and contacts without hiding them.
void add_block_outline(Scene& scene, const Model& m, const PlotOptions& opt);

// Cables as thin square tubes, one per segment, coloured by the segment's axial force (N,
// tension positive), at the nodes' positions (with opt.magnify, their original place plus
// magnify times their displacement). Returns the number of segments drawn.
int add_cables(Scene& scene, const Model& m, const PlotOptions& opt);

// Liners as their triangles, coloured by each element's membrane force n_x (N/m, tension
// positive; liner.h), at the nodes' positions (with opt.magnify as cables). Returns the number of
// elements drawn.
int add_liners(Scene& scene, const Model& m, const PlotOptions& opt);

// Arrows of block displacement or velocity at the centroids. Coloured by magnitude with a
// legend unless the scene already has a coloured layer (then dark, so the two do not
// compete); block layers already in the scene are made translucent so the arrows show.
void add_vectors(Scene& scene, const Model& m, VectorKind kind, const PlotOptions& opt);

// Contact patches (sub-contacts when the view has them, else contacts), each a square of
// its area on its plane, coloured by the quantity. Returns false with `error` when the
// view's arrays are inconsistent.
bool add_contacts(Scene& scene, const ContactView& contacts, ContactQuantity q, const PlotOptions& opt,
                  std::string& error);

// Principal stresses at points: zones or contacts. value[k] is signed, compression
// negative, and goes with the unit direction direction[k].
struct PrincipalField {
    std::vector<Vec3> points;                       // (n)
    std::vector<std::array<double, 3>> value;       // (n) Pa
    std::vector<std::array<Vec3, 3>> direction;     // (n) unit
    double typical_size = 0;                        // m, length of the largest bar (0: renderer's choice)
    // Colour by sign alone (compression, tension), not by the signed value: for zones, where
    // the two must be told apart at a glance however small the bar.
    bool by_sign = false;
    int n_sampled_from = 0;                         // zones: how many there were to choose from
};
// On contacts a principal field has the normal stress along the normal and the shear stress
// along the shear direction (the third is zero).
PrincipalField principal_from_contacts(const ContactView& contacts);
// On zones (zones_to_draw): the three principal stresses at the zone centroids. A picture of
// many zones would be a thicket, so at most about `max_points` zones are taken, one in each
// cell of a regular grid over them; with opt.cut only the zones the plane crosses, with
// their bars on the plane.
PrincipalField principal_from_zones(const Model& m, const PlotOptions& opt, int max_points = 1200);
// Double-headed bars, length proportional to |value|, coloured by the signed value (or by sign).
void add_principal(Scene& scene, const PrincipalField& field, const PlotOptions& opt);

// Shorthand for the commonest picture: blocks coloured by `by`, default options, the given
// block indices (empty: all shown blocks).
Scene build_block_scene(const Model& m, BlockColour by, const std::vector<int>& block_indices);

// Histories `numbers` (1-based) against step, or against history `vs` when vs > 0, as a line
// chart with axis titles and a legend, into `scene` (frame from begin_scene). Returns false
// with `error` naming the first history that does not exist, or when there are no samples.
bool add_history_chart(Scene& scene, const HistorySet& h, const std::vector<int>& numbers, int vs,
                       std::string& error);
// The same as a Scene of its own (default size, title "histories").
Scene build_history_chart(const HistorySet& h, const std::vector<int>& numbers, int vs);

// Name, units and whether signed, for legends and messages ("displacement magnitude", "m").
struct QuantityInfo {
    std::string title, units;
    bool is_signed = false;
};
QuantityInfo block_colour_info(BlockColour by);
QuantityInfo contact_quantity_info(ContactQuantity q);
QuantityInfo zone_quantity_info(ZoneQuantity q);
// Names of the zone states, in the order of their category numbers.
const std::vector<std::string>& zone_state_names();

} // namespace odec::render
