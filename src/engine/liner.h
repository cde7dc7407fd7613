// Liners and shotcrete: thin elastic shells of flat triangles laid on the free surface of
// deformable blocks and bonded to it by springs that can fail.
//
// A liner is made on the zone faces of the surface of deformable blocks that face a void (no
// other block on their outer side) and whose three corners lie in a range. Its nodes are those
// faces' corners (one node per gridpoint), each with six degrees of freedom: three
// translations and three rotations. Each triangle is a flat shell element, in its own frame
// (x along its first edge, z its normal, away from the rock):
//   membrane   constant-strain triangle (CST): plane stress, E t / (1 - nu^2)
//   bending    discrete Kirchhoff triangle (DKT, Batoz, Bathe and Ho 1980): the rotations vary
//              quadratically, Kirchhoff's condition held at the corners and the mid-sides;
//              D = E t^3 / (12 (1 - nu^2)), integrated at the three mid-sides (exact)
//   drilling   the rotation about the normal tied to the element's in-plane rotation by a
//              small penalty (1e-3 E t A), so that it is not a free mode; a rigid motion
//              leaves it unstressed
// The element is linear (small strains and rotations): its stiffness K (18 x 18, world axes)
// is built once from the positions at creation, and its nodal forces are K times the nodes'
// displacements and rotations since then. A liner starts unstressed.
//
// Bond. Each node is tied to the rock at its position (the zone of the block it lies on, its
// gridpoints by their weights; cable.h find_rock_tie) by two springs over its share A of the
// liner's area (a third of each element around it): normal stiffness kn A and shear stiffness
// ks A (kn, ks in Pa/m), along and across the liner's normal there. Their forces grow with the
// relative velocity of node and rock times the timestep. The bond breaks in tension when the
// normal tension passes ncut A, and in shear when the shear force passes scoh A + tan(sfric)
// times the normal compression. A broken bond carries no tension and only friction (tan(sfric)
// times the compression) in shear: the liner may then come off the rock and slide on it.
// Strengths not given: no limit (the bond never breaks).
//
// Each step (the 'liners' stage, after the joints and cables, before the integration):
//   weight     each node starts with its share of the liner's weight (li_dens) under gravity
//   elements   f = -K d, d the element's nodal displacements and rotations since creation
//   bond       normal and shear forces from the relative motion, capped as above; the rock
//              takes their reaction at the tie (its gridpoints by weight)
// and, after the blocks and gridpoints are integrated:
//   nodes      velocities and spins from the forces and moments under the model's damping
//              law, then positions and rotations
// Liners are walked in order on one thread, so the sums are the same whatever the threads.
// Masses. Static mode: every node gets the mass k dt^2 and the rotational inertia kr dt^2, k and
// kr bounds on its translational and rotational stiffness (the element rows' sums of |K| and the
// bond), so that the model's timestep is its own stable one; the bond's stiffness also counts on
// the rock. Dynamic mode: the node has its real mass rho t A and the rotational inertia
// kr dt^2 (a thin shell's own is too small to matter and would set a tiny step).
//
// Sign conventions. Forces and moments per unit width in the element's report frame: x the
// direction in the element's plane across the liner's axis (axis x normal; around the tunnel
// for a tunnel's axis), y = normal x x. n_x, n_y, n_xy membrane forces, N/m, tension positive
// (the thrust of a tunnel lining, compression positive, is -n_x); m_x, m_y, m_xy bending
// moments, N m/m, positive when the face away from the rock (the opening's side) is in tension.
// Bond forces: normal force on the liner, N, positive in compression (the rock pushing the
// liner off); shear force on the liner, N (its magnitude).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/polyhedron.h"

namespace odec {

struct Model;
struct AutoDampingSums;
struct Range;

// Shell and bond of a liner (`prop mat=n li_e ... li_thick ...`).
struct LinerMaterial {
    bool defined = false;
    double e = 0;        // Pa, Young's modulus
    double nu = 0;       // Poisson's ratio
    double thick = 0;    // m, thickness
    double density = 0;  // kg/m^3
    double kn = 0;       // Pa/m, bond normal stiffness per unit area
    double ks = 0;       // Pa/m, bond shear stiffness per unit area
    double ncut = -1;    // Pa, bond tensile strength (< 0: not given: no limit)
    double scoh = -1;    // Pa, bond shear cohesion (< 0: not given: no limit)
    double sfric = 0;    // deg, bond friction angle
};

// State bits of a node's bond.
enum LinerBondState : std::uint8_t {
    kBondSlipNow = 1,       // the shear force is at its limit this step
    kBondBrokenTension = 2, // broke in tension
    kBondBrokenShear = 4,   // broke in shear
    kBondOpen = 8,          // broken and open (no contact) this step
};

struct LinerSet {
    // Liners, by index: elements elem_offset[c] .. elem_offset[c+1]-1, nodes node_offset[c] ..
    std::vector<int> id;            // (n_liners) user id, 1-based, never reused
    std::vector<int> material;      // (n_liners) material number
    std::vector<Vec3> axis;         // (n_liners) unit axis of the report frame
    std::vector<int> node_offset;   // (n_liners + 1)
    std::vector<int> elem_offset;   // (n_liners + 1)
    int next_id = 1;

