// The common-plane search on raw vertex arrays (internal to the contact code).
#pragma once

#include "engine/contact.h"
#include "engine/polyhedron.h"

namespace odec {

// A convex block as the search sees it: world vertices and the face lists that join them.
struct BlockView {
    const Vec3* v = nullptr;              // (n_vertices) world positions
    const Polyhedron* topo = nullptr;     // faces (its own vertex positions are not used)
    int n_vertices() const { return topo->n_vertices(); }
};

// See find_common_plane in contact.h; `band` <= 0 searches every feature.
CommonPlane common_plane(const BlockView& a, const BlockView& b, const Vec3* warm, double band,
                         double prefer_joint = 0);

// The reference point of the common plane of a and b with unit normal n: midway between the
// means of their vertices, moved along n onto the plane midway in the gap (ContactSet keeps no
// point: contact_point derives it from the blocks as they stand).
Vec3 plane_point(const BlockView& a, const BlockView& b, const Vec3& n);

// Outward unit normal of face f from world vertices (Newell), and its area.
Vec3 world_face_normal(const BlockView& v, int f, double* area = nullptr);

} // namespace odec
