// Tunnel geometry: rock around a straight tunnel as convex blocks, joined into one mass.
//
// The pattern is the same for a new box of rock (`poly tunnel`) and for blocks that already
// exist (`tunnel`): in the cross-section, the tunnel wall is a regular polygon of n sides with
// the area of the circle of the given radius, and around it lie rings of blocks bounded by
// radial planes through the axis at the polygon's corners and by larger regular polygons
// (the rings) with their corners on the same rays. Ring thicknesses grow by a ratio from the
// wall outward. Planes across the axis divide the whole into segments.
#pragma once

#include <string>
#include <vector>

#include "engine/model.h"
#include "engine/range.h"

namespace odec {

struct TunnelSpec {
    Vec3 a = Vec3::Zero();        // m, start of the axis
    Vec3 b = Vec3::UnitY();       // m, end of the axis
    double radius = 1;            // m; the wall polygon has the area of a circle of this radius
    int n_sides = 16;             // sides of the wall polygon: the rays and the sectors around the axis
    int n_rings = 4;              // layers of rock blocks outside the wall
    double ratio = 0;             // thickness of a layer over that of the layer inside it; 0: the
                                  // ratio that makes the ring radii grow geometrically
    int n_segments = 1;           // slices along the axis
    // `poly tunnel`: half-sizes of the box across the axis, along the frame's u and v (m).
    double half_u = 0, half_v = 0;
    // `tunnel`: the radius of the circle whose area the outermost ring has (m).
    double outer_radius = 0;
};

// The tunnel's frame: w along the axis from a to b; u horizontal and square to the axis (x when
// the axis is vertical); v = u x w, the upward one of the two directions square to both (y when
// the axis is vertical). For an axis along +y, u = +x and v = +z.
struct TunnelFrame {
    Vec3 u = Vec3::UnitX(), v = Vec3::UnitZ(), w = Vec3::UnitY();
    double length = 0; // m, |b - a|
};
TunnelFrame tunnel_frame(const Vec3& a, const Vec3& b);

// Distance from the axis to the corners of the regular n-gon with the area of a circle of
// radius r: r sqrt(2 pi / (n sin(2 pi / n))), about 1.3 % more than r for n = 16.
double equal_area_circumradius(double r, int n);

// Why spec cannot be built, with `keyword` naming the word to blame ("radius", "box", "ratio",
// "nrad", "a"...), or "" when it can. `box` says whether spec is a `poly tunnel` (bounded by
// half_u and half_v) or a `tunnel` cut (bounded by outer_radius).
std::string tunnel_problem(const TunnelSpec& spec, bool box, std::string& keyword);

// One block of a `poly tunnel`, in world coordinates.
struct TunnelBlock {
    Polyhedron shape;
    int layer = 0;    // 0: the core inside the wall; k >= 1: the k-th ring of rock from the wall
    int segment = 0;  // 0-based from a to b
    int sector = -1;  // 0-based around the axis from +u toward +v; -1 for the core
};

// The blocks of a box of rock around a tunnel (spec must pass tunnel_problem with box = true):
// per segment, the core (one prism on the wall polygon) and n_sides blocks in each of n_rings
// rings, the last of which reaches the box. Faces between two of these blocks carry the face
// tag joint_tag; the box's outer faces and the two ends carry 0. Neighbouring blocks share
// their faces exactly: the same corners, computed once. Returns false with `error` when a
// block comes out invalid (which tunnel_problem should have prevented).
bool make_tunnel_blocks(const TunnelSpec& spec, int joint_tag, std::vector<TunnelBlock>& out, std::string& error);

// The cut of existing blocks by the pattern of `spec` (which must pass tunnel_problem with
// box = false), worked out before the model changes. Each block that reaches into the wall
// or the rings between a and b is cut, in world axes about its centroid: by the planes across
// the axis at a and at b (where they cross it) and between the segments, then by the radial
// planes through the axis at the polygon's corners (the wall's sectors, which go on to the
// block's own faces), then in each sector by the chords of the wall and of every ring. The
// core is the n wedges inside the wall. Every new face carries joint_tag. A cut that would
// leave a piece thinner than sliver_tol is not made. A block the rings do not reach is left
// whole.
struct TunnelCutPlan {
    std::vector<int> blocks;                        // indices of the blocks to cut
    std::vector<Vec3> origins;                      // (blocks) m, each block's centroid
    std::vector<std::vector<Polyhedron>> pieces;    // (blocks) its pieces, world axes, about the centroid
    std::vector<std::vector<int>> layers;           // (blocks)(pieces) 0: inside the wall; k: ring k;
                                                    //   n_rings + 1: beyond the rings; -1: beyond a or b
    int slivers_skipped = 0;                        // cuts not made
    long n_pieces() const;
};
TunnelCutPlan plan_tunnel_cut(const Model& m, const TunnelSpec& spec, const std::vector<int>& targets, int joint_tag,
                              double sliver_tol);

// Carry out a plan: each block is replaced by its pieces (the first keeps its index and id;
// see replace_by_pieces). The pieces inside the wall join group core_group (-1: keep theirs).
// A cut through a piece of a clump ends the clump (clump.h). Returns how many clumps ended.
int apply_tunnel_cut(Model& m, const TunnelCutPlan& plan, int core_group);

// The 2D cross-section (coordinates along u and v) of every ring corner: ring k, ray j, for
// rings 0 (the wall) to n_rings - 1 (poly tunnel, whose last ring is the box) or n_rings (tunnel).
std::vector<std::vector<Eigen::Vector2d>> tunnel_rings(const TunnelSpec& spec, bool box);

} // namespace odec
