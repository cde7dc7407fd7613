// Contacts of deformable blocks (internal to the contact code).
//
// A deformable block touches its neighbours through the gridpoints on its surface, as in
// 3DEC. The common plane is found as for rigid blocks, from the block's corners (which
// follow their gridpoints). Then every surface gridpoint of a deformable block that lies
// within ctol of the plane, on a surface triangle facing it, becomes a sub-contact:
//   its area     its own share of its block's surface seen along the normal, a third of each
//                surface triangle around it that faces the plane (the nodal area);
//   its partner  the point of the other block's surface straight across the plane: on a
//                rigid block, a point of the face there (riding on that block); on a
//                deformable block, a point of the surface triangle there, held by its three
//                weights (barycentric coordinates);
//   its motion   the gridpoint's velocity against the partner point's (the triangle's
//                corner velocities weighted), so closure and shear are measured as for
//                rigid blocks and the joint law is the same;
//   its force    on the gridpoint, and the opposite force on the partner: on the rigid
//                block with its moment, or shared by the triangle's corners by weight.
// Between two deformable blocks each side's gridpoints press on the other's surface, each
// with half its area, so that the contact is the same whichever block is called a.
// A gridpoint outside the other block's footprint carries nothing.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/common_plane.h"
#include "engine/contact.h"
#include "engine/model.h"

namespace odec {

struct GridpointSub {
    std::int64_t key = 0;                 // identity across refreshes: side and gridpoint
    int side = 3;                         // 3: gridpoint of a, 4: gridpoint of b
    int gp = -1;                          // the gridpoint
    double area = 0;                      // m^2
    double closure = 0;                   // m, > 0 where the two surfaces overlap
    Vec3 local = Vec3::Zero();            // the partner point (see ContactSet::sub_point)
    std::array<int, 3> tri = {-1, -1, -1}; // partner triangle on a deformable block, else -1
    bool operator<(const GridpointSub& o) const { return key < o.key; }
};

// The surface triangles of every deformable block into cs.surface_* (when not ready).
void refresh_contact_surface(Model& m);

// Sub-contacts of blocks a < b, one of them or both deformable, across the common plane cp;
// adds the area each block face carries to face_area_a/b (for the joint-plane tag). Sorted
// by key.
void gridpoint_subcontacts(const Model& m, int a, int b, const CommonPlane& cp, double tol,
                           std::vector<GridpointSub>& out, std::vector<double>& face_area_a,
                           std::vector<double>& face_area_b);

} // namespace odec
