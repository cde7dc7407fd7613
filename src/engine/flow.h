// Fluid flow along the joints (as 3DEC does it): the cubic law between flow nodes at the
// sub-contacts, the pore pressure pushing on both faces of each joint, and the joint law on
// effective normal stress.
//
// Flow nodes. Every sub-contact of a joint is a flow point; points of any
// contacts that stand at one place (within a thousandth of the contact tolerance) are one node, so
// water passes from one joint to the next across block edges. A node holds a pressure p (Pa, >= 0:
// a joint holds no suction) and a volume V = sum over its sub-contacts of aperture x area share.
//
// Hydraulic aperture of a sub-contact, m:  a = azero - un, held between ares and amax (amax 0: no
// cap), un the joint's closure from the motion (> 0 closed; sub_un of contact.h). So a joint under
// an effective normal stress sn' (closure sn'/jkn) has the aperture azero - sn'/jkn, an open joint
// azero plus its gap. azero, ares and amax are joint material properties ('prop jmat').
//
// Links. Each contact polygon (its sub-contacts ordered around their centre, seen along the
// contact normal) is fanned into triangles; over each triangle the pressure is linear, and the
// conductance of the flow between two of its corners i, j is that of a parallel-plate channel,
// a^3 / (12 mu) times cot(theta_k) / 2, theta_k the triangle's angle at its third corner (the
// linear finite-element weights: exact for a pressure that varies linearly over the joint). The
// weights of a link summed over its triangles are held at zero or above; a is the mean of the
// apertures at its two ends. Flow from i to j, m^3/s:
//     q = c (p_i - p_j - rho g . (x_i - x_j))     (g the model's gravity, rho the fluid's density)
// so a hydrostatic field p = rho |g| (z_w - z) moves nothing. A free node at zero pressure is dry and
// gives no water, so the joints above a water table stay dry (a node driven below zero by what leaves
// it within a sub-step is held at zero: the only place water is not conserved exactly).
//
// Update. A free node's pressure changes by Kw dt / V times the net inflow (Kw the fluid's bulk
// modulus), held at zero or above; a node with a fixed pressure ('bound pp') keeps it. Two modes:
//   steady     (the default) each mechanical step the flow takes 'substeps' sub-steps, each node at
//              its own stable step V / (Kw sum c) times 0.8 (its storage scaled, as masses are in a
//              static analysis): the pressures head for the steady field, not along a real path in
//              time. A node with no volume (a point of no area) takes the mean of its neighbours'
//              pressures weighted by the conductances.
//   transient  the flow follows the model's time: each mechanical step of dt it advances dt in
//              equal sub-steps no larger than 0.8 of the smallest node's stable step; the change of a
//              node's volume as the joint opens or closes counts (a closing joint squeezes its
//              water: dp = Kw (q dt - dV) / V).
//
// Forces. At every sub-contact the node's pressure times the sub-contact's wetted area pushes the two
// blocks apart along the contact normal (p A n on block b, -p A n on block a, at the sub-contact),
// beside the joint's own spring force. The joint's springs carry the effective stress: the joint law
// (joint_law.cpp) computes sn' = jkn x closure and Coulomb's limit c + sn' tan(phi) on it, so a joint
// slips sooner and opens once the pressure passes the total normal stress.
//
// State. A node's pressure and whether it is fixed are kept with its position (saved); when contact
// detection changes the sub-contacts, the nodes are made again and each new node takes the state of
// the old node nearest it within half the contact tolerance (none: a water table gives it the
// hydrostatic pressure, else 0).
//
// Zoned (deformable) blocks. Their sub-contacts are gridpoints (contact_gridpoint.h). Links come
// from the block's surface triangles whose corners are flow points and that lie along the joint,
// block by block (so water passes between the joints one face meets). Between two zoned faces one
// leads and the other follows (the larger face follows): a following node takes the pressure of the
// point it meets on the leading face and gives that triangle's corners its inflow and volume, by the
// weights. A gridpoint's wetted share (sub_wet) is its area on triangles flat to the joint whose
// partner surface is flat too, shared between joints flat to the same triangle, so that contacts
// grazing a face across a joint crossing do not push the water a second time. Glued contacts
// (joined cuts) carry no flow.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/polyhedron.h"

namespace odec {

struct Model;
struct Range;

enum class FlowMode : std::uint8_t { Steady = 0, Transient = 1 };

struct FlowSet {
    // ---- settings (saved) ----
    bool configured = false;       // 'config flow'
    bool on = false;               // 'set flow on|off'
    FlowMode mode = FlowMode::Steady;
    int substeps = 1;              // steady: flow sub-steps per mechanical step
    double density = 1000;         // kg/m^3, fluid
    double viscosity = 1e-3;       // Pa s, dynamic viscosity
    double bulk = 2e9;             // Pa, fluid bulk modulus
    bool has_wtable = false;       // 'insitu pp wtable z' or 'bound pp wtable z' given
    double wtable = 0;             // m, elevation of the water table (along -gravity; z without gravity)
    double time = 0;               // s, flow time (transient)
    long steps = 0;                // flow sub-steps taken

