// Helpers shared by the files that build polyhedra (polyhedron_build.cpp, polyhedron_pieces.cpp):
// faces as loops of indices into one vertex array.
#pragma once

#include <string>
#include <vector>

#include "engine/polyhedron.h"

namespace odec::detail {

using Loops = std::vector<std::vector<int>>;

// Diagonal of the bounding box: the length that relative tolerances scale with.
double extent(const std::vector<Vec3>& pts);

// Faces (each a loop of corners, outward or not) as one vertex array and loops of indices into
// it: corners within tol merged (the first met stands for the others), repeated corners in a
// row dropped. False with `error` (naming the face) for fewer than 4 faces, a corner that is
// not finite, a face of fewer than 3 distinct corners, or one that visits a corner twice.
bool read_face_loops(const std::vector<std::vector<Vec3>>& faces, double tol, std::vector<Vec3>& v, Loops& loops,
                     std::string& error);

// Newell normal of a loop (twice its vector area; not normalised), taken relative to the
// loop's first vertex so that far from the origin it keeps its digits.
Vec3 loop_area_vector(const std::vector<Vec3>& v, const std::vector<int>& loop);

// Mean of a loop's vertices.
Vec3 loop_center(const std::vector<Vec3>& v, const std::vector<int>& loop);

// True when b lies on the segment a-c within tol (so that dropping b changes nothing).
bool on_segment(const Vec3& a, const Vec3& b, const Vec3& c, double tol);

// Remove from each loop the corners that only lie on a straight edge: vertices used by
// fewer than three faces that sit on the segment between their loop neighbours.
void drop_edge_vertices(const std::vector<Vec3>& v, Loops& loops, double tol);

// Flat polyhedron from loops over v, keeping only the vertices the loops use (in their
// original order). `tags` (one per loop, or empty) become face_joint unless all are 0.
Polyhedron assemble(const std::vector<Vec3>& v, const Loops& loops, const std::vector<int>& tags);

// Topology of outward-wound loops: each directed edge used once and met by its reverse,
// one shell. Returns an empty string when closed, else the problem (naming a face).
std::string closure_problem(const Loops& loops, int n_vertices);

} // namespace odec::detail
