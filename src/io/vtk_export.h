// `export vtk 'name'`: the model as VTK XML files that ParaView opens directly.
//
// Written by hand (no VTK here: only the render backend includes VTK), in ASCII with
// round-trip precision, so a file is the same bytes for the same model. Every file goes to
// a temporary name first and is renamed, so a reader never sees half a file.
//
// One export at step n writes
//   name-blocks-<n>.vtu         blocks as polyhedron cells, with cell and point data
//   name-zones-<n>.vtu          zones of deformable blocks as tetrahedra (when there are any)
//   name-contacts-<n>.vtp       contacts as points with their data (when contacts are given)
//   name-subcontacts-<n>.vtp    sub-contacts, likewise (when there are any)
//   name-cables-<n>.vtp         cables (when there are any): a line cell per segment with
//                               axial_force (N, tension positive), yield_state (0 elastic,
//                               1 yielding in tension, 2 in compression, 3 earlier), cable_id and
//                               segment; point data per node: node, displacement (m), block_id
//                               (0: no grout), grout_force (N, on the cable along it),
//                               grout_slip (m) and grout_state (0 elastic, 1 slipping,
//                               2 earlier, -1 no grout)
//   name-liners-<n>.vtp         liners (when there are any): a triangle per element with n_x,
//                               n_y, n_xy (N/m, tension positive), m_x, m_y, m_xy (N m/m, the
//                               void-side face in tension positive), in each element's frame
//                               (liner.h), liner_id and element; point data per node: node,
//                               displacement (m), block_id (0: no rock), bond_normal_force (N,
//                               compression positive), bond_shear_force (N) and bond_state
//                               (bits 1 slipping, 2 broken in tension, 4 in shear, 8 open; -1 no rock)
//   name.pvd                    the collection: entries of earlier exports are kept and this
//                               step's are added (or replaced), so ParaView plays the steps.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "engine/model.h"
#include "render/contact_view.h"

namespace odec {

// A named array of doubles with n_components per tuple (3 for vectors, 6 for symmetric
// tensors in VTK's order xx yy zz xy yz xz). Integer arrays are written as Int32.
struct VtkArray {
    std::string name;
    int n_components = 1;
    bool integer = false;
    std::vector<double> values;                  // (n_tuples * n_components)
    std::vector<std::string> component_names;    // empty, or one per component
};

// Cells that are convex polyhedra (blocks now, zones later as tetrahedra or polyhedra).
struct VtkPolyhedronMesh {
    std::vector<Vec3> points;                   // (n_points) m
    std::vector<int> cell_offsets;              // (n_cells + 1) into cell_faces
    // For each cell, its faces: each face is a count followed by that many point indices.
    std::vector<int> cell_faces;
    std::vector<VtkArray> point_data, cell_data;
    int n_cells() const { return cell_offsets.empty() ? 0 : static_cast<int>(cell_offsets.size()) - 1; }
};

// The blocks that are not excavated, with cell data block_id, material, group, region,
// displacement, displacement_magnitude, velocity, rotation and point data displacement and
// velocity (a rigid block's motion at each vertex; a deformable block's corners move with
// their gridpoints, and its velocity is the mean of theirs).
VtkPolyhedronMesh blocks_mesh(const Model& m);

bool write_vtu(const VtkPolyhedronMesh& mesh, const Model& m, const std::string& path, std::string& error);

// Cells that are tetrahedra (VTK_TETRA), corners in VTK's order: the first three seen
// counter-clockwise from the fourth, as zones keep theirs.
struct VtkTetMesh {
    std::vector<Vec3> points;               // (n_points) m
    std::vector<std::array<int, 4>> cells;  // (n_cells) point indices
    std::vector<VtkArray> point_data, cell_data;
};

// The zones of the deformable blocks that are not excavated, at the current gridpoint
// positions, with cell data
//   stress      6 components in VTK's order xx yy zz xy yz xz, Pa, tension positive
//   smin, smid, smax   principal stresses, Pa (smin the most compressive)
//   state       ZoneState bits (1 shear now, 2 tension now, 4 shear past, 8 tension past)
//   model       zone model (0 null, 1 elastic, 2 Mohr-Coulomb)
//   block_id, zone     the block's id and the zone's number (from 1, as histories name it)
// and point data gridpoint (its number, from 1), displacement (m) and velocity (m/s, at
// the time of the positions). Only the gridpoints of these zones are points.
VtkTetMesh zones_mesh(const Model& m);

bool write_tet_vtu(const VtkTetMesh& mesh, const Model& m, const std::string& path, std::string& error);
// Contacts (or sub-contacts) with their data: as points (one vertex cell each, point data),
// or, given the sub-contacts in `outline`, as patches (one polygon cell each, cell data): the
// outline of each contact's sub-contacts, as 'plot contact' shows the contact.
bool write_contacts_vtp(const ContactRows& rows, const std::vector<std::string>& state_names, const Model& m,
                        const std::string& path, std::string& error, const ContactRows* outline = nullptr);
// The patch drawn for contact i: the convex outline of its sub-contacts in its plane, else
// a square of its area about its centroid.
// `own` lists the rows of `subs` that belong to contact i.
std::vector<Vec3> contact_outline(const ContactRows& rows, const ContactRows& subs, const std::vector<int>& own,
                                  int i);

// The cables as lines (see the file list above).
bool write_cables_vtp(const Model& m, const std::string& path, std::string& error);
// The liners as triangles (see the file list above).
bool write_liners_vtp(const Model& m, const std::string& path, std::string& error);

// The whole export. `name` may carry a directory and an extension (.vtu, .vtp, .pvd, .vtk:
// dropped). `contacts` may be null (no contact files). On success `written` lists the
// files written, the .pvd last.
bool export_vtk(const Model& m, const ContactView* contacts, const std::string& name,
                std::vector<std::string>& written, std::string& error);

} // namespace odec
