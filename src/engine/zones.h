// Deformable blocks: tetrahedral zones and their gridpoints.
//
// A deformable block is divided into tetrahedral zones of uniform strain (`gen edge`). Its
// degrees of freedom are the translations of the zones' corners, the gridpoints; the block's
// own centroid and rotation are no longer integrated, its corners follow their gridpoints.
// Blocks that are joined and zoned together share the gridpoints of their common faces and
// act as one continuum ("body"); other neighbours keep gridpoints of their own.
//
// Each step, for every zone:
//   velocity gradient  L = sum_i v_i (x) grad N_i from its four gridpoint velocities
//                      (grad N_i from the zone's corners: the rows of the inverse edge matrix)
//   mixed discretization: the volumetric part of L is replaced by the mean, over the zone's
//                      corners, of the volume-weighted average volumetric rate of the zones
//                      around each corner (nodal mixed discretization). A single tetrahedron
//                      has one strain for four corners and locks when plastic flow keeps the
//                      volume constant; the averaged volumetric rate gives a mesh of them the
//                      freedom to flow, so collapse loads come out right.
//   stress increment   from the strain increment D dt by the zone's model (zone_model.h); in
//                      large strain the stress is first rotated with the spin (Jaumann).
//   corner forces      f_i = -V sigma grad N_i, gathered on the gridpoints with gravity
//                      (mass rho V / 4 per corner) and the applied tractions.
// Gridpoints are then integrated by central differences with the same damping as blocks.
//
// Sign convention of zone stresses: tension positive (Pa), as in the classic codes and the
// `insitu` and `bound stress` commands.
//
// Stable timestep: for lumped masses m_i and stiffness K, central differences need
// dt < 2 / omega_max; omega_max^2 is bounded by the largest row sum of |K_ij| / m_i, and for an
// isotropic tetrahedron |K_ij| <= V (K + 4G/3) |grad N_i| |grad N_j|.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "engine/polyhedron.h"

namespace odec {

struct Model;
struct Range;

// Zone constitutive models (`change cons=c`).
enum ZoneModel : std::uint8_t { kZoneNull = 0, kZoneElastic = 1, kZoneMohrCoulomb = 2 };

// Plastic state of a zone.
enum ZoneState : std::uint8_t {
    kShearNow = 1,     // at the shear yield surface this step
    kTensionNow = 2,   // at the tension cut-off this step
    kShearPast = 4,    // yielded in shear at some earlier step
    kTensionPast = 8,  // yielded in tension at some earlier step
};

// Stress or strain as six components: xx yy zz xy xz yz.
using Sym6 = std::array<double, 6>;

// Zones per chunk of the zone stage's colouring (see ZoneSet::color_order).
constexpr int kZoneChunk = 256;

struct ZoneSet {
    std::vector<std::array<int, 4>> gp;  // (n_zones) gridpoint indices, positive orientation
    std::vector<int> block;              // (n_zones) block index
    std::vector<std::uint8_t> model;     // (n_zones) ZoneModel
    std::vector<std::uint8_t> state;     // (n_zones) ZoneState bits
    std::vector<Sym6> stress;            // (n_zones) Pa, tension positive
    std::vector<double> volume;          // (n_zones) m^3, at the geometry in use
    // Derived from the gridpoint positions (the current ones in large strain, those when zoned in
    // small strain) and refreshed when they change; empty until first needed.
    std::vector<std::array<double, 9>> grad; // (n_zones) 1/m, gradients of the shape functions of
                                          //            corners 1..3 (corner 0's is minus their sum)
    // Derived (not saved), rebuilt when stale: chunks of kZoneChunk consecutive zones by colour,
    // no two chunks of one colour sharing a gridpoint, so that threads can add into the
    // gridpoints colour by colour (parallel.h). Colours in order, chunks in order within each.
    std::vector<int> color_order;        // (n_chunks) chunk indices
    std::vector<int> color_offset;       // (n_colours + 1) first entry of each colour
    int colored_zones = 0;               // the number of zones they were made for

    int size() const { return static_cast<int>(gp.size()); }
};

// A face of a zone on the surface of its continuum, loaded by `bound stress`.
struct BoundaryFace {
    std::array<int, 3> gp;   // its corners
    Vec3 force;              // N, traction times area, shared equally by the three corners
    int table = 0;           // table scaling the force by model time ('hist table n'), 0 none
};

struct GridpointSet {
    std::vector<Vec3> pos;               // (n_gp) m, current position
    std::vector<Vec3> ref;               // (n_gp) m, position when zoned (small-strain geometry)
    std::vector<Vec3> vel;               // (n_gp) m/s at t - dt/2
    std::vector<Vec3> disp;              // (n_gp) m since the last `reset disp`
    std::vector<Vec3> force;             // (n_gp) N, unbalanced force of this step
    std::vector<Vec3> applied;           // (n_gp) N, `bound xload ...` forces
    std::vector<int> applied_table;      // (n_gp) table scaling `applied` by model time, 0 none
    std::vector<Vec3> traction;          // (n_gp) N, `bound stress` (from the loaded faces)
    std::vector<double> mass;            // (n_gp) kg, rho V / 4 of the zones around
    std::vector<double> inertial_mass;   // (n_gp) kg, what the integration divides forces by
                                         //        (mass_scaling.h); gravity acts on `mass`
    std::vector<double> stiffness;       // (n_gp) N/m, for the timestep
    std::vector<double> force_scale;     // (n_gp) N, sum of magnitudes of the forces this step
    std::vector<double> nmd_volume;      // (n_gp) m^3, volume of the zones around (scratch)
    std::vector<double> nmd_rate;        // (n_gp) m^3/s, volume-weighted volumetric rate (scratch)
    std::vector<int> block;              // (n_gp) a block it belongs to (the first)
    std::vector<std::uint8_t> vel_bc;    // (n_gp) bit k: velocity component k prescribed
    std::vector<Vec3> vel_bc_value;      // (n_gp) m/s, prescribed velocity components
    std::vector<int> vel_bc_table;       // (n_gp) table scaling vel_bc_value, 0 none
    std::vector<std::uint8_t> half_kick; // (n_gp) 1: velocity given at t, first kick is dt/2

