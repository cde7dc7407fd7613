// Contacts between blocks: the common-plane method with sub-contacts.
//
// A contact joins two blocks a < b whose bounding boxes, enlarged by the contact
// tolerance ctol, overlap and whose gap is below ctol. Between them lies the common
// plane (normal n pointing from a to b, reference point p): the plane that makes the
// gap between the blocks, measured on either side of it, as large as possible (or the
// overlap as small as possible). Its normal is the contact normal (contact_detect.cpp
// explains the search).
//
// The contact is carried by sub-contacts at the vertices of the contact polygon: the
// vertices of either block's faces that lie on the other block's face, and the points
// where an edge of one crosses an edge of the other. Each owns the share of the contact
// area nearest it (a third of each adjacent triangle; a corner pressing into a face tilted
// to it, its own share of its faces) and remembers its own joint history
// (normal closure, shear displacement and stress, whether it has failed), so a joint can
// be half slipping, half stuck, or partly open. Forces act at these points, which span
// the whole contact area, so a block can lean its load out to the very edge of its base,
// as a rigid block does. Between geometry refreshes each point rides on its block.
//
// A contact with a deformable block is carried instead by the block's surface gridpoints
// (sides 3 and 4 below), each pressing on the other block's surface (contact_gridpoint.h).
//
// Everything is a structure of arrays: per contact, and per sub-contact with each
// contact's sub-contacts stored consecutively (sub_offset). Arrays are rebuilt only when
// detection reruns, into buffers kept between runs, so cycling allocates nothing.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "engine/normal_code.h"
#include "engine/point_code.h"
#include "engine/sub_key.h"
#include "engine/pod_array.h"

