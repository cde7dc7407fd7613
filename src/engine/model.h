// The model: everything the cycle runs on, and nothing about how it was typed.
//
// Blocks are held as a structure of arrays indexed by block_index (0..n_blocks-1);
// each block also has a user-visible id that never changes and is never reused,
// so that `range id 7` means the same block after others were deleted.
//
// A rigid block keeps its shape in its own body frame, relative to its centroid;
// the world position of each vertex is centroid + R * local, refreshed once per
// step into the flat array `world_vertices` that contact detection reads.
//
// Deformable blocks keep their zones and gridpoints beside BlockSet, in a ZoneSet and a
// GridpointSet of their own (zones.h); a zone knows its block, a deformable block the
// gridpoints at its corners.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "engine/cable.h"
#include "engine/contact.h"
#include "engine/energy.h"
#include "engine/flow.h"
#include "engine/history.h"
#include "engine/insitu.h"
#include "engine/liner.h"
#include "engine/polyhedron.h"
#include "engine/table.h"
#include "engine/zones.h"

namespace odec {

using Quat = Eigen::Quaterniond;

// Block material (`prop mat=n`).
struct Material {
    bool defined = false;
    double density = 0;   // kg/m^3
    double bulk = 0;      // Pa (deformable blocks)
    double shear = 0;     // Pa
    double cohesion = 0;  // Pa
    double friction = 0;  // deg
    double tension = 0;   // Pa
    double dilation = 0;  // deg
};

// Joint material (`prop jmat=n`).
struct JointMaterial {
    bool defined = false;
    double kn = 0;            // Pa/m
    double ks = 0;            // Pa/m
    double friction = 0;      // deg
    double cohesion = 0;      // Pa
    double tension = 0;       // Pa
    double dilation = 0;      // deg
    double zdilation = 0;     // m, shear displacement at which dilation stops (0: no limit)
    double res_friction = 0;  // deg (joint model 2)
    double azero = 0;         // m, hydraulic aperture at zero effective normal stress (flow.h)
    double ares = 0;          // m, residual (smallest) hydraulic aperture
    double amax = 0;          // m, largest hydraulic aperture (0: no cap)
};

// A plane cut by `jset`: the faces it makes on both sides carry its number, so that
// contacts across it know their joint set, joint material and whether it was joined.
struct JointPlane {
    int set = 0;          // which `jset` command made it (1-based, in order)
    bool joined = false;  // `jset ... join`: the two sides are glued
    int jmat = 0;         // joint material for contacts across it (0: Settings::default_jmat)
};

// What put a load on a rigid block: 'bound xload ... xmoment ...' (a force at a point and a
// couple), or 'bound stress' (the traction on one boundary face).
enum class LoadKind : std::uint8_t { Point = 0, Face = 1 };

// A load on a rigid block ('bound'): a force at a material point of the block and a couple,
// both times a table of time. The force and the couple keep their directions in world axes as
// the block turns; the point turns with the block. Its moment about the centroid is
// (R lever) x force + couple, R the block's orientation.
struct BlockLoad {
    LoadKind kind = LoadKind::Point;
    int table = 0;                 // table scaling force and couple by model time ('hist table n'), 0 none
    Vec3 lever = Vec3::Zero();     // m, the point of application from the centroid, body frame
    Vec3 force = Vec3::Zero();     // N, world axes
    Vec3 couple = Vec3::Zero();    // N m, world axes
};

// Degrees of freedom of a block that a boundary condition prescribes.
enum BlockFlags : std::uint8_t {
    kFixed = 1,      // `fix`: velocity and spin held at zero
    kHidden = 2,     // `hide`: left out of jset and pictures
    kExcavated = 4,  // `excavate`: null block, kept for a later `fill`
    kDeformable = 8, // divided into zones (`gen edge`): its gridpoints move, not the block
};

struct BlockSet {
    std::vector<int> id;                  // (n_blocks) user id, 1-based, never reused
    std::vector<Polyhedron> shape;        // (n_blocks) vertices relative to centroid, body frame
    std::vector<Vec3> centroid;           // (n_blocks) m
    std::vector<Quat> orientation;        // (n_blocks) body frame -> world
    std::vector<Vec3> vel;                // (n_blocks) m/s at t - dt/2
    std::vector<Vec3> ang_vel;            // (n_blocks) rad/s at t - dt/2
    std::vector<Vec3> accel;              // (n_blocks) m/s^2 last applied (for velocity at t)
    std::vector<Vec3> ang_accel;          // (n_blocks) rad/s^2 last applied
    std::vector<Vec3> force;              // (n_blocks) N, unbalanced force of this step
    std::vector<Vec3> moment;             // (n_blocks) N m about the centroid
    std::vector<std::vector<BlockLoad>> loads; // (n_blocks) `bound xload ...`, `bound stress`
    std::vector<double> force_scale;      // (n_blocks) N, sum of magnitudes of forces this step
    std::vector<Vec3> disp;               // (n_blocks) m, of the centroid since the last `reset disp`
    // (n_blocks) body frame -> world at the last `reset disp` (or when the block was made): the
    // material point at body offset p was then at centroid - disp + ref_orientation * p, so every
    // point's displacement and the block's turn since then are exact for any rotation
    // (point_displacement, rotation_since_reset).
    std::vector<Quat> ref_orientation;
    std::vector<double> volume;           // (n_blocks) m^3
    std::vector<double> mass;             // (n_blocks) kg
    std::vector<Mat3> inertia_body;       // (n_blocks) kg m^2 about centroid, body frame
    std::vector<Mat3> inertia_unit;       // (n_blocks) m^5, inertia per unit density, body frame
    // What the integration divides forces by (mass_scaling.h): the real mass and inertia in
    // dynamic mode (raised for the few blocks 'mscale' scales), masses chosen from the contact
    // stiffness in static mode. Gravity always acts on the real mass.
    std::vector<double> inertial_mass;    // (n_blocks) kg
    std::vector<double> inertial_moment;  // (n_blocks) kg m^2, isotropic; 0: the real inertia tensor
                                          //            times inertial_mass / mass
    std::vector<int> material;            // (n_blocks) material number (`change mat`)
    std::vector<int> region;              // (n_blocks) region number given at creation
    std::vector<int> group;               // (n_blocks) index into Model::group_names, -1 none
    std::vector<std::uint8_t> flags;      // (n_blocks) BlockFlags
    std::vector<std::uint8_t> vel_bc;     // (n_blocks) bit k: velocity component k prescribed
    std::vector<Vec3> vel_bc_value;       // (n_blocks) m/s, prescribed velocity components
    std::vector<int> vel_bc_table;        // (n_blocks) table number scaling vel_bc_value, 0 none
    std::vector<std::uint8_t> half_kick;  // (n_blocks) 1: velocity given at t, first kick is dt/2
    std::vector<std::uint8_t> cons;       // (n_blocks) zone model its zones get (ZoneModel)
    std::vector<std::vector<int>> corner_gp; // (n_blocks) deformable: gridpoint at each vertex; else empty
    std::vector<double> zone_edge;        // (n_blocks) m, deformable: the edge length it was zoned with
    std::vector<int> body;                // (n_blocks) deformable: continuum it belongs to (blocks zoned
                                          //            together and joined share gridpoints), 1-based; rigid 0
    std::vector<int> clump;               // (n_blocks) rigid piece of a solid that is not convex: the clump it
                                          //            moves with as one rigid body (clump.h), named by the id
                                          //            its first piece was given; 0: a block alone

