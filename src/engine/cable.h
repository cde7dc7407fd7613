// Fully grouted cables and rock bolts: axial bars of steel, bonded to the rock along their
// length by a grout annulus that can slip.
//
// A cable is a straight line cut into segments; its nodes carry three translational degrees of
// freedom. Each segment is an axial spring of stiffness E A / L0 between its two nodes, elastic
// and perfectly plastic: its axial force (tension positive, N) stays between -ycomp and ytens.
// Each node is tied to the rock at its position, the host: a rigid block (the material point of
// the block there: centroid velocity plus spin times the lever) or the zone of a deformable block
// that holds it (its four gridpoints, by the barycentric weights of the node in the zone).
// Across the cable's axis the node moves with the host (a rigid tie, so bends of the cable push
// on the rock); along the axis it is coupled to the host by the grout, a shear spring of
// stiffness kbond L (N/m/m times the node's share L of the cable's length) whose force is capped
// at sbond L (sbond: the bond strength per unit length, N/m): past it the grout slips, keeping
// that force, without softening. A node outside every block has no grout and moves freely.
//
// Each step (the 'cables' stage, after the joints and before the integration):
//   weight     each node starts with the weight of its share of steel (cb_dens) under gravity
//   segments   axial force += E A / L0 * (v_j - v_i) . t dt, capped at ytens / -ycomp
//   grout      shear force += -kbond L (v_node - v_host) . t dt, capped at sbond L
//   forces     the node keeps the axial part of its segment and grout forces; the host takes the
//              grout's reaction and the node's force across the axis, at the host's material
//              point (rigid) or shared by the weights (gridpoints). Cables are walked in order,
//              one thread, so the sums are the same whatever the number of threads.
// and, in the integration stage, after the blocks and gridpoints have moved:
//   nodes      the axial velocity from the axial force and the node's mass (with the model's
//              damping law), the velocity across the axis the host's at the material point.
//
// Masses. In dynamic mode a node has the mass rho A L of its share of steel (cb_dens). In static
// mode, as gridpoints do (mass_scaling.h), every node gets the mass k (dt / 1.8)^2 with which its
// own stable step is the model's timestep, k = kbond L + 2 sum E A / L0 over its segments (a
// bound on its axial stiffness); the grout's stiffness also counts on its host, so that the rock
// around a cable stays stable. With no contacts or zones to set the timestep, the cables' own
// stable step with real masses sets it.
//
// Pretension: the segments start with that axial force; the grout then carries it into the rock
// (and slips where it cannot).
//
// Sign conventions: axial force tension positive (N); the grout force is the force of the grout
// on the cable along the cable's direction (from its first node to its last), N; the slip is the
// plastic relative displacement of the cable against the rock along that direction, m.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/polyhedron.h"

namespace odec {

struct Model;
struct AutoDampingSums;

// Steel and grout of a cable (`prop mat=n cb_area ... cb_sbond ...`).
struct CableMaterial {
    bool defined = false;
    double area = 0;     // m^2, steel cross-section
    double e = 0;        // Pa, Young's modulus of the steel
    double ytens = 0;    // N, tensile yield force (0: not given: no limit)
    double ycomp = 0;    // N, compressive yield force (0: carries no compression)
    double kbond = 0;    // N/m/m, grout shear stiffness per unit length
    double sbond = 0;    // N/m, grout bond strength per unit length (0: not given: no limit)
    double density = 0;  // kg/m^3, of the steel (dynamic mode)
};

// State bits of a segment and of a node's grout.
enum CableState : std::uint8_t {
    kCableYieldTensionNow = 1,   // segment: at its tensile yield this step
    kCableYieldCompNow = 2,      // segment: at its compressive yield this step
    kCableYieldPast = 4,         // segment: yielded at some earlier step
    kGroutSlipNow = 8,           // node: the grout slips this step
    kGroutSlipPast = 16,         // node: the grout slipped at some earlier step
};

struct CableSet {
    // Cables, by index; segment k of cable c joins nodes node_offset[c] + k and + k + 1, and is
    // segment node_offset[c] - c + k of the segment arrays.
    std::vector<int> id;               // (n_cables) user id, 1-based, never reused
    std::vector<int> material;         // (n_cables) cable material number
    std::vector<int> node_offset;      // (n_cables + 1)
    int next_id = 1;

    // Nodes.
    std::vector<Vec3> pos;             // (n_nodes) m, current position
    std::vector<Vec3> vel;             // (n_nodes) m/s at t - dt/2
    std::vector<Vec3> disp;            // (n_nodes) m, since creation or the last 'reset disp'
    std::vector<Vec3> force;           // (n_nodes) N, unbalanced force of this step (axial part
                                       //          for a node tied to the rock)
    std::vector<double> length;        // (n_nodes) m, share of the cable's length
    std::vector<double> mass;          // (n_nodes) kg, rho A L
    std::vector<double> inertial_mass; // (n_nodes) kg, what the integration divides forces by
    std::vector<double> stiffness;     // (n_nodes) N/m, axial stiffness bound (timestep, masses)
    std::vector<int> host_block;       // (n_nodes) block id of the rock it is tied to, 0: none
    std::vector<Vec3> host_lever;      // (n_nodes) m, rigid host: the material point from its
                                       //          centroid, body frame
    std::vector<std::array<int, 4>> host_gp;     // (n_nodes) deformable host: its zone's gridpoints
                                                 //          (-1: rigid host or none)
    std::vector<std::array<double, 4>> host_w;   // (n_nodes) their weights
    std::vector<double> grout_force;   // (n_nodes) N, on the cable along its direction
    std::vector<double> slip;          // (n_nodes) m, plastic slip of the grout
    std::vector<std::uint8_t> state;   // (n_nodes) CableState grout bits
    std::vector<std::uint8_t> vel_bc;  // (n_nodes) 1: velocity prescribed
    std::vector<Vec3> vel_bc_value;    // (n_nodes) m/s

