// Tetrahedral meshes of convex blocks, for zoning deformable blocks.
//
// The mesher is Gmsh's library (Debian's libgmsh-dev, GPL-2-or-later with exceptions,
// compatible with odec's GPL-3), opened at the first zoning: its frontal-Delaunay surface
// mesher and Delaunay volume mesher
// give zones of good quality quickly, and, because all the blocks of one call are given to
// it as one geometry in which a face shared by two blocks (the same polygon) is one surface,
// the meshes of neighbouring blocks conform on their shared faces node for node.
//
// Delaunay meshes of thin slices keep flat tetrahedra whose corners all lie on the surface
// (slivers, which set the timestep of the whole model); mesh/tet_improve.h removes them after
// the mesher, without changing the surface meshes.
//
// This file knows nothing of the model: blocks go in as polyhedra, nodes and tetrahedra come
// out. The engine decides which blocks share nodes (joined ones) and which get copies.
#pragma once

#include <array>
#include <atomic>
#include <string>
#include <vector>

#include "engine/polyhedron.h"

namespace odec {

struct TetMesh {
    std::vector<Vec3> nodes;                         // (n_nodes) m, shared by all the solids
    std::vector<std::vector<std::array<int, 4>>> tets; // (n_solids) node indices, positive volume
    std::vector<std::vector<int>> corner_node;       // (n_solids) node of each vertex of the solid
    std::vector<std::vector<int>> face_surface;      // (n_solids) per face: which surface it is; two
                                                     // solids with a face on one surface share its nodes
    std::vector<double> solid_worst;                 // (n_solids) smallest radius ratio in each
    double worst_quality = 1;                        // smallest radius ratio 3 r_in / r_out (1: regular)
    double mean_quality = 1;
};

// Mesh each convex solid into tetrahedra of mean edge length about edges[s] (m): a vertex
// shared by solids takes the smallest, and sizes grade in between. Zones of a radius ratio
// under 0.2 are then improved (mesh/tet_improve.h): solids of ordinary shape (convex, aspect
// ratio under 20) get none under 0.1 at any edge; a solid too thin for the edge may. Returns "" on success,
// else why not (the mesher's own message). The same solids and edges give the same mesh, bit
// for bit, whatever the session did before. The mesher runs in a child process: raising
// *interrupt (Ctrl-C) stops it within a tenth of a second, with "interrupted: ..." returned.
std::string mesh_solids(const std::vector<Polyhedron>& solids, const std::vector<double>& edges, TetMesh& out,
                        const std::atomic<bool>* interrupt = nullptr);

// Radius ratio of a tetrahedron: 3 r_in / r_circumscribed, 1 for a regular one, 0 when flat.
double radius_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

} // namespace odec
