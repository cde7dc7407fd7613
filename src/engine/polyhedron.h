// Convex polyhedra: the shape of every block.
//
// A block is a convex polyhedron with planar faces. The layout is flat (one
// array of vertices, one array of face-vertex indices with offsets) so that a
// block owns three heap buffers however many faces it has, and the contact
// code can walk faces without chasing pointers.
//
// Faces list their vertices counter-clockwise when seen from outside, so the
// right-hand normal of each face points out of the block.
//
// Mass properties come from the divergence theorem: each face is fanned into
// triangles, each triangle with the origin spans a signed tetrahedron, and the
// tetrahedra's volume, first and second moments add up to the polyhedron's.
// The sums are exact for any closed, consistently oriented polyhedron (convex
// or not), which the unit tests check on bricks and a general shape.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct Polyhedron {
    std::vector<Vec3> vertices;     // (n_vertices) m
    std::vector<int> face_offsets;  // (n_faces + 1) start of each face in face_vertices
    std::vector<int> face_vertices; // (sum of face sizes) vertex indices, CCW from outside
    // (n_faces) joint plane that made each face: index into Model::joint_planes plus one,
    // 0 for faces made by `poly` commands. Empty means all 0.
    std::vector<int> face_joint;

    int n_vertices() const { return static_cast<int>(vertices.size()); }
    int n_faces() const { return face_offsets.empty() ? 0 : static_cast<int>(face_offsets.size()) - 1; }
    int face_size(int f) const { return face_offsets[f + 1] - face_offsets[f]; }
    int face_vertex(int f, int k) const { return face_vertices[face_offsets[f] + k]; }

    // Outward unit normal of face f (Newell's method, robust for any planar polygon).
    Vec3 face_normal(int f) const;
    // Area of face f.
    double face_area(int f) const;
    // Axis-aligned bounding box.
    void bounds(Vec3& lo, Vec3& hi) const;
    // Move every vertex by d.
    void translate(const Vec3& d);
};

// Volume, centroid and inertia tensor of a solid of unit density.
struct MassProperties {
    double volume = 0;              // m^3
    Vec3 centroid = Vec3::Zero();   // m
    Mat3 inertia = Mat3::Zero();    // m^5: inertia tensor about the centroid per unit density
};

MassProperties mass_properties(const Polyhedron& p);

// Axis-aligned box x1..x2, y1..y2, z1..z2 (each pair in increasing order).
Polyhedron make_brick(double x1, double x2, double y1, double y2, double z1, double z2);

// Build a convex polyhedron from its faces given as vertex loops (any winding).
// Shared vertices are merged within tol. Returns false and fills `error` (naming the
// face by its 1-based index) when a face is not planar, the solid is not closed or
// not convex, or it has no volume.
bool make_from_faces(const std::vector<std::vector<Vec3>>& faces, double tol, Polyhedron& out,
                     std::string& error);

// Convex hull of a set of points, as a polyhedron. Returns false with `error` when the
// points are coplanar or fewer than four.
bool make_convex_hull(const std::vector<Vec3>& points, double tol, Polyhedron& out, std::string& error);

// Split p by the plane n.x = d (n unit). `below` gets the part with n.x <= d, `above`
// the rest. Returns false (and leaves both untouched) when the plane misses p or one part
// would be thinner than tol.
bool split_by_plane(const Polyhedron& p, const Vec3& n, double d, double tol, Polyhedron& below,
                    Polyhedron& above);

// True when the point lies inside or on p (within tol).
bool contains_point(const Polyhedron& p, const Vec3& x, double tol);

// Why split_by_plane did or did not cut: the plane crossed p and both parts were kept
// (Split), the plane at most touched p (Missed), or it crossed p so close to its
// boundary that one part would be thinner than tol (Sliver).
enum class SplitOutcome { Split, Missed, Sliver };

// As split_by_plane above; the new cap face, added to both parts, gets the face_joint tag
// cap_joint, the other faces keep theirs. `outcome` (when given) says why.
bool split_by_plane(const Polyhedron& p, const Vec3& n, double d, double tol, int cap_joint,
                    Polyhedron& below, Polyhedron& above, SplitOutcome* outcome = nullptr);

// Prism between polygon a and polygon b, b being a translated copy of a (listed from any
// vertex, in either direction). Returns false with `error` when it is not a prism.
bool make_prism(const std::vector<Vec3>& a_loop, const std::vector<Vec3>& b_loop, double tol,
                Polyhedron& out, std::string& error);

// Tetrahedron with these corners (any order). Returns false with `error` when flat.
bool make_tetra(const Vec3& v1, const Vec3& v2, const Vec3& v3, const Vec3& v4, double tol,
                Polyhedron& out, std::string& error);

// A closed solid that need not be convex, as convex pieces that fill it exactly.
struct SolidPieces {
    std::vector<Polyhedron> pieces; // convex, world coordinates; one when the solid is convex
    MassProperties whole;           // of the solid itself
};

// Build the solid bounded by these faces (vertex loops, any winding), convex or not, as
// convex pieces (polyhedron_pieces.cpp). Corners within tol are merged and corners lying on
// an edge dropped, as make_from_faces does; every face must be planar within tol and a simple
// polygon, and the faces one closed shell. Each corner is then moved onto the planes of its
// faces (by at most tol), so that the faces are planar to round-off. A piece's faces on the
// solid's surface get face_joint 0, those between pieces `inner_tag`. Returns false with
// `error` (naming a face by its 1-based index) when the faces do not bound one solid.
bool make_convex_pieces(const std::vector<std::vector<Vec3>>& faces, double tol, int inner_tag, SolidPieces& out,
                        std::string& error);

// True when p is a closed, consistently outward-oriented, convex polyhedron with volume:
// every face planar within tol, every vertex on the inner side of every face plane within
// tol, every edge shared by exactly two faces in opposite directions, one shell.
// `why` (when given) gets the first problem found.
bool is_convex_polyhedron(const Polyhedron& p, double tol, std::string* why = nullptr);

} // namespace odec