namespace odec {

struct Model;
struct BlockSet;
struct JointMaterial;
struct Range;
struct Polyhedron;

// A face within 20 degrees of a contact's plane lies flat to it (cos 20 deg): the gridpoint areas
// of contacts, the faces 'insitu' loads and the area the joints' water wets.
constexpr double kFlatToPlane = 0.9396926207859084;

// The largest single-precision number not above x (infinities as they are): a bound that is
// kept in single precision never promises more than was found.
inline float float_not_above(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

// A bound in sixteen bits: the upper half of the largest single-precision number not above x,
// rounded down again (its range, eight bits of precision), so that it still never promises more
// than was found; not a number stays so. Read through bound16_value.
inline std::uint16_t bound16_not_above(double x) {
    const float f = float_not_above(x);
    if (f != f) return 0x7FC0;
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    std::uint32_t hi = u >> 16;
    if ((u & 0xFFFFu) && (u >> 31)) ++hi; // below zero, down is away from it
    return static_cast<std::uint16_t>(hi);
}
inline float bound16_value(std::uint16_t h) {
    const std::uint32_t u = static_cast<std::uint32_t>(h) << 16;
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

// The nearest single-precision number to x, the largest finite one beyond their range.
inline float float_nearest(double x) {
    constexpr double kMax = std::numeric_limits<float>::max();
    return static_cast<float>(x > kMax ? kMax : x < -kMax ? -kMax : x);
}

// Sub-contact state flags.
enum SubContactFlags : std::uint8_t {
    kSubSlip = 1,    // slipping this step (shear stress at the Coulomb limit)
    kSubOpen = 2,    // no compression: the joint is open here
    kSubFailed = 4,  // failed in shear or tension: cohesion and tension lost for good
    kSubNew = 8,     // created by the last geometry refresh: its first increment is already in it
    kSubFresh = 16,  // created by the last refresh where the contact was already carried: its
                     // closure was measured then (the step's normal increment is in it), its shear
                     // and dilation taken from the nearest sub-contact before (the step's shear
                     // increment is not)
};

// Open since its last step (not made by the last refresh, whose closure is the geometry's): the
// sub-contacts whose closures dynamic mode holds by reference (sub_closure).
inline bool held_open(std::uint8_t flags) { return (flags & (kSubOpen | kSubNew | kSubFresh)) == kSubOpen; }

// What `print contact` shows as the state of a whole contact.
enum class ContactState : std::uint8_t { Elastic, Slipping, Open, Failed };
const char* contact_state_name(ContactState s);

// The mark of a gridpoint's sub-contact key (ContactSet::sub_key).
constexpr std::int64_t kGridpointKey = std::int64_t{1} << 60;
// The key of the sub-contact of gridpoint gp of block a (of_b 0) or b (of_b 1): sides 3 and 4.
inline std::int64_t gridpoint_sub_key(int of_b, int gp) {
    return (static_cast<std::int64_t>(of_b) << 61) | kGridpointKey | gp;
}

// The shear axes of a contact plane of unit normal n: e1 and e2 = n x e1 in the plane, fixed by
// n alone, so that a shear vector held on them means the same whatever its history.
inline void shear_axes(const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
    const Eigen::Vector3d ref = std::abs(n.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    e1 = (ref - ref.dot(n) * n).normalized();
    e2 = n.cross(e1);
}

struct ContactSet {
    // ---- per contact (n_contacts) ----
    PodArray<int> id;                     // (n_contacts) user id, 1-based, kept while the contact lives
    PodArray<int> block_a;                // (n_contacts) block index, a < b
    PodArray<int> block_b;                // (n_contacts) block index
    PodArray<NormalCode> normal_code;     // (n_contacts) common-plane unit normal, from a to b, in
                                          //          eight bytes (read through normal(c); its
                                          //          reference point is not kept: contact_point)
    PodArray<float> gap;                  // (n_contacts) m, signed gap at the last refresh (< 0 overlap),
                                          //          in single precision (it only decides when
                                          //          the contact's geometry is looked at again)
    PodArray<std::uint32_t> joint;        // (n_contacts) its joint in one word: the joint material number
                                          //          (bits 0..29; at most 1,000,000 on file), the
                                          //          joint model 2 (bit 30; else 1) and glued (bit 31:
                                          //          no slip, no opening); read through jmat, jcons
                                          //          and joined
    PodArray<int> sub_offset;             // (n_contacts + 1) first sub-contact of each contact
    PodArray<std::uint16_t> free_motion;  // (n_contacts, or none: unknown) m: how far its blocks may
                                          //          move (`movement` since their geometry references)
                                          //          before a corner that carries no sub-contact could
                                          //          press into the other block (for a contact that
                                          //          carries none, before its blocks could touch at
                                          //          all: no more than its gap); -infinity: unknown;
                                          //          rounded down to sixteen bits
                                          //          (bound16_not_above), so it never says more

    // ---- per sub-contact (n_subs) ----
    // Its contact is the one whose sub_offset range holds it (sub_owner), its side and the vertex
    // or gridpoint it stands for are in its key (sub_side, sub_vertex): none is stored.
    PodArray<std::uint32_t> sub_code;     // (n_subs) its key (read through sub_key: what the point is,
                                          //          vertex, or pair of edges: the identity that
                                          //          carries its history across refreshes; sides
                                          //          0, 1: (side << 61) | vertex; sides 3, 4:
                                          //          ((side - 3) << 61) | kGridpointKey | gridpoint, so
                                          //          that a gridpoint never takes over the history
                                          //          of a vertex of the same number when its block
                                          //          is zoned; side 2: bit 62 set), in four bytes
                                          //          (sub_key.h): written through push_key, set_key
    KeyTable key_table;                   // the keys no four-byte code holds (saved as the keys)
    PodArray<double> sub_area;            // (n_subs) m^2, share of the contact area (they sum to it)
    PodArray<TaggedPointCode> sub_point;  // (n_subs) m, point in the owner's body frame (block b for
                                          //          side 1, else block a); sides 3 and 4: where the
                                          //          gridpoint meets the other block, in that block's
                                          //          body frame when it is rigid, else the weights of
                                          //          the corners of sub_triangle. Made anew at every
                                          //          refresh, it is held in fourteen bytes
                                          //          (point_code.h) with the sub-contact's flags
                                          //          (SubContactFlags) in the five bits its exponent
                                          //          leaves: read through sub_point_local,
                                          //          sub_weights and sub_flags
    PodArray<std::array<int, 3>> sub_tri;    // (n_subs, or empty when no sub-contact has one) sides 3
                                          //          and 4 against a deformable block: the gridpoints
                                          //          of the surface triangle the gridpoint meets; else
                                          //          -1 (read through sub_triangle)
    PodArray<double> sub_un;              // (n_subs) m, normal closure (> 0 compressed), from motion
    PodArray<double> sub_udil;            // (n_subs, or empty while all are 0) m, dilation accumulated
                                          //          while slipping (read through sub_dilation): kept
                                          //          once a joint material has dilation (update_contacts)
                                          //          or a sub-contact has some
    // Its normal stress is not stored: its closure and its joint's normal stiffness give it
    // (sub_normal_stress), as its joint law made it at its last step.
    // The shear vectors are held as their components on the shear axes of their contact's
    // normal (shear_axes): the normal is fixed between refreshes, and a refresh that turns it
    // turns them onto the new plane. Read them as vectors through sub_shear_disp and
    // sub_shear_stress.
    PodArray<Eigen::Vector2d> sub_us;     // (n_subs) m, shear displacement of b relative to a
    PodArray<Eigen::Vector2d> sub_ss;     // (n_subs) Pa, shear stress on b (opposes its slip)

    // ---- detection bookkeeping ----
    double ctol = 0;                      // m, tolerance in use (settings.ctol or chosen)
    int next_id = 1;                      // next contact id
    bool detected = false;                // false: the next detect_contacts runs in full
    std::vector<Eigen::Vector3d> ref_centroid;    // (n_blocks) centroid at the last detection
    std::vector<Eigen::Quaterniond> ref_orientation; // (n_blocks) orientation at the last detection
    std::vector<Eigen::Vector3d> geo_centroid;       // (n_blocks) centroid at the last geometry refresh
    std::vector<Eigen::Quaterniond> geo_orientation; // (n_blocks) orientation then
    std::vector<double> radius;           // (n_blocks) m, largest vertex distance from the centroid
    long n_detections = 0;                // full detections so far (for tests and profiling)
    std::uint64_t change_seen = 0;        // (not saved) Model::geometry_changed.count() at the last detection
    long revision = 0;                    // (not saved) counts the refreshes that rewrote the contacts,
                                          //   so that what is derived from them knows to follow
    double build_seconds = 0;             // (not saved) s, building the contacts of refresh passes
                                          //   (on the threads), for the benchmarks
    double write_seconds = 0;             // (not saved) s, writing them into the set (on one thread)

    // Derived from the zones, rebuilt when the model changes (not saved): the surface
    // triangles of every deformable block, outward, grouped by block.
    std::vector<std::array<int, 3>> surface_tri;  // gridpoints, counter-clockwise seen from outside
    std::vector<int> surface_face;                // the block face each lies on
    std::vector<int> surface_offset;              // (n_blocks + 1) first triangle of each block
    bool surface_ready = false;

    // Derived each step by detect_contacts (not saved): how far each block has moved since its
    // geometry reference (movement: translation plus turn times radius), m, for the contact
    // update, which reads it once (motion_fresh) to leave alone the contacts that stay open.
    std::vector<double> block_motion;             // (n_blocks) m
    bool motion_fresh = false;
    // Whether the open sub-contacts between rigid blocks hold their closures by their blocks'
    // geometry references (sub_closure), as they do in dynamic mode; in static mode they hold
    // them as they are. The contact update gives them so as the mode asks.
    bool open_by_reference = false;
    // Derived from the contacts as a refresh left them (not saved), for detect_contacts to pass
    // over all of them at once: the least free_motion (NaN or -infinity: some unknown), and
    // whether any sub-contact lies on a touch line; made for `summary_revision` (of revision).
    float least_free_motion = 0;
    bool any_touch_line = true;
    long summary_revision = -1;
    int left_open = 0;                            // (not saved) contacts the last update left alone
    int batched = 0;                              // (not saved) contacts the last update stepped in
                                                  //          batches (step_plain_subs)
    // (not saved) The contact update's memory of the open contacts it left alone (dynamic mode),
    // for such a contact, the largest closure plus dilation of its sub-contacts (all open by
    // reference), which it takes again at the next step instead of reading them, while nothing
    // can have changed them: the same run of cycle(), refreshes (revision) and commands
    // (Model::edits) as when it was made, at the next step. NaN: not known. (rest.margin)
    struct RestMemory {
        std::vector<double> margin;               // (n_contacts, or none: dynamic mode only)
        long step = -1, revision = -1, edits = -1, run = -1; // when it was made
        int used = 0;                             // contacts the last update left alone by it
        // Of those, the quiet ones: a bit per entry of color_order, set where its contact is
        // left alone without a look while the contacts' largest reach stays below `slack` (the
        // least of their margins' distances below zero); none: no contact is.
        std::vector<std::uint64_t> quiet;
        int n_quiet = 0;
        double slack = 0;
        int used_quiet = 0;                       // quiet contacts the last update left without a look
        int used_close = 0;                       // contacts the last update left alone by the closer
                                                  //   bound on their blocks' reach alone
    } rest;
    long cycle_runs = 0;                          // (not saved) calls of cycle() on this model

    // Derived each step by update_contacts in static mode (not saved): the joint stiffness each
    // block feels, for its mass (mass_scaling.h).
    std::vector<double> joint_kt;                 // (n_blocks) N/m, sum of k times area
    std::vector<double> joint_kr;                 // (n_blocks) N m, the same times the squared lever

    // Derived (not saved), made again whenever detection changes which pairs are in contact or
    // which of them carry sub-contacts: the contacts that carry sub-contacts, by colour, no two
    // contacts of one colour sharing a block, so that the contact update adds their forces
    // straight into the blocks on the threads.
    PodArray<int> color_order;                       // (contacts carrying sub-contacts) colour by colour,
                                                  //   each in contact order, then those no colour could take
    std::vector<int> color_offset;                // (n_colours + 1) first entry of each colour
    bool colored = false;

    int size() const { return static_cast<int>(block_a.size()); }
    // Contact c's joint material number, joint model (1 or 2) and whether it is glued.
    int jmat(int c) const { return static_cast<int>(joint[c] & kJointMaterialMask); }
    int jcons(int c) const { return (joint[c] & kJointModel2) ? 2 : 1; }
    bool joined(int c) const { return (joint[c] & kJointGlued) != 0; }
    void set_jmat(int c, int jm) { joint[c] = (joint[c] & ~kJointMaterialMask) | (static_cast<std::uint32_t>(jm) & kJointMaterialMask); }
    void set_jcons(int c, int jc) { joint[c] = jc == 2 ? joint[c] | kJointModel2 : joint[c] & ~kJointModel2; }
    void set_joined(int c, bool glued) { joint[c] = glued ? joint[c] | kJointGlued : joint[c] & ~kJointGlued; }
    static std::uint32_t joint_word(int jm, int jc, bool glued) {
        return (static_cast<std::uint32_t>(jm) & kJointMaterialMask) | (jc == 2 ? kJointModel2 : 0u) | (glued ? kJointGlued : 0u);
    }
    static constexpr std::uint32_t kJointMaterialMask = (1u << 30) - 1, kJointModel2 = 1u << 30, kJointGlued = 1u << 31;
    // Sub-contact k's point in its owner's body frame (sub_point), m.
    Eigen::Vector3d sub_point_local(int k) const { return decode_point(sub_point[k]); }
    // Sub-contact k's flags (SubContactFlags), kept with its point.
    std::uint8_t sub_flags(int k) const { return static_cast<std::uint8_t>(point_tag(sub_point[k])); }
    void set_sub_flags(int k, std::uint8_t flags) { set_point_tag(sub_point[k], flags); }
    // The weights of the corners of sub_triangle(k) (sides 3 and 4 against a deformable block):
    // the third is what the first two leave of 1, so that they share out a force whole.
    Eigen::Vector3d sub_weights(int k) const {
        const Eigen::Vector3d w = decode_point(sub_point[k]);
        return Eigen::Vector3d(w[0], w[1], 1.0 - w[0] - w[1]);
    }
    // The unit normal of contact c, from a to b.
    [[gnu::always_inline]] Eigen::Vector3d normal(int c) const { return decode_normal(normal_code[c]); }
    int n_subs() const { return static_cast<int>(sub_code.size()); }
    // The key of sub-contact k.
    std::int64_t sub_key(int k) const { return key_of_code(sub_code[k]); }
    std::int64_t key_of_code(std::uint32_t code) const {
        return key_code_in_table(code) ? key_table.keys[key_code_index(code)] : key_of_short_code(code);
    }
    // The code of key, entered in the table when no short code holds it.
    std::uint32_t code_of_key(std::int64_t key) {
        std::uint32_t code;
        if (short_key_code(key, code)) return code;
        if (key_table.keys.size() >= kKeyTableLimit) throw std::bad_alloc(); // 8 GB of keys
        key_table.keys.push_back(key);
        return table_key_code(key_table.keys.size() - 1);
    }
    // A sub-contact with this key after the last.
    void push_key(std::int64_t key) { sub_code.push_back(code_of_key(key)); }
    void set_key(int k, std::int64_t key) { sub_code[k] = code_of_key(key); }
    // The table's entries of sub-contacts that are gone given back, once they are more than
    // those in use (and 1024): the keys in use keep their order, the codes follow them.
    void compact_key_table();
    // The keys of all sub-contacts, in order (for the file).
    std::vector<std::int64_t> sub_keys() const {
        std::vector<std::int64_t> keys(sub_code.size());
        for (size_t k = 0; k < keys.size(); ++k) keys[k] = key_of_code(sub_code[k]);
        return keys;
    }
    // The block vertex (sides 0, 1) or gridpoint (sides 3, 4) sub-contact k stands for; -1 for
    // a crossing of edges (side 2).
    int sub_vertex(int k) const { return key_vertex(sub_key(k)); }
    // What sub-contact k stands for: 0, a vertex of block a; 1, a vertex of block b; 2, where an
    // edge of one crosses an edge of the other; 3, a gridpoint of deformable block a pressing on
    // b; 4, a gridpoint of deformable block b pressing on a.
    int sub_side(int k) const {
        const std::uint32_t code = sub_code[k];
        return key_code_in_table(code) ? key_side(key_of_code(code)) : short_code_side(code);
    }
    static int key_side(std::int64_t key) {
        if ((key >> 62) & 1) return 2;
        const int of_b = static_cast<int>((key >> 61) & 1);
        return (key & kGridpointKey) ? 3 + of_b : of_b;
    }
    static int key_vertex(std::int64_t key) {
        const int side = key_side(key);
        if (side == 2) return -1;
        return static_cast<int>(key & ((side >= 3 ? kGridpointKey : std::int64_t{1} << 61) - 1));
    }
    // A shear vector of contact c (on its shear axes) as a vector, and a vector in its plane as
    // its components on those axes.
    Eigen::Vector3d shear_in_world(int c, const Eigen::Vector2d& v) const {
        Eigen::Vector3d e1, e2;
        shear_axes(normal(c), e1, e2);
        return v[0] * e1 + v[1] * e2;
    }
    Eigen::Vector2d shear_on_axes(int c, const Eigen::Vector3d& v) const {
        Eigen::Vector3d e1, e2;
        shear_axes(normal(c), e1, e2);
        return Eigen::Vector2d(v.dot(e1), v.dot(e2));
    }
    // Sub-contact k of contact c: its shear stress on block b (Pa) and shear displacement (m).
    Eigen::Vector3d sub_shear_stress(int c, int k) const { return shear_in_world(c, sub_ss[k]); }
    Eigen::Vector3d sub_shear_disp(int c, int k) const { return shear_in_world(c, sub_us[k]); }
    // The dilation of sub-contact k, m.
    double sub_dilation(int k) const { return sub_udil.empty() ? 0.0 : sub_udil[k]; }
    // The normal stress of sub-contact k of contact c (Pa, compression positive) for the normal
    // stiffness kn (Pa/m) of its joint: what its joint law makes of its closure (update_contacts;
    // the dilation counts on a joint that is not glued), 0 while it is open and until its first
    // step (a sub-contact a refresh made).
    [[gnu::always_inline]] double sub_sn_for(int c, int k, double kn) const {
        if (sub_flags(k) & (kSubOpen | kSubNew | kSubFresh)) return 0.0;
        return joined(c) ? kn * sub_un[k] : kn * (sub_un[k] + sub_dilation(k));
    }
    // The surface triangle sub-contact k meets (sides 3 and 4 against a deformable block), else -1s.
    std::array<int, 3> sub_triangle(int k) const {
        return sub_tri.empty() ? std::array<int, 3>{-1, -1, -1} : sub_tri[k];
    }
    // The contact sub-contact k belongs to (a search of sub_offset).
    int sub_owner(int k) const;
    void clear();
};

// Find new contacts, drop lost ones and refresh the contact geometry (normal, sub-contacts,
// areas), when some block has moved more than a fraction of ctol since the last time, or
// the model changed (Model::geometry_changed).
void detect_contacts(Model& m);
// After blocks were removed or gridpoints renumbered (new_block[b], new_gp[g]: the new index, -1
// gone; null: unchanged): the contacts between two remaining blocks keep their state (ids,
// sub-contact histories), renumbered; a contact with a block gone goes, and a gridpoint's
// sub-contact goes with its gridpoint or with a corner of the triangle it meets (detection makes
// it again from the geometry). What is derived from the contacts is made again.
void renumber_contacts(Model& m, const std::vector<int>* new_block, const std::vector<int>* new_gp);
// For commands and FISH between steps: the contacts of the model as it stands (and, with_surface,
// the zones' contact surface), found now unless they already are (Model::contacts_current).
void ensure_contacts_current(Model& m, bool with_surface);
// Colour the contacts (ContactSet::color_order): done by update_contacts when needed.
void color_contacts(ContactSet& cs, int n_blocks);
// Relative motion -> joint stresses -> forces and moments on both blocks.
void update_contacts(Model& m, double dt);
// Largest stable timestep the contacts allow: dtfrac * 2 sqrt(m_min / k_max).
// With no contacts yet it is estimated from the stiffest joint material and the largest
// face; 0 when there is nothing to estimate from.
double contact_critical_timestep(const Model& m);
// The stiffest contact, N/m: its joint material's larger stiffness times its area (0: none).
double stiffest_contact(const Model& m);
// The largest timestep at which the explicit cycle is still stable, s, unscaled by dtfrac:
// per free block (a clump as one body, about its centroid: clump.h), 2 / omega with omega^2 the
// larger of (sum of the contact stiffnesses on it) / mass and (sum of stiffness times squared
// lever arm) / smallest principal inertia; the
// smallest over the blocks. It is never below contact_critical_timestep (the automatic step
// must always pass). With no contacts it is contact_critical_timestep / dtfrac, the estimate
// from the stiffest contact that could form; 0 when there is nothing to estimate from.
// `block` (may be null) receives the index of the block that sets it, or -1.
double stable_timestep_limit(const Model& m, int* block = nullptr);
// Contact tolerance in use: settings.ctol, or 5 % of the mean block size when that is 0.
double contact_tolerance(const Model& m);

// `change jmat=n jcons=j range ...`: existing contacts whose centroid (or either block,
// for region/group/id filters) the range selects. jmat or jcons <= 0 leaves that one alone.
// Returns how many contacts changed.
int assign_joint_material(Model& m, const Range& r, int jmat, int jcons);
// The first contact whose joint material has no properties (0 or a number never given 'prop
// jmat'), or -1; with loaded_only, only one whose blocks overlap. -1 as well when no joint
// material has properties at all (a model without joints).
int contact_without_joint_properties(const Model& m, bool loaded_only);
// `join range ...`: glue every contact between two of these blocks. Returns how many.
int join_blocks(Model& m, const std::vector<int>& block_indices);

// ---- the common plane (also used by the tests) ----
struct CommonPlane {
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // unit, from block a to block b
    Eigen::Vector3d point = Eigen::Vector3d::Zero();   // m, on the plane, midway in the gap
    double gap = 0;                                    // m, > 0 apart, < 0 overlapping
};
// Common plane of two convex polyhedra given in world coordinates. `warm` (may be null)
// is the previous normal: kept through ties, so the plane does not flip between equal
// choices. `band` limits the search to features that far from the warm plane (0: all).
// When a face of a and a face of b lie on one plane (a joint between them) and the gap
// across it is within `prefer_joint` of the largest (and they overlap across it by at most
// prefer_joint / 100), that plane is the common plane.
CommonPlane find_common_plane(const Polyhedron& a, const Polyhedron& b, const Eigen::Vector3d* warm,
                              double band = 0, double prefer_joint = 0);

// ---- queries for print, hist and pictures ----
struct ContactInfo {
    int id = 0;
    int block_a = -1, block_b = -1;       // block indices
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero(); // m, area centroid of the sub-contacts
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    double area = 0;                      // m^2, where the blocks touch now (contact_touch_area)
    double normal_stress = 0;             // Pa, mean over the sub-contacts (weighted by their areas),
                                          //     compression positive
    double shear_stress = 0;              // Pa, magnitude of the mean shear stress vector
    double normal_disp = 0;               // m, mean closure (> 0 compressed), dilation included
    double shear_disp = 0;                // m, magnitude of the mean shear displacement
    Eigen::Vector3d shear_stress_vec = Eigen::Vector3d::Zero(); // Pa, on block b
    Eigen::Vector3d shear_disp_vec = Eigen::Vector3d::Zero();   // m, of b relative to a
    int n_subs = 0;
    int jmat = 0, jcons = 0;
    bool joined = false;
    ContactState state = ContactState::Elastic;
};
// With touch_area false, `area` is left 0 (the rest needs no geometry: for histories).
ContactInfo contact_info(const Model& m, int contact_index, bool touch_area = true);
// Area-weighted centroid of a contact's sub-contacts (its reference point when they have none).
Eigen::Vector3d contact_centroid(const Model& m, int contact_index);
// The reference point of contact c's common plane, m: midway between its blocks' vertex means,
// moved along its normal onto the plane midway in the gap between them, for the blocks as they
// stand now (at a refresh, the point the plane was found with).
Eigen::Vector3d contact_point(const Model& m, int contact_index);
// The area where contact c's blocks touch now, m^2. Where faces lie on the common plane (within
// ctol of it): the shares of the contact polygon that belong to its closed sub-contacts (those
// that carry stress or are glued; one away from the other block carries nothing and is open).
// Where a face is tilted to the plane (an edge or a corner pressing into a face): the part where
// the solids overlap, a strip as thin as the penetration, however large the spring areas of the
// sub-contacts that carry it. For a deformable block: the areas of its gridpoints that press.
double contact_touch_area(const Model& m, int contact_index);
// World position of sub-contact k (of contact c) now.
Eigen::Vector3d sub_point(const Model& m, int c, int k);
// The closure of an open sub-contact. While a sub-contact between two rigid blocks is open
// (kSubOpen), sub_un holds not its closure but the closure it would have with both blocks at
// their geometry references (ContactSet::geo_centroid, geo_orientation, which a block keeps
// until it has moved ctol/10 from them): its closure now is that less how far the blocks have
// moved towards each other at its point since (reference_shift). So an open sub-contact's state
// does not change while it stays open (its shear displacement is not summed either: there is
// nothing to slide on), and a contact whose sub-contacts are all open by more than their blocks
// can have moved is not looked at (update_contacts). Read and write closures through these.
// Whether the open sub-contacts of contact c keep their closures so: both its blocks are rigid.
bool closure_by_reference(const Model& m, int c);
// n . (D_b(x) - D_a(x)), m: D_X(x) is how far the material point of block X now at x has moved
// since X's geometry reference (none while the references are not made).
double reference_shift(const Model& m, int a, int b, const Eigen::Vector3d& x, const Eigen::Vector3d& n);
// The closure of sub-contact k of contact c now, m (> 0 compressed), without its dilation.
double sub_closure(const Model& m, int c, int k);
// Sets it (after its flags: an open sub-contact keeps it by reference).
void set_sub_closure(Model& m, int c, int k, double un);
// The open sub-contacts of contact c given their closures now in sub_un (to_reference false),
// or back by reference (true): before and after the blocks' geometry references move.
void shift_open_closures(Model& m, int c, bool to_reference);
// For tests: how far blocks b .. b + 3 can have moved since the references ref_c, ref_q (the
// detection's bound), made four at a time and one by one.
void block_movements_for_test(const ContactSet& cs, const BlockSet& s, int b, const std::vector<Eigen::Vector3d>& ref_c,
                              const std::vector<Eigen::Quaterniond>& ref_q, double four[4], double one_by_one[4]);
// For tests and benchmarks: whether the contact update leaves alone the contacts that stay open
// whatever their blocks did (on unless told; the results are the same bits either way).
void set_rest_open_contacts(bool on);
bool rest_open_contacts();
// For tests and benchmarks: whether the contact update steps the plain sub-contacts many contacts
// at a time (contact_axes.h, step_plain_subs; on unless told; the same bits either way).
void set_batched_sub_contacts(bool on);
bool batched_sub_contacts();
// Joint material number jm, or null when it names no defined one.
const JointMaterial* joint_material(const Model& m, int jm);
// The joint material of contact c (joint_material of its number).
const JointMaterial* contact_joint_material(const Model& m, int c);
// The normal stiffness of contact c's joint (Pa/m; 0 without a defined joint material).
double contact_kn(const Model& m, int c);
// The normal stress of sub-contact k of contact c, Pa, compression positive (ContactSet::sub_sn_for
// with its joint's stiffness); without c, its contact is looked up.
double sub_normal_stress(const Model& m, int c, int k);
double sub_normal_stress(const Model& m, int k);
// Index of the contact whose centroid is nearest x, or -1 when there are none.
int find_contact_at(const Model& m, const Eigen::Vector3d& x);
// Index of the contact with this id, or -1.
int contact_index(const Model& m, int contact_id);

} // namespace odec