    // ---- per node (saved) ----
    std::vector<Vec3> pos;         // (n_nodes) m, where the node stands
    std::vector<double> pp;        // (n_nodes) Pa, pore pressure (>= 0)
    std::vector<std::uint8_t> fixed; // (n_nodes) 1: pressure held ('bound pp')
    std::vector<double> last_volume; // (n_nodes, or empty) m^3, at the previous step (transient: the
                                     //   change of volume squeezes the water); empty: none yet

    // ---- derived (not saved), made again when the contacts change ----
    long revision = -1;            // ContactSet::revision the nodes were made for
    long rebuilds = 0;             // times the nodes were made (for tests and profiling)
    std::uint64_t shape = 0;       // fingerprint of the contacts the nodes were made from (a refresh
                                   //   that keeps it keeps the nodes and links)
    int n_subs_seen = -1;
    std::vector<int> sub_node;     // (n_subs) node of each sub-contact (-1: none, deformable)
    std::vector<double> sub_aperture; // (n_subs) m, hydraulic aperture
    std::vector<double> sub_wet;   // (n_subs) share of the sub-contact's area the water wets (1 between
                                   //   rigid blocks; a gridpoint's area on faces flat to the joint)
    std::vector<double> volume;    // (n_nodes) m^3
    std::vector<double> inflow;    // (n_nodes) m^3/s, net inflow of the last sub-step
    std::vector<double> area;      // (n_nodes) m^2, sum of the sub-contact areas
    // Nodes that take their pressure from others (a gridpoint of one zoned block facing a zoned
    // block's face: the corners of the triangle it meets, by their weights). CSR by node; empty
    // rows for the nodes that are their own.
    std::vector<int> follow_offset;   // (n_nodes + 1)
    std::vector<int> follow_node;     // the nodes followed
    std::vector<double> follow_w;     // their weights (summing to 1)
    std::vector<int> link_a, link_b;   // (n_links) the two nodes
    std::vector<int> link_sa, link_sb; // (n_links) the two sub-contacts (for the aperture)
    std::vector<double> link_w;        // (n_links) width / length of the channel (>= 0)
    std::vector<double> link_q;        // (n_links) m^3/s, from a to b, last sub-step
    double dt = 0;                 // s, last sub-step (transient) or smallest node step (steady)
    std::vector<Vec3> block_force;  // (n_blocks) N, the pressure's force on each block, last step
    std::vector<Vec3> block_moment; // (n_blocks) N m, its moment about the centroid

    int n_nodes() const { return static_cast<int>(pp.size()); }
    int n_links() const { return static_cast<int>(link_a.size()); }
    // Drop the derived arrays: made again at the next sync.
    void invalidate() { revision = -1; n_subs_seen = -1; }
};

// Whether the model's fluid flow is configured ('config flow').
inline bool flow_configured(const FlowSet& f) { return f.configured; }

// Make the flow nodes and links again when the contacts changed since they were made, carrying
// the pressures and fixities of the old nodes by position.
void flow_sync(Model& m);
// The hydraulic aperture of every sub-contact and the volume of every node, from the joints now.
void flow_apertures(Model& m);
// Contacts detected if the model changed, then flow_sync: the nodes as they stand now.
void flow_ready(Model& m);
// What 'bound pp' and 'insitu pp' set, at the nodes a range selects.
struct PressureSpec {
    bool wtable = false;           // hydrostatic below the water table (FlowSet::wtable)
    double p = 0;                  // Pa, at the origin
    Vec3 grad = Vec3::Zero();      // Pa/m
};
// Sets the pressure of the nodes `nodes` (fixing them when `fix`); returns how many.
int set_flow_pressure(Model& m, const std::vector<int>& nodes, const PressureSpec& spec, bool fix);
// The flow's own stable step, s: 0.8 of the smallest V / (Kw sum c) over the free nodes; 1 s when no
// free node stores water, 0 with no nodes. The model's timestep when nothing else sets one (every
// block held: the flow alone is computed).
double flow_stable_timestep(Model& m);
// Problems that keep the model from cycling with flow on ("" when none).
std::string flow_problem(const Model& m);
// One mechanical step of dt: the pressures advance (steady or transient) and push on the blocks.
// Returns "" or why the flow could not advance.
std::string flow_step(Model& m, double dt);
// The hydrostatic pressure at x under the water table (0 above it or without one), Pa.
double hydrostatic_pressure(const Model& m, const Vec3& x);
// The nodes a range selects (location filters test the node, region, group and id filters the
// blocks of its first sub-contact's contact).
std::vector<int> flow_nodes_in_range(const Model& m, const Range& r);
// Index of the node nearest x, or -1 when there are none.
int flow_node_at(const Model& m, const Vec3& x);
// Mean pressure (Pa) and aperture (m) of contact c's sub-contacts, weighted by their areas, and
// the flow along its links (m^3/s, the sum of their |q|).
struct ContactFlow {
    double pp = 0, aperture = 0, flow = 0;
};
ContactFlow contact_flow(const Model& m, int c);
// How far the flow is from steady: the sum over the free nodes of |net inflow| over the sum of |q| over
// the links, of the last sub-step (0 without flow). 'solve' with flow on also waits for it to fall
// below its ratio.
double flow_unbalance(const Model& m);
// The flow the fixed-pressure boundaries feed into the joints, m^3/s: the sum over the nodes with a
// fixed pressure of what flows out of them into the network (those the water leaves by not counted;
// in steady flow the two are equal).
double fixed_inflow(const Model& m);

} // namespace odec