    int size() const { return static_cast<int>(pos.size()); }
};

// Faces loaded by `bound stress` (each face once; a new stress on a face replaces the old).
struct StressBoundary {
    std::vector<BoundaryFace> faces;
};

// A tetrahedral mesh for some blocks, as the mesher gives it: `nodes` shared by all, per block
// its tetrahedra and the node at each of its polyhedron's vertices.
struct BlockMesh {
    std::vector<Vec3> nodes;
    std::vector<std::vector<std::array<int, 4>>> tets;  // parallel to `blocks`
    std::vector<std::vector<int>> corner_node;          // parallel to `blocks`
};

// Make `blocks` deformable with this mesh (replacing zones they had). Blocks in the same body
// (body[k] equal) share gridpoints at shared nodes; others get copies. The zones take each
// block's zone model (BlockSet::cons) and start unstressed; gridpoints start at rest.
void zone_blocks(Model& m, const std::vector<int>& blocks, const std::vector<int>& body, const BlockMesh& mesh);

// Remove the zones and gridpoints of these blocks (they become rigid again, or are deleted).
void remove_zones(Model& m, const std::vector<int>& blocks);

// Gridpoint masses and stiffnesses from the zones' materials (after `prop`, `change`, zoning).
void update_gridpoint_masses(Model& m);

// Corner positions of deformable blocks from their gridpoints (into blocks.world_vertices).
void refresh_deformable_vertices(Model& m);

// Why the zones cannot cycle (a zone without material, elastic moduli missing...), or "".
std::string zones_problem(const Model& m);

// The stiffness of each gridpoint for the timestep, N/m: the zones' bound (`stiffness`) and the
// joints that can press on it (see zone_critical_timestep).
// joint_factor: a margin on the joints' part, whose bound holds on average over a joint but
// not at every gridpoint where the meshes of its two sides do not match.
std::vector<double> gridpoint_stiffness(const Model& m, double joint_factor = 1.0);

// Largest stable timestep of the zones, s (0 when there are none). Where a deformable block
// has something to touch, the stiffest joint material on its surface gridpoints counts too
// (the contact surface must be ready: refresh_contact_surface).
double zone_critical_timestep(const Model& m);

// Zone stage of the cycle: strain rates, stresses, and the forces of the zones, gravity and
// applied loads on the gridpoints (into gridpoints.force). `scale` also sums force magnitudes
// into force_scale, for the unbalanced-force ratio.
void zone_forces(Model& m, double dt);

// Gridpoint integration is part of the integrate stage (stages.h).

// Gridpoints of deformable blocks (not excavated) that the range selects by their position.
std::vector<int> select_gridpoints(const Model& m, const Range& r);

// The faces of active zones that no other active zone shares (the surface of each continuum),
// each as its zone and the corner opposite it (0..3).
std::vector<std::pair<int, int>> boundary_faces(const Model& m);

// Apply the stress s + x gx + y gy + z gz (tension positive) as a traction on every boundary
// face whose centre the range selects, replacing what `bound stress` put there before; times
// table `table` of model time when it is not 0. Returns the number of faces loaded.
int apply_boundary_stress(Model& m, const Range& r, const Sym6& s, const Sym6& gx, const Sym6& gy,
                          const Sym6& gz, int table = 0);
// The tractions of the loaded faces without a table, summed on their corners (gridpoints.traction);
// the faces with a table are added as the model cycles.
void recompute_tractions(Model& m);
// Remove `bound stress` from the faces the range selects; returns how many.
int remove_boundary_stress(Model& m, const Range& r);

// Set the stress of every active zone whose centroid the range selects to s + x gx + y gy + z gz.
// Returns the number of zones set.
int set_insitu_stress(Model& m, const Range& r, const Sym6& s, const Sym6& gx, const Sym6& gy, const Sym6& gz);

// Velocity of gridpoint g at the time of its position.
Vec3 gridpoint_velocity_at_t(const Model& m, int g);

// Principal stresses of s, smallest (most compressive) first, and their directions (columns).
void principal_stresses(const Sym6& s, Vec3& values, Mat3* directions = nullptr);

// Centroid of zone z at the current geometry.
Vec3 zone_centroid(const Model& m, int z);

// Index of the zone containing x (or the one whose centroid is nearest), -1 when none.
int find_zone_at(const Model& m, const Vec3& x);
// Index of the gridpoint nearest x, -1 when none.
int find_gridpoint_near(const Model& m, const Vec3& x);
// Index of the gridpoint of block b (index) nearest x, -1 when it has none.
int find_gridpoint_of_block_near(const Model& m, int b, const Vec3& x);

// True when the block is deformable.
bool is_deformable(const Model& m, int block_index);

} // namespace odec