    // Segments.
    std::vector<double> axial;         // (n_segments) N, tension positive
    std::vector<double> rest_length;   // (n_segments) m, L0
    std::vector<std::uint8_t> seg_state; // (n_segments) CableState yield bits

    std::vector<CableMaterial> materials; // index = material number (0 unused)

    int size() const { return static_cast<int>(id.size()); }
    int n_nodes() const { return static_cast<int>(pos.size()); }
    int n_segments() const { return static_cast<int>(axial.size()); }
    int first_segment(int c) const { return node_offset[c] - c; }
    int segments_of(int c) const { return node_offset[c + 1] - node_offset[c] - 1; }
    // Index of the cable with this id, or -1.
    int index(int cable_id) const;
};

// Ties to the rock, shared by cables and liners (liner.h). A point is tied to the first block
// (in the order blocks were made) that holds it: a rigid block's material point (its body-frame
// lever from the centroid), or a deformable block's zone (its four gridpoints and the point's
// barycentric weights, clipped to the zone just outside it). block_id 0: in no rock.
void find_rock_tie(const Model& m, const Vec3& x, int& block_id, Vec3& lever, std::array<int, 4>& gp,
                   std::array<double, 4>& w);
// Whether such a tie still stands (its block neither deleted, excavated nor zoned anew).
bool rock_tie_holds(const Model& m, int block_id, const Vec3& lever, const std::array<int, 4>& gp);
// Whether a node re-tied from block old_block_id (0: none) to block new_block_id is in the same
// rock as before: its old block still stands (not deleted or excavated: only zoned again, or cut)
// and holds it again. Grout and bond forces are kept only then.
bool rock_tie_kept(const Model& m, int old_block_id, int new_block_id);
// Velocity of the tied material point at t - dt/2; `index` receives the block's index (-1: none).
Vec3 rock_tie_velocity(const Model& m, int block_id, const Vec3& lever, const std::array<int, 4>& gp,
                       const std::array<double, 4>& w, int& index);

// Add a cable from p1 to p2 cut into n_segments, of cable material `mat` (which must be defined
// with a positive area and modulus), with this pretension (N). Its nodes are tied to the blocks
// holding them. Returns its index, or -1 with `why` set.
int add_cable(Model& m, const Vec3& p1, const Vec3& p2, int n_segments, int mat, double pretension,
              std::string& why);

// Tie the nodes whose rock changed (blocks cut, deleted, excavated or zoned anew), and those in no
// rock, to the rock holding them now: a rigid block's material point, or a deformable block's
// zone and weights. A node keeps a tie that still stands.
void attach_cable_nodes(Model& m);

// Why the cables cannot cycle (a material undefined), or "".
std::string cables_problem(const Model& m);

// The cables' own stable timestep with real masses, s (0: no cables or no masses).
double cable_critical_timestep(const Model& m);
// Choose the nodes' inertial masses for the timestep m.dt (static: from their stiffness; dynamic:
// real, raised to allow `raise_to` when > 0). Returns "" or why not.
std::string choose_cable_masses(Model& m, double raise_to);

// The grout's stiffness on the rock: added to each gridpoint's (k, N/m), and to each rigid
// block's translational (kt, N/m) and rotational (kr, N m) sums, by block index.
void add_cable_gridpoint_stiffness(const Model& m, std::vector<double>& k);
void add_cable_block_stiffness(const Model& m, std::vector<double>& kt, std::vector<double>& kr);

// The cables stage: segment and grout forces, onto the nodes and into the rock.
void cable_forces(Model& m, double dt);
// Part of the integration stage, after blocks and gridpoints: the nodes' velocities and positions.
// Returns the index of a node whose motion became non-finite, or -1.
int integrate_cables(Model& m, double dt, AutoDampingSums* sums = nullptr);

// Elastic energy stored in the segments and the grout, J.
double cable_strain_energy(const Model& m);
// Largest unbalanced force on a free cable node, N (0: none).
double cable_max_unbalanced(const Model& m);
// Adds the free nodes' unbalanced forces to `unbal` and the sums of the magnitudes of the forces
// on them (segments and grout) to `total`, N, for the unbalanced-force ratio.
void cable_unbalanced_sums(const Model& m, double& unbal, double& total);

// The segment nearest x: its index in the segment arrays, -1 when there are none; `cable`
// receives the cable's index.
int nearest_cable_segment(const Model& m, const Vec3& x, int& cable);
// The node nearest x, -1 when none.
int nearest_cable_node(const Model& m, const Vec3& x, int& cable);

// Remove the cables with these indices.
void remove_cables(Model& m, std::vector<int> cables);

// Cables of the model follow 'reset disp'.
void reset_cable_displacements(Model& m);

} // namespace odec