    // Nodes.
    std::vector<Vec3> pos0;         // m, position at creation
    std::vector<Vec3> pos;          // m, current position
    std::vector<Vec3> vel;          // m/s at t - dt/2
    std::vector<Vec3> spin;         // rad/s at t - dt/2
    std::vector<Vec3> u;            // m, displacement since creation (element forces)
    std::vector<Vec3> rot;          // rad, rotation since creation (small)
    std::vector<Vec3> disp;         // m, since creation or the last 'reset disp'
    std::vector<Vec3> force;        // N, unbalanced force of this step
    std::vector<Vec3> moment;       // N m, unbalanced moment of this step
    std::vector<double> force_scale;// N, sum of the magnitudes of the forces on it this step
    std::vector<double> area;       // m^2, share of the liner's area
    std::vector<Vec3> normal;       // unit, the liner's normal there (away from the rock)
    std::vector<double> mass;       // kg, rho t A
    std::vector<double> inertial_mass;   // kg
    std::vector<double> inertial_moment; // kg m^2
    std::vector<int> host_block;    // block id of the rock it is bonded to, 0: none
    std::vector<Vec3> host_lever;   // rigid host: body-frame lever
    std::vector<std::array<int, 4>> host_gp;   // deformable host: zone gridpoints
    std::vector<std::array<double, 4>> host_w; // their weights
    std::vector<double> bond_n;     // N, normal force on the liner, compression positive
    std::vector<Vec3> bond_s;       // N, shear force on the liner (world axes)
    std::vector<std::uint8_t> state;// LinerBondState bits

    // Elements.
    std::vector<std::array<int, 3>> elem; // node indices (counter-clockwise seen from the void)

    // Derived (not saved; rebuilt from pos0 and the materials when empty or stale).
    std::vector<std::array<double, 324>> k;  // (n_elem) world-axes stiffness, 18 x 18 row-major
    std::vector<double> stiff_t, stiff_r;    // (n_nodes) stiffness bounds, N/m and N m

    std::vector<LinerMaterial> materials; // index = material number (0 unused)

    int size() const { return static_cast<int>(id.size()); }
    int n_nodes() const { return static_cast<int>(pos.size()); }
    int n_elements() const { return static_cast<int>(elem.size()); }
    int index(int liner_id) const;
    // The liner an element or a node belongs to.
    int liner_of_element(int e) const;
    int liner_of_node(int i) const;
};

// Stress resultants of an element at its centroid, in its report frame (see the top).
struct LinerResultants {
    double nx = 0, ny = 0, nxy = 0; // N/m, tension positive
    double mx = 0, my = 0, mxy = 0; // N m/m, opening-side face in tension positive
    Vec3 centroid = Vec3::Zero();
    Vec3 x_dir = Vec3::UnitX(), normal = Vec3::UnitZ();
};

// Make a liner of material `mat` on the free zone faces whose corners are all in `range`,
// report frame axis `axis` (zero: the range's cylinder axis, else z). Returns its index, or -1
// with `why` set; the model is unchanged then.
int add_liner(Model& m, const Range& range, int mat, const Vec3& axis, std::string& why);

// Remove the liners with these indices.
void remove_liners(Model& m, std::vector<int> liners);

// Why the liners cannot cycle, or "".
std::string liners_problem(const Model& m);
// Re-tie nodes whose rock changed; rebuild element stiffness.
void attach_liner_nodes(Model& m);
// Element stiffnesses and the nodes' stiffness bounds from pos0 and the materials.
void build_liner_stiffness(LinerSet& ls);
// The same when they are missing (after 'restore': they are not saved).
void refresh_liner_stiffness(LinerSet& ls);

// The liners' own stable timestep with real masses (translations), s (0: none).
double liner_critical_timestep(const Model& m);
// Inertial masses for the timestep m.dt; in dynamic mode the real ones, raised where `mscale`
// asks for a step (raise_to, s; 0: none) that the node's real mass would not allow. Returns ""
// or why not.
std::string choose_liner_masses(Model& m, double raise_to = 0);
// The bond's stiffness on the rock (into gridpoint k, N/m; rigid blocks kt, kr by index).
void add_liner_gridpoint_stiffness(const Model& m, std::vector<double>& k);
void add_liner_block_stiffness(const Model& m, std::vector<double>& kt, std::vector<double>& kr);

// The liners stage: element and bond forces (into the nodes and the rock), then, once the rock's
// forces are all in, the nodes' motion; integrate_liners returns the index of a node whose motion
// became non-finite, or -1.
void liner_forces(Model& m, double dt);
int integrate_liners(Model& m, double dt, AutoDampingSums* sums = nullptr);

LinerResultants liner_resultants(const LinerSet& ls, int e);

double liner_strain_energy(const Model& m);
double liner_max_unbalanced(const Model& m);
void liner_unbalanced_sums(const Model& m, double& unbal, double& total);

int nearest_liner_element(const Model& m, const Vec3& x);
int nearest_liner_node(const Model& m, const Vec3& x);

void reset_liner_displacements(Model& m);

} // namespace odec
