// Removal of slivers from tetrahedral meshes, after the mesher.
//
// Gmsh's Delaunay mesher leaves flat tetrahedra ("slivers") whose four corners all lie on the
// surface of a block, typically across thin slices (a plane-strain section one or two zones
// thick): the two faces of the slice get the same triangulation, and the Delaunay choice
// among the co-spherical corners of a quadrilateral across the slice is often the flat one.
// Gmsh's own optimizer moves only interior nodes and swaps only edges of bad tetrahedra
// (its face swaps are disabled), so these survive it; they set the timestep of the model.
//
// This pass works on one solid's tetrahedra at a time and never changes the triangulation of
// a solid's surface (the meshes of neighbouring blocks stay conforming node for node) nor
// moves a node on it: it flips faces (2-3) and removes edges (n tetrahedra around an edge
// into 2n-4, the 3-2 and 4-4 flips among them), moves interior nodes to raise the worst
// tetrahedron around them, and, where that is not enough, splits an interior edge at a new
// node and moves that node. Every change raises the worst quality of the tetrahedra it
// replaces, so the pass ends; it is deterministic (the same mesh in gives the same out).
#pragma once

#include <array>
#include <vector>

#include "engine/polyhedron.h"

namespace odec {

struct TetImproveStats {
    long flips = 0;   // face flips and edge removals done
    long moves = 0;   // interior nodes moved
    long splits = 0;  // edges split (one node added each)
};

// Raises the tetrahedra of each solid below quality `target` (radius ratio) as far as the
// operations above can. tets[s] are node indices with positive volume; nodes added by
// splits are appended to `nodes`. Nodes on the surface of a solid stay where they are.
TetImproveStats improve_tets(std::vector<Vec3>& nodes, std::vector<std::vector<std::array<int, 4>>>& tets,
                             double target);

} // namespace odec