    // Derived, refreshed every step: world vertex positions of all blocks.
    std::vector<int> vertex_offset;       // (n_blocks + 1) start of each block in world_vertices
    std::vector<Vec3> world_vertices;     // (sum of n_vertices) m
    std::vector<Mat3> rotation;           // (n_blocks) each block's orientation as a matrix, made with the
                                          //            world vertices (the contact update turns its
                                          //            sub-contacts' points by it)
    bool vertices_behind = false;         // the rigid blocks' world vertices are those of an earlier
                                          //            step (refresh_block_rotations): only within a
                                          //            cycle, until catch_up_world_vertices

    int size() const { return static_cast<int>(id.size()); }
};

// Cycle stages, timed into Profile.
enum class Stage { ApplyLoads, DetectContacts, UpdateContacts, Zones, Integrate, Record, Checks, Cables, Flow, Liners, Count };
const char* stage_name(Stage s);

struct Profile {
    double seconds[static_cast<int>(Stage::Count)] = {};
    long steps = 0;
};

enum class DampingMode { Local, Auto, Rayleigh, Off };

struct Damping {
    DampingMode mode = DampingMode::Local;
    double local = 0.8;             // local damping coefficient
    double rayleigh_fraction = 0;   // critical damping fraction
    double rayleigh_frequency = 0;  // Hz
    double auto_coefficient = 0;    // adaptive global damping: current viscous coefficient (1/s)
    // Adaptive damping's memory of the last step (AutoDampingSums): the sum of v.f over the free
    // degrees of freedom with the velocities it gave (N m/s), and of m v.v with them (kg m^2/s^2).
    double auto_after = 0;
    double auto_inertia = 0;
    // s, the timestep of that step, which moved the model by those velocities (0: not known, as
    // in files of format 15, taken as the timestep of the next step).
    double auto_dt = 0;
};

// Adaptive damping's fraction of critical for the frequency the model shows (integrate.cpp):
// its coefficient is 2 * kAutoDampingFraction * omega.
constexpr double kAutoDampingFraction = 0.7;

// What adaptive damping (integrate.cpp) gathers over the free degrees of freedom of a step
// (translations and rotations of blocks and clumps, gridpoints' components), f being the
// unbalanced force (or moment) of the step and m the inertial mass (or moment): the sums of v.f
// with the velocities before (`before`) and after (`after`) the step's kick, and of m v.v after.
struct AutoDampingSums {
    double before = 0, after = 0, inertia = 0;
    void add(double m, double f, double v0, double v1) {
        before += v0 * f;
        after += v1 * f;
        inertia += m * v1 * v1;
    }
    void add(const AutoDampingSums& o) {
        before += o.before;
        after += o.after;
        inertia += o.inertia;
    }
};

struct Settings {
    double dt_fixed = 0;      // s; > 0 when `set dt` forces a timestep
    double dtfrac = 0.1;      // fraction of the critical timestep
    double ctol = 0;          // m contact tolerance; 0: chosen from block sizes
    int default_jmat = 1;     // joint material of newly created contacts (`set jmat`)
    int default_jcons = 1;    // joint model of newly created contacts
    bool large_strain = true; // rigid blocks always move by large displacements
    // Static or dynamic analysis (mass_scaling.h). Static, with density scaling, unless
    // `config dyn` was given; `set dyn on|off` switches once it was.
    bool dyn_configured = false; // `config dyn`
    bool dynamic = false;        // real masses and real time
    double mscale_dt = 0;        // s; > 0: `mscale`: in dynamic mode, masses that would need a
                                 // smaller timestep are raised to allow this one
    // m; `set ovtol`: the deepest overlap allowed, when cycling starts, between blocks that
    // carry no stress yet; 0: kOverlapFraction of the smaller block's size.
    double ovtol = 0;
};

// The overlap tolerance unless 'set ovtol' gives one: this fraction of the size (the cube root
// of the volume) of the smaller of two blocks.
constexpr double kOverlapFraction = 0.005;

// What the last choice of inertial masses did, for the commands to report.
struct MassScalingReport {
    bool fresh = false;        // chosen again since the commands last reported it
    bool is_static = false;    // static mode: every mass from its stiffness
    double dt = 0;             // s, the timestep they allow
    double real_dt = 0;        // s, the timestep real masses would need
    int n_gridpoints = 0;      // mscale: gridpoint masses raised
    int n_blocks = 0;          // mscale: block masses raised
    int n_nodes = 0;           // mscale: cable and liner node masses raised
    double added = 0;          // kg, mscale: mass added
    double total = 0;          // kg, real mass of what moves
    double min_factor = 0;     // mscale: smallest and largest factor applied to a raised mass
    double max_factor = 0;
};

// The largest step number: cycling stops there with an error rather than count past what a
// long holds (about 9.2e18), and a save file holding more is refused.
constexpr long kMaxStep = 1000000000000000000L; // 1e18

// A flag that counts how often it was set: whoever saw count() when it last acted knows
// whether anything changed since, though the flag stays set until the cycle clears it.
class ChangeFlag {
public:
    ChangeFlag& operator=(bool v) {
        value = v;
        if (v) ++count_;
        return *this;
    }
    operator bool() const { return value; }
    std::uint64_t count() const { return count_; }
    bool value = true; // read and written as such by save and restore

private:
    std::uint64_t count_ = 1;
};

struct Model {
    std::string title;
    BlockSet blocks;
    std::vector<Material> materials;            // index = material number (0 unused)
    std::vector<JointMaterial> joint_materials; // index = joint material number (0 unused)
    std::vector<std::string> group_names;
    std::vector<JointPlane> joint_planes;       // face_joint k refers to joint_planes[k-1]
    int n_joint_sets = 0;                       // `jset` commands so far
    int slivers_skipped = 0;                    // cuts not made because a piece would be a sliver
    ContactSet contacts;
    ZoneSet zones;                              // tetrahedral zones of deformable blocks
    GridpointSet gridpoints;                    // their corners
    CableSet cables;                            // cables and rock bolts (cable.h)
    FlowSet flow;                               // fluid flow in the joints (flow.h)
    LinerSet liners;                            // liners and shotcrete (liner.h)
    StressBoundary stress_boundary;             // faces loaded by `bound stress`
    std::vector<InsituRecord> insitu;           // `insitu` fields, in order, for zones made later
    HistorySet histories;
    TableSet tables;
    Vec3 gravity = Vec3::Zero();  // m/s^2
    Damping damping;
    Settings settings;
    Profile profile;
    MassScalingReport mass_scaling;
    EnergyAccount energy;                       // 'set energy on' (energy.h)

    long step = 0;                // steps taken since `new`
    long edits = 0;               // (not saved) commands carried out on this model (what a command
                                  // may have changed, the contact update's memory of open
                                  // contacts does not trust: ContactSet::rest)
    double time = 0;              // s
    double dt = 0;                // s, timestep in use
    int next_block_id = 1;
    ChangeFlag geometry_changed; // contacts and timestep must be recomputed (the cycle clears it)

    // The contacts are those of the model as it stands: found, and found again since the last
    // change of geometry (commands and FISH between steps need not find them twice).
    bool contacts_current() const {
        return contacts.detected && (!geometry_changed || contacts.change_seen == geometry_changed.count());
    }

    // Index of the block with this id, or -1 (blocks are kept in id order).
    int block_index(int block_id) const;
    // Index of group `name`, creating it when `create`; -1 when absent and not created.
    int group_index(const std::string& name, bool create);
    // Factor on a prescribed velocity or a load driven by table n ('bound ... hist table n') at
    // the model's time (or at time t): 1 without a table (n <= 0), 0 when table n no longer exists.
    double table_factor(int table) const { return table_factor(table, time); }
    double table_factor(int table, double t) const;
};

} // namespace odec
