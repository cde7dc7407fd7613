// Save files: the whole model state, byte for byte.
//
// Layout (integers little-endian, doubles as their own IEEE-754 bytes):
//
//   magic            12 bytes  "ODEC-SAVE" CR LF ^Z
//   format version   u32       kSaveFormatVersion
//   program version  u64 n, then n bytes ("0.1.0")
//   payload length   u64
//   payload          sections in a fixed order, each: tag (4 bytes), body length (u64), body
//   checksum         u64       FNV-1a 64 of every byte before it
//
// Why so. The magic and the two versions come first and will never move, so any odec can
// tell a foreign file or a newer one and say which program wrote it; the CR LF ^Z tail of
// the magic catches a file mangled by a text-mode copy. The payload length up front tells
// a truncated file (and by how much) from a damaged one before anything is parsed, and the
// checksum at the very end covers every byte before it, so a flipped bit anywhere is caught
// before any of the model is believed. Each section carries its length and must be read to
// its exact end, and every array carries its length, so a reader and a writer that disagree
// on a field fail loudly instead of reading shifted bytes. Doubles are their bytes, never
// text: a restored model must cycle on to the same bits as one that was never saved, so
// everything the next step reads is written, down to the contact-detection caches (positions
// at the last detection and refresh, block radii, the warm-start normals) and the adaptive
// damping coefficient.
//
// Each struct's fields are listed once, in a `fields` function that both the writer and the
// reader walk, so the two cannot drift apart.
//
// Every file odec writes can be read back: save runs the checks restore runs on what it read
// (check_consistent, check_values) and writes nothing when they fail. Neither holds the file
// in memory. save walks the fields twice: once counting, for the lengths that precede each
// section and the payload, and once writing through a 64 KiB buffer that hashes as it goes;
// so saving needs no memory that grows with the model, and works after memory ran out.
// restore compares the file's size with the one its header gives, reads it once through a
// buffer for the checksum and then again to parse it, so it holds the model and no copy of
// the file.
#include "io/save.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <type_traits>
#include <utility>

#include "engine/clump.h"
#include "io/files.h"

#ifndef ODEC_VERSION
#define ODEC_VERSION "0.1.0"
#endif

namespace odec {

static_assert(std::numeric_limits<double>::is_iec559 && sizeof(double) == 8,
              "save files hold doubles as IEEE-754 binary64 bytes");
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "save files are little-endian and written as the platform's own bytes");

const char* save_program_version() { return ODEC_VERSION; }

std::string save_file_name(const std::string& name) {
    const size_t slash = name.find_last_of('/');
    const std::string base = slash == std::string::npos ? name : name.substr(slash + 1);
    // A leading dot marks a hidden file, not an extension.
    const size_t dot = base.find_last_of('.');
    const bool has_extension = dot != std::string::npos && dot > 0 && dot + 1 < base.size();
    return has_extension || base.empty() ? name : name + kSaveExtension;
}

namespace {

constexpr char kMagic[12] = {'O', 'D', 'E', 'C', '-', 'S', 'A', 'V', 'E', '\r', '\n', '\x1a'};
constexpr size_t kMagicSize = sizeof kMagic;
constexpr size_t kChecksumSize = 8;
constexpr std::uint64_t kMaxVersionText = 256;

std::string hex(std::uint64_t x) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(x));
    return buf;
}

// ---- the fields of each struct, walked by Writer and Reader alike ----

template <class M, class T>
using If = std::enable_if_t<std::is_same_v<std::remove_const_t<M>, T>>;

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Material> {
    io(x.defined); io(x.density); io(x.bulk); io(x.shear); io(x.cohesion); io(x.friction);
    io(x.tension); io(x.dilation);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, JointMaterial> {
    io(x.defined); io(x.kn); io(x.ks); io(x.friction); io(x.cohesion); io(x.tension);
    io(x.dilation); io(x.zdilation); io(x.res_friction);
    if (io.format >= 13) {
        io(x.azero); io(x.ares); io(x.amax);
    }
}

// Format 13: fluid flow in the joints (flow.h): settings, fluid and the nodes' state.
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, FlowSet> {
    io(x.configured); io(x.on);
    io.enumeration(x.mode, static_cast<int>(FlowMode::Transient) + 1);
    io(x.substeps); io(x.density); io(x.viscosity); io(x.bulk); io(x.has_wtable); io(x.wtable);
    io(x.time); io(x.steps); io(x.pos); io(x.pp); io(x.fixed); io(x.last_volume);
}

// Format 11: cables (cable.h).
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, CableMaterial> {
    io(x.defined); io(x.area); io(x.e); io(x.ytens); io(x.ycomp); io(x.kbond); io(x.sbond); io(x.density);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, CableSet> {
    io(x.id); io(x.material); io(x.node_offset); io(x.next_id);
    io(x.pos); io(x.vel); io(x.disp); io(x.force); io(x.length); io(x.mass); io(x.inertial_mass);
    io(x.stiffness); io(x.host_block); io(x.host_lever); io(x.host_gp); io(x.host_w);
    io(x.grout_force); io(x.slip); io(x.state); io(x.vel_bc); io(x.vel_bc_value);
    io(x.axial); io(x.rest_length); io(x.seg_state); io(x.materials);
}

// Format 12: liners (liner.h). Element stiffnesses are derived (rebuilt from pos0).
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, LinerMaterial> {
    io(x.defined); io(x.e); io(x.nu); io(x.thick); io(x.density); io(x.kn); io(x.ks); io(x.ncut); io(x.scoh);
    io(x.sfric);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, LinerSet> {
    io(x.id); io(x.material); io(x.axis); io(x.node_offset); io(x.elem_offset); io(x.next_id);
    io(x.pos0); io(x.pos); io(x.vel); io(x.spin); io(x.u); io(x.rot); io(x.disp); io(x.force); io(x.moment);
    io(x.force_scale); io(x.area); io(x.normal); io(x.mass); io(x.inertial_mass); io(x.inertial_moment);
    io(x.host_block); io(x.host_lever); io(x.host_gp); io(x.host_w); io(x.bond_n); io(x.bond_s); io(x.state);
    io(x.elem); io(x.materials);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, JointPlane> {
    io(x.set); io(x.joined); io(x.jmat);
}

// Format 6: the fields of `insitu`, with the ranges they were given for (a named range's
// union nests ranges: a file may nest them no deeper than any script could).
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Range>;

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Filter> {
    thread_local int depth = 0;
    struct Nest {
        Nest() { ++depth; }
        ~Nest() { --depth; }
    } nest;
    io.check(depth <= 64, "ranges nest deeper than 64");
    io.enumeration(x.kind, static_cast<int>(FilterKind::AnyOf) + 1);
    io(x.negate); io(x.lo); io(x.hi); io(x.name); io(x.a); io(x.b); io(x.radius); io(x.any_of);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Range> {
    io(x.filters);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, StressField> {
    io(x.s); io(x.gx); io(x.gy); io(x.gz);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, InsituRecord> {
    io(x.range); io(x.field);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Polyhedron> {
    io(x.vertices); io(x.face_offsets); io(x.face_vertices); io(x.face_joint);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Table> {
    io(x.points);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, History> {
    // The last kind each format knows: format 3 added zone stresses and reactions.
    const HistoryKind last = io.format >= 14  ? HistoryKind::LinerMx
                             : io.format >= 13  ? HistoryKind::FlowRate
                             : io.format >= 11  ? HistoryKind::CableGrout
                             : io.format >= 8 ? HistoryKind::Energy
                             : io.format >= 5 ? HistoryKind::Fish
                             : io.format >= 3 ? HistoryKind::ZReaction
                                              : HistoryKind::SDis;
    io.enumeration(x.kind, static_cast<int>(last) + 1);
    io(x.point); io(x.block_id); io(x.contact_id); io(x.label); io(x.values);
    // Format 2: the material point a block history follows. Format 1 sampled the
    // centroid; its files take the point's offset at the block's current pose.
    if (io.format >= 2) io(x.body_offset);
    // Format 3: what a history samples in deformable blocks (older files have none).
    if (io.format >= 3) {
        io(x.gridpoint); io(x.zone); io(x.gridpoints); io(x.blocks);
    }
    // Format 5: the FISH name a history samples (the functions themselves are not saved).
    if (io.format >= 5) io(x.source);
    // Format 7: the sample a history made during a run starts with (older files give it a
    // NaN for each sample before it: restore_model takes them off).
    if (io.format >= 9) io(x.first);
    // Format 11: the cable a cable history samples.
    if (io.format >= 11) {
        io(x.cable_id); io(x.cable_item);
    }
}

// Format 7 keeps each block's orientation at the last 'reset disp'. Older files kept the turn
// since then as the sum of spin times step, which is the rotation vector of the turn when the
// axis stayed fixed (a block toppling in a plane): the reference is the present orientation
// turned back by it, as near as those files allow.
template <class IO, class M>
void legacy_rotation(IO& io, M& x) {
    std::vector<Vec3> rotation;
    io(rotation);
    if constexpr (!std::is_const_v<M>) {
        io.check(rotation.size() == x.orientation.size(), "the block rotations and orientations differ in length");
        x.ref_orientation.resize(rotation.size());
        for (size_t b = 0; b < rotation.size(); ++b) {
            const double angle = rotation[b].norm();
            const Quat turn = angle > 0 && std::isfinite(angle) ? Quat(Eigen::AngleAxisd(angle, rotation[b] / angle))
                                                                 : Quat::Identity();
            x.ref_orientation[b] = std::isfinite(angle) ? (turn.conjugate() * x.orientation[b]).normalized()
                                                        : Quat(std::nan(""), 0, 0, 0);
        }
    }
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, HistorySet> {
    io(x.ncyc); io(x.items); io(x.sample_steps);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, TableSet> {
    io(x.tables);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Settings> {
    io(x.dt_fixed); io(x.dtfrac); io(x.ctol); io(x.default_jmat); io(x.default_jcons); io(x.large_strain);
    // Format 6: static and dynamic analysis (older files were computed dynamically, with real
    // masses: they restore in dynamic mode).
    if (io.format >= 6) {
        io(x.dyn_configured); io(x.dynamic); io(x.mscale_dt);
    }
    // Format 10: the overlap tolerance (older files restore with the automatic one).
    if (io.format >= 10) io(x.ovtol);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Damping> {
    io.enumeration(x.mode, static_cast<int>(DampingMode::Off) + 1);
    io(x.local); io(x.rayleigh_fraction); io(x.rayleigh_frequency); io(x.auto_coefficient);
    // Format 15: adaptive damping's memory of the last step (older files start without it: the
    // first step after restore keeps the coefficient they saved).
    if (io.format >= 15) {
        io(x.auto_after); io(x.auto_inertia);
    }
    // Format 16: the timestep of that step (older files take the next step's).
    if (io.format >= 16) io(x.auto_dt);
}

// Format 8: the energy account (older files restore with it off).
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, EnergyAccount> {
    io(x.on); io(x.start_step); io(x.initial); io(x.given);
    io(x.gravity); io(x.load); io(x.velocity); io(x.damping);
    io(x.pending_gravity); io(x.pending_load); io(x.pending_velocity); io(x.pending_damping);
    io(x.slip); io(x.plastic); io(x.kinetic); io(x.peak); io(x.mark_kinetic); io(x.mark_strain);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, Profile> {
    // Format 3 added the zone stage, format 6 the checks, format 11 the cables, 13 the flow, 14
    // the liners; older files time the others, in the same order.
    const int expected = static_cast<int>(Stage::Count) - (io.format >= 3 ? 0 : 1) - (io.format >= 6 ? 0 : 1) -
                         (io.format >= 11 ? 0 : 1) - (io.format >= 13 ? 0 : 1) - (io.format >= 14 ? 0 : 1);
    int n_stages = expected;
    io(n_stages);
    io.check(n_stages == expected, "the profile has " + std::to_string(n_stages) + " stages, save format " +
                                       std::to_string(io.format) + " has " + std::to_string(expected));
    for (int k = 0; k < static_cast<int>(Stage::Count); ++k) {
        if (io.format < 3 && k == static_cast<int>(Stage::Zones)) continue;
        if (io.format < 6 && k == static_cast<int>(Stage::Checks)) continue;
        if (io.format < 11 && k == static_cast<int>(Stage::Cables)) continue;
        if (io.format < 13 && k == static_cast<int>(Stage::Flow)) continue;
        if (io.format < 14 && k == static_cast<int>(Stage::Liners)) continue;
        io(x.seconds[k]);
    }
    io(x.steps);
}

// Format 7: a load on a rigid block.
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, BlockLoad> {
    io.enumeration(x.kind, static_cast<int>(LoadKind::Face) + 1);
    io(x.table); io(x.lever); io(x.force); io(x.couple);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, BlockSet> {
    io(x.id); io(x.shape); io(x.centroid); io(x.orientation); io(x.vel); io(x.ang_vel);
    io(x.accel); io(x.ang_accel); io(x.force); io(x.moment);
    if (io.format >= 7) {
        io(x.loads);
    } else {
        // Older files hold one applied force per block, at its centroid.
        std::vector<Vec3> applied;
        io(applied);
        if constexpr (!std::is_const_v<M>) {
            x.loads.assign(applied.size(), {});
            for (size_t b = 0; b < applied.size(); ++b) {
                if (applied[b].isZero(0)) continue;
                BlockLoad l;
                l.force = applied[b];
                x.loads[b].push_back(l);
            }
        }
    }
    io(x.force_scale);
    io(x.disp);
    if (io.format >= 9) io(x.ref_orientation);
    else legacy_rotation(io, x);
    io(x.volume); io(x.mass); io(x.inertia_body); io(x.inertia_unit);
    io(x.material); io(x.region); io(x.group); io(x.flags); io(x.vel_bc); io(x.vel_bc_value);
    io(x.vel_bc_table); io(x.half_kick);
    // Format 3: deformable blocks (older files hold rigid blocks only; restore_model gives
    // them the defaults of a new block).
    if (io.format >= 3) {
        io(x.cons); io(x.corner_gp); io(x.zone_edge); io(x.body);
    }
    if (io.format >= 6) {
        io(x.inertial_mass); io(x.inertial_moment);
    }
    if (io.format >= 12) io(x.clump);
    // Derived from the above, but written as they are so nothing is recomputed differently
    // (unless stale: see world_vertices_stale).
    io.world_vertices(x.vertex_offset, x.world_vertices);
}

// Zones and gridpoints: every array, the derived and scratch ones too. Some are read before
// the next step rewrites them (the forces of the last step, by a history's velocity at t and
// by the unbalanced force; the shape-function gradients, kept from zoning in small strain);
// writing all of them makes a restored model the same bits as the saved one.
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, ZoneSet> {
    io(x.gp); io(x.block); io(x.model); io(x.state); io(x.stress); io(x.volume); io(x.grad);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, GridpointSet> {
    io(x.pos); io(x.ref); io(x.vel); io(x.disp); io(x.force); io(x.applied); io(x.traction);
    io(x.mass); io(x.stiffness); io(x.force_scale); io(x.nmd_volume); io(x.nmd_rate); io(x.block);
    io(x.vel_bc); io(x.vel_bc_value); io(x.vel_bc_table); io(x.half_kick);
    if (io.format >= 6) io(x.inertial_mass);
    // Format 7: loads that follow a table (older files have none).
    if (io.format >= 7) io(x.applied_table);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, BoundaryFace> {
    io(x.gp); io(x.force);
    if (io.format >= 7) io(x.table);
}

template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, StressBoundary> {
    io(x.faces);
}

// Whether the sub-contact offsets of x are whole: one more than its contacts, from 0 to its
// sub-contacts, never decreasing (check_consistent says so when they are not).
bool sub_offsets_whole(const ContactSet& x) {
    const size_t nc = x.block_a.size(), ns = x.sub_code.size();
    if (x.sub_offset.empty()) return nc == 0 && ns == 0;
    if (x.sub_offset.size() != nc + 1 || x.sub_offset[0] != 0 || static_cast<size_t>(x.sub_offset[nc]) != ns) return false;
    for (size_t c = 0; c < nc; ++c) {
        if (x.sub_offset[c + 1] < x.sub_offset[c]) return false;
    }
    return true;
}

// Each sub-contact's contact, from the offsets (as far as they go, when they are not whole).
std::vector<int> sub_owners(const ContactSet& x) {
    std::vector<int> owner(x.sub_code.size(), -1);
    const int ns = static_cast<int>(owner.size());
    for (int c = 0; c + 1 < static_cast<int>(x.sub_offset.size()); ++c) {
        for (int k = std::max(x.sub_offset[c], 0); k < std::min(x.sub_offset[c + 1], ns); ++k) owner[k] = c;
    }
    return owner;
}

// Each sub-contact's vertex or gridpoint (ContactSet::sub_vertex), -1 where its side is missing.
std::vector<int> sub_vertices(const ContactSet& x) {
    std::vector<int> vertex(x.sub_code.size(), -1);
    for (size_t k = 0; k < vertex.size(); ++k) vertex[k] = x.sub_vertex(static_cast<int>(k));
    return vertex;
}

// Each sub-contact's side (ContactSet::sub_side), as the file has it.
std::vector<std::uint8_t> sub_sides(const ContactSet& x) {
    std::vector<std::uint8_t> side(x.sub_code.size());
    for (size_t k = 0; k < side.size(); ++k) side[k] = static_cast<std::uint8_t>(x.sub_side(static_cast<int>(k)));
    return side;
}

// An array the file has and memory derives, written element by element as it is made (no copy
// of it is held): n elements of type T, the k-th at(k).
template <class T, class F>
struct Derived {
    size_t n;
    F at;
};
template <class T, class F>
Derived<T, F> derived(size_t n, F at) {
    return Derived<T, F>{n, at};
}

// An array an older format wrote with elements of type Old, read into `to`: each element checked
// (`ok`; else the file is refused, saying `why`) and converted (`convert`).
template <class Old, class IO, class A, class Ok, class Convert>
void read_converted(IO& io, A& to, Ok&& ok, const char* why, Convert&& convert) {
    std::vector<Old> old;
    io(old);
    io.check(std::all_of(old.begin(), old.end(), ok), why);
    to.resize(old.size());
    for (size_t i = 0; i < old.size(); ++i) to[i] = convert(old[i]);
}

// A sub-contact's contact, side and vertex are not kept in memory (they follow from the offsets
// and the key), but the file has them: they are written as they derive, and on reading they must
// be what they derive to. The triangles are kept only once some sub-contact has one; the file has
// them for every sub-contact.
template <class IO, class M>
auto fields(IO& io, M& x) -> If<M, ContactSet> {
    io(x.id); io(x.block_a); io(x.block_b);
    // Format 18: the normals as their codes (normal_code.h); older files have vectors, coded here.
    if (io.format >= 18) {
        io(x.normal_code);
    } else if constexpr (!std::is_const_v<M>) {
        read_converted<Vec3>(
            io, x.normal_code, [](const Vec3& n) { return n.allFinite() && std::abs(n.norm() - 1) <= 1e-6; },
            "a contact normal is not a unit vector", [](const Vec3& n) { return encode_normal(n); });
    }
    // Format 17 has no reference point of the plane (contact_point derives it from the blocks);
    // older files have one, checked and left.
    if constexpr (!std::is_const_v<M>) {
        if (io.format < 17) {
            std::vector<Vec3> point;
            io(point);
            io.check(point.size() == x.block_a.size(), "the contact arrays differ in length");
            io.check(std::all_of(point.begin(), point.end(), [](const Vec3& p) { return p.allFinite(); }),
                     "a contact point is not a finite number");
        }
    }
    // Format 18: the gap in single precision and the joint model in a byte; older files have a
    // double and an int, narrowed here. A contact's joint is one word in memory
    // (ContactSet::joint); the file has its material, model and glue apart.
    if constexpr (std::is_const_v<M>) {
        io(x.gap);
        const size_t nc = x.joint.size();
        io(derived<int>(nc, [&x](size_t c) { return x.jmat(static_cast<int>(c)); }));
        io(derived<std::uint8_t>(nc, [&x](size_t c) { return static_cast<std::uint8_t>(x.jcons(static_cast<int>(c))); }));
        io(derived<std::uint8_t>(nc, [&x](size_t c) { return static_cast<std::uint8_t>(x.joined(static_cast<int>(c))); }));
    } else {
        if (io.format >= 18) io(x.gap);
        else read_converted<double>(io, x.gap, [](double) { return true; }, "", [](double g) { return float_nearest(g); });
        std::vector<int> jmat, jcons;
        std::vector<std::uint8_t> joined;
        io(jmat);
        if (io.format >= 18) {
            std::vector<std::uint8_t> narrow;
            io(narrow);
            jcons.assign(narrow.begin(), narrow.end());
        } else {
            io(jcons);
        }
        io(joined);
        io.check(jcons.size() == jmat.size() && joined.size() == jmat.size(), "the contact arrays differ in length");
        io.check(std::all_of(jmat.begin(), jmat.end(), [](int j) { return j >= 0 && j <= 1000000; }),
                 "the joint material is out of range");
        io.check(std::all_of(jcons.begin(), jcons.end(), [](int j) { return j == 1 || j == 2; }),
                 "the joint model is out of range");
        io.check(std::all_of(joined.begin(), joined.end(), [](std::uint8_t g) { return g <= 1; }), "a flag is out of range");
        x.joint.resize(jmat.size());
        for (size_t c = 0; c < jmat.size() && c < jcons.size() && c < joined.size(); ++c) {
            x.joint[c] = ContactSet::joint_word(jmat[c], jcons[c], joined[c] != 0);
        }
    }
    // Format 19: whether the open sub-contacts' closures are held by reference (contact.h;
    // older files hold them as they are), and how far each contact's blocks may move before a
    // corner could press in unseen (free_motion, sixteen bits in memory, an int on file): the
    // detection of the step after a restore looks where the model's own would. Older files have
    // none (looked at every step until each contact is rebuilt); nor does a model whose contacts
    // were made elsewhere.
    if (io.format >= 19) io(x.open_by_reference);
    if constexpr (std::is_const_v<M>) {
        io(derived<int>(x.free_motion.size(), [&x](size_t c) { return static_cast<int>(x.free_motion[c]); }));
    } else if (io.format >= 19) {
        std::vector<int> bound;
        io(bound);
        io.check(bound.empty() || bound.size() == x.gap.size(), "the contact arrays differ in length");
        io.check(std::all_of(bound.begin(), bound.end(), [](int v) { return v >= 0 && v <= 0xFFFF; }),
                 "a contact's free motion is out of range");
        x.free_motion.assign(bound.begin(), bound.end());
    }
    io(x.sub_offset);
    if constexpr (std::is_const_v<M>) {
        io(sub_owners(x)); io(sub_sides(x));
        io(derived<std::int64_t>(x.sub_code.size(), [&x](size_t k) { return x.sub_key(static_cast<int>(k)); }));
        io(sub_vertices(x));
    } else {
        std::vector<int> owner, vertex;
        std::vector<std::uint8_t> side;
        std::vector<std::int64_t> keys;
        io(owner); io(side); io(keys); io(vertex);
        // Format 16 marks the keys of gridpoints (kGridpointKey); older files have them bare.
        if (io.format < 16) {
            for (size_t k = 0; k < keys.size() && k < side.size(); ++k) {
                if (side[k] >= 3 && keys[k] >= 0 && keys[k] < (std::int64_t{1} << 62)) keys[k] |= kGridpointKey;
            }
        }
        // In memory, in four bytes each (sub_key.h).
        x.sub_code.clear();
        x.key_table = KeyTable{};
        x.sub_code.reserve(keys.size());
        for (const std::int64_t key : keys) x.push_key(key);
        const size_t ns = x.sub_code.size();
        io.check(owner.size() == ns && vertex.size() == ns && side.size() == ns,
                 "the sub-contact arrays differ in length");
        io.check(!sub_offsets_whole(x) || owner == sub_owners(x), "a sub-contact belongs to another contact");
        io.check(side == sub_sides(x), "a sub-contact side does not match its key");
        io.check(vertex == sub_vertices(x), "a sub-contact vertex or gridpoint does not match its key");
    }
    io(x.sub_area);
    // Format 18: the points as their codes (point_code.h); older files have vectors, coded here.
    // Memory keeps each sub-contact's flags in its code's spare bits; the file has the codes
    // bare and the flags apart (below).
    if (io.format >= 18) {
        if constexpr (std::is_const_v<M>) {
            io(derived<PointCode>(x.sub_point.size(), [&x](size_t k) { return untagged_point(x.sub_point[k]); }));
        } else {
            read_converted<PointCode>(io, x.sub_point, [](const PointCode& p) { return point_code_valid(p); },
                                      "a sub-contact point's code is out of range",
                                      [](const PointCode& p) { return tagged_point(p, 0); });
        }
    } else if constexpr (!std::is_const_v<M>) {
        read_converted<Vec3>(io, x.sub_point, [](const Vec3& v) { return v.allFinite(); }, "a sub-contact point is not a finite number",
                             [](const Vec3& v) { return tagged_point(encode_point(v), 0); });
    }
    io(x.sub_un);
    // The dilations are kept only once some sub-contact has one; the file has them for every
    // sub-contact.
    if constexpr (std::is_const_v<M>) {
        if (x.sub_udil.empty()) io(std::vector<double>(x.sub_code.size(), 0.0));
        else io(x.sub_udil);
    } else {
        io(x.sub_udil);
        if (std::all_of(x.sub_udil.begin(), x.sub_udil.end(), [](double u) { return u == 0 && !std::signbit(u); })) {
            PodArray<double>().swap(x.sub_udil);
        }
    }
    // Format 18 keeps no normal stresses (the closures and the joints' stiffnesses give them:
    // sub_normal_stress); older files have them, checked and left.
    if constexpr (!std::is_const_v<M>) {
        if (io.format < 18) {
            std::vector<double> sn;
            io(sn);
            io.check(sn.size() == x.sub_code.size(), "the sub-contact arrays differ in length");
            io.check(std::all_of(sn.begin(), sn.end(), [](double v) { return std::isfinite(v); }),
                     "a normal stress is not a finite number");
        }
    }
    // Format 17: the shear vectors on their contacts' shear axes (two numbers); older files have
    // them as vectors, put on the axes here.
    if (io.format >= 17) {
        io(x.sub_us); io(x.sub_ss);
    } else if constexpr (!std::is_const_v<M>) {
        std::vector<Vec3> us, ss;
        io(us); io(ss);
        const size_t ns = x.sub_code.size();
        io.check(us.size() == ns && ss.size() == ns, "the sub-contact arrays differ in length");
        io.check(sub_offsets_whole(x) && x.normal_code.size() == x.block_a.size(), "the sub-contact offsets are wrong");
        x.sub_us.resize(ns);
        x.sub_ss.resize(ns);
        for (int c = 0; c < static_cast<int>(x.block_a.size()); ++c) {
            for (int k = x.sub_offset[c]; k < x.sub_offset[c + 1]; ++k) {
                x.sub_us[k] = x.shear_on_axes(c, us[k]);
                x.sub_ss[k] = x.shear_on_axes(c, ss[k]);
            }
        }
    }
    if constexpr (std::is_const_v<M>) {
        io(derived<std::uint8_t>(x.sub_point.size(), [&x](size_t k) { return x.sub_flags(static_cast<int>(k)); }));
    } else {
        std::vector<std::uint8_t> flags;
        io(flags);
        io.check(flags.size() == x.sub_point.size(), "the sub-contact arrays differ in length");
        io.check(std::all_of(flags.begin(), flags.end(),
                             [](std::uint8_t f) { return f <= (kSubSlip | kSubOpen | kSubFailed | kSubNew | kSubFresh); }),
                 "a sub-contact flag is out of range");
        for (size_t k = 0; k < flags.size() && k < x.sub_point.size(); ++k) x.set_sub_flags(static_cast<int>(k), flags[k]);
    }
    // Format 4: contacts of deformable blocks (older files have rigid sub-contacts only).
    if (io.format >= 4) {
        if constexpr (std::is_const_v<M>) {
            if (x.sub_tri.empty()) io(std::vector<std::array<int, 3>>(x.sub_code.size(), {-1, -1, -1}));
            else io(x.sub_tri);
        } else {
            io(x.sub_tri);
            const bool none = std::all_of(x.sub_tri.begin(), x.sub_tri.end(),
                                          [](const std::array<int, 3>& t) { return t[0] == -1 && t[1] == -1 && t[2] == -1; });
            if (none) PodArray<std::array<int, 3>>().swap(x.sub_tri);
        }
    }
    io(x.ctol); io(x.next_id); io(x.detected);
    io(x.ref_centroid); io(x.ref_orientation); io(x.geo_centroid); io(x.geo_orientation); io(x.radius);
    io(x.n_detections);
}

// The scalars of the model itself.
template <class IO, class M>
void model_scalars(IO& io, M& m) {
    io(m.title); io(m.step); io(m.time); io(m.dt); io(m.next_block_id); io(m.geometry_changed.value);
    io(m.n_joint_sets); io(m.slivers_skipped); io(m.gravity);
}

// The whole model, section by section, in file order.
template <class IO, class M>
void model_sections(IO& io, M& m) {
    io.section("MODL", [&] { model_scalars(io, m); });
    io.section("SETS", [&] { io(m.settings); });
    io.section("DAMP", [&] { io(m.damping); });
    io.section("PROF", [&] { io(m.profile); });
    io.section("MATS", [&] { io(m.materials); });
    io.section("JMAT", [&] { io(m.joint_materials); });
    io.section("GRPS", [&] { io(m.group_names); });
    io.section("JPLN", [&] { io(m.joint_planes); });
    io.section("BLKS", [&] { io(m.blocks); });
    if (io.format >= 3) {
        io.section("ZONE", [&] { io(m.zones); });
        io.section("GRID", [&] { io(m.gridpoints); });
        io.section("SBND", [&] { io(m.stress_boundary); });
    }
    io.section("CONT", [&] { io(m.contacts); });
    if (io.format >= 6) io.section("INSI", [&] { io(m.insitu); });
    io.section("HIST", [&] { io(m.histories); });
    io.section("TABL", [&] { io(m.tables); });
    if (io.format >= 8) io.section("ENRG", [&] { io(m.energy); });
    if (io.format >= 11) io.section("CABL", [&] { io(m.cables); });
    if (io.format >= 13) io.section("FLOW", [&] { io(m.flow); });
    if (io.format >= 14) io.section("LINR", [&] { io(m.liners); });
}

// ---- writing ----

// Types whose bytes in memory are their bytes on file (see Writer: doubles and floats as they are, int as
// four bytes, one-byte integers as one, Eigen's vectors, matrices and quaternions as their
// coefficients in storage order), so that arrays of them are written and read in one go.
template <class T>
struct Bulk : std::false_type {};
template <> struct Bulk<double> : std::true_type {};
template <> struct Bulk<float> : std::true_type {};
template <> struct Bulk<NormalCode> : std::true_type {};
template <> struct Bulk<PointCode> : std::true_type {};
template <> struct Bulk<int> : std::true_type {};
template <> struct Bulk<std::uint8_t> : std::true_type {};
template <> struct Bulk<Vec3> : std::true_type {};
template <> struct Bulk<Eigen::Vector2d> : std::true_type {};
template <> struct Bulk<Mat3> : std::true_type {};
template <> struct Bulk<Quat> : std::true_type {};
template <class T, size_t N>
struct Bulk<std::array<T, N>> : Bulk<T> {};
static_assert(sizeof(int) == 4 && sizeof(NormalCode) == 8 && sizeof(PointCode) == 14 && sizeof(Vec3) == 24 && sizeof(Eigen::Vector2d) == 16 && sizeof(Mat3) == 72 && sizeof(Quat) == 32 &&
                  sizeof(std::array<int, 4>) == 16 && sizeof(std::array<double, 6>) == 48,
              "the bulk types have no padding");

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;
// The buffer a save is written and a restore read through: the whole file is never in memory.
constexpr size_t kBufferBytes = size_t{64} << 10;

// A write to the save file failed (errno).
struct WriteFailure {
    int error_number;
};

// The save file, written through a small buffer; every byte put is added to the checksum.
class Sink {
public:
    explicit Sink(int fd) : fd_(fd), buf_(new char[kBufferBytes]) {}
    std::uint64_t hash = kFnvOffset;

    void put(const void* p, size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        std::uint64_t h = hash;
        for (size_t i = 0; i < n; ++i) {
            h ^= c[i];
            h *= kFnvPrime;
        }
        hash = h;
        while (n > 0) {
            const size_t k = std::min(n, kBufferBytes - used_);
            std::memcpy(buf_.get() + used_, c, k);
            used_ += k;
            c += k;
            n -= k;
            if (used_ == kBufferBytes) flush();
        }
    }
    // Throws WriteFailure.
    void flush() {
        if (used_ > 0 && !write_all(fd_, buf_.get(), used_)) throw WriteFailure{errno};
        used_ = 0;
    }

private:
    int fd_;
    std::unique_ptr<char[]> buf_;
    size_t used_ = 0;
};

// The lengths of the sections, counted by a first pass so that each can be written before its
// body in the second.
struct SectionLengths {
    static constexpr size_t kMax = 32;
    std::array<std::uint64_t, kMax> length{};
    size_t count = 0;
};

// Walks the model's fields, either counting their bytes (no sink) or writing them.
class Writer {
public:
    Writer(Sink* sink, SectionLengths& lengths) : sink_(sink), lengths_(lengths) {}
    std::uint32_t format = kSaveFormatVersion; // the format being written
    std::uint64_t written = 0;                 // bytes so far
    bool drop_world_vertices = false;          // stale: written as none (restore drops them)
    bool lengths_differ = false;               // the writing pass disagreed with the counting one

    void bytes(const void* p, size_t n) {
        written += n;
        if (sink_) sink_->put(p, n);
    }
    template <class U>
    void raw(U x) {
        static_assert(std::is_trivially_copyable_v<U>);
        bytes(&x, sizeof x);
    }

    void operator()(const double& x) { raw(x); }
    void operator()(const float& x) { raw(x); }
    // Integers have a fixed size on file whatever their size in memory: bool and 8-bit ones
    // one byte, int four, anything wider eight.
    template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
    void operator()(const T& x) {
        if constexpr (std::is_same_v<T, bool>) raw(static_cast<std::uint8_t>(x ? 1 : 0));
        else if constexpr (sizeof(T) == 1) raw(static_cast<std::uint8_t>(x));
        else if constexpr (std::is_same_v<T, int>) raw(static_cast<std::int32_t>(x));
        else {
            static_assert(std::is_signed_v<T> && sizeof(T) <= 8);
            raw(static_cast<std::int64_t>(x));
        }
    }
    void operator()(const std::string& s) {
        raw(static_cast<std::uint64_t>(s.size()));
        bytes(s.data(), s.size());
    }
    void operator()(const Vec3& v) { for (int i = 0; i < 3; ++i) raw(v[i]); }
    void operator()(const Eigen::Vector2d& v) { for (int i = 0; i < 2; ++i) raw(v[i]); }
    void operator()(const Quat& q) { for (int i = 0; i < 4; ++i) raw(q.coeffs()[i]); }
    void operator()(const Mat3& a) { for (int i = 0; i < 9; ++i) raw(a.data()[i]); }
    template <class A, class B>
    void operator()(const std::pair<A, B>& p) { (*this)(p.first); (*this)(p.second); }
    // Fixed-size arrays have no length on file: their size is part of the layout.
    template <class T, size_t N>
    void operator()(const std::array<T, N>& a) { for (const T& x : a) (*this)(x); }
    template <class T>
    void operator()(const std::vector<T>& v) { array(v); }
    template <class T>
    void operator()(const PodArray<T>& v) { array(v); }
    // A derived array: as an array of its elements.
    template <class T, class F>
    void operator()(const Derived<T, F>& d) {
        raw(static_cast<std::uint64_t>(d.n));
        for (size_t k = 0; k < d.n; ++k) {
            const T x = d.at(k);
            if constexpr (Bulk<T>::value) bytes(&x, sizeof x);
            else (*this)(x);
        }
    }
    // An array: its length, then its elements.
    template <class V>
    void array(const V& v) {
        using T = typename V::value_type;
        raw(static_cast<std::uint64_t>(v.size()));
        if constexpr (Bulk<T>::value) {
            if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
        } else {
            for (const T& x : v) (*this)(x);
        }
    }
    template <class K, class V>
    void operator()(const std::map<K, V>& mp) {
        raw(static_cast<std::uint64_t>(mp.size()));
        for (const auto& kv : mp) { (*this)(kv.first); (*this)(kv.second); }
    }
    template <class T>
    auto operator()(const T& x) -> decltype(fields(*this, x)) { fields(*this, x); }

    template <class E>
    void enumeration(const E& e, int) { raw(static_cast<std::int32_t>(e)); }
    void check(bool, const std::string&) {}
    void world_vertices(const std::vector<int>& offsets, const std::vector<Vec3>& vertices) {
        if (drop_world_vertices) {
            (*this)(std::vector<int>());
            (*this)(std::vector<Vec3>());
        } else {
            (*this)(offsets);
            (*this)(vertices);
        }
    }

    template <class F>
    void section(const char* tag, F&& body) {
        bytes(tag, 4);
        const size_t k = lengths_.count++;
        if (k >= SectionLengths::kMax) {
            lengths_differ = true;
            return;
        }
        raw(sink_ ? lengths_.length[k] : std::uint64_t{0});
        const std::uint64_t start = written;
        body();
        const std::uint64_t len = written - start;
        if (!sink_) lengths_.length[k] = len;
        else if (len != lengths_.length[k]) lengths_differ = true;
    }

private:
    Sink* sink_;
    SectionLengths& lengths_;
};

// ---- reading ----

struct ReadError {
    std::string what;
};

// A read of the save file failed (errno).
struct ReadFailure {
    int error_number;
};

// The save file, read through a small buffer from its start; every byte handed out is added
// to the checksum.
class Source {
public:
    explicit Source(int fd) : fd_(fd), buf_(new char[kBufferBytes]) {}
    std::uint64_t hash = kFnvOffset;

    // The next n bytes into p, or skipped when p is null. Throws ReadFailure, or ReadError
    // when the file ends first (it was cut while being read: its size was known).
    void get(void* p, size_t n) {
        auto* out = static_cast<unsigned char*>(p);
        std::uint64_t h = hash;
        while (n > 0) {
            if (at_ == have_) fill();
            const size_t k = std::min(n, have_ - at_);
            const auto* c = reinterpret_cast<const unsigned char*>(buf_.get() + at_);
            for (size_t i = 0; i < k; ++i) {
                h ^= c[i];
                h *= kFnvPrime;
            }
            if (out) {
                std::memcpy(out, c, k);
                out += k;
            }
            at_ += k;
            n -= k;
        }
        hash = h;
    }

private:
    void fill() {
        for (;;) {
            const ssize_t k = ::read(fd_, buf_.get(), kBufferBytes);
            if (k < 0 && errno == EINTR) continue;
            if (k < 0) throw ReadFailure{errno};
            if (k == 0) throw ReadError{"the file became shorter while it was read"};
            have_ = static_cast<size_t>(k);
            at_ = 0;
            return;
        }
    }
    int fd_;
    std::unique_ptr<char[]> buf_;
    size_t have_ = 0, at_ = 0;
};

// Reads fields from bytes in memory (the header) or from a Source (the payload), never past
// `end`: every length is checked against the bytes left before anything is allocated.
class Reader {
public:
    Reader(const char* begin, const char* end) : mem_(begin), pos_(0), end_(static_cast<std::uint64_t>(end - begin)) {}
    Reader(Source& src, std::uint64_t begin, std::uint64_t end) : src_(&src), pos_(begin), end_(end) {}
    std::uint32_t format = kSaveFormatVersion; // the format of the file being read

    template <class U>
    U raw() {
        static_assert(std::is_trivially_copyable_v<U>);
        U x;
        get(&x, sizeof x);
        return x;
    }

    void operator()(double& x) { x = raw<double>(); }
    void operator()(float& x) { x = raw<float>(); }
    template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
    void operator()(T& x) {
        if constexpr (std::is_same_v<T, bool>) {
            const std::uint8_t b = raw<std::uint8_t>();
            if (b > 1) fail("a flag holds " + std::to_string(b));
            x = b != 0;
        } else if constexpr (sizeof(T) == 1) {
            x = static_cast<T>(raw<std::uint8_t>());
        } else if constexpr (std::is_same_v<T, int>) {
            x = raw<std::int32_t>();
        } else {
            const std::int64_t v = raw<std::int64_t>();
            if (v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max()) {
                fail("the number " + std::to_string(v) + " does not fit");
            }
            x = static_cast<T>(v);
        }
    }
    void operator()(std::string& s) {
        const size_t n = count(1);
        s.resize(n);
        if (n > 0) get(&s[0], n);
    }
    void operator()(Vec3& v) { for (int i = 0; i < 3; ++i) v[i] = raw<double>(); }
    void operator()(Eigen::Vector2d& v) { for (int i = 0; i < 2; ++i) v[i] = raw<double>(); }
    void operator()(Quat& q) { for (int i = 0; i < 4; ++i) q.coeffs()[i] = raw<double>(); }
    void operator()(Mat3& a) { for (int i = 0; i < 9; ++i) a.data()[i] = raw<double>(); }
    template <class A, class B>
    void operator()(std::pair<A, B>& p) { (*this)(p.first); (*this)(p.second); }
    template <class T, size_t N>
    void operator()(std::array<T, N>& a) { for (T& x : a) (*this)(x); }
    template <class T>
    void operator()(std::vector<T>& v) { array(v); }
    template <class T>
    void operator()(PodArray<T>& v) { array(v); }
    template <class V>
    void array(V& v) {
        using T = typename V::value_type;
        // Every element takes at least a byte, so a length beyond the bytes left is damage,
        // caught before it can ask for a huge allocation.
        if constexpr (Bulk<T>::value) {
            v.resize(count(sizeof(T)));
            if (!v.empty()) get(v.data(), v.size() * sizeof(T));
        } else {
            v.resize(count(1));
            for (T& x : v) (*this)(x);
        }
    }
    template <class K, class V>
    void operator()(std::map<K, V>& mp) {
        const size_t n = count(1);
        mp.clear();
        for (size_t i = 0; i < n; ++i) {
            K k{};
            (*this)(k);
            if (mp.find(k) != mp.end()) fail("a key is repeated");
            (*this)(mp[k]);
        }
    }
    template <class T>
    auto operator()(T& x) -> decltype(fields(*this, x)) { fields(*this, x); }

    template <class E>
    void enumeration(E& e, int n_values) {
        const std::int32_t v = raw<std::int32_t>();
        if (v < 0 || v >= n_values) {
            fail("an enumeration holds " + std::to_string(v) + " (0 to " + std::to_string(n_values - 1) + " allowed)");
        }
        e = static_cast<E>(v);
    }
    void check(bool ok, const std::string& what) {
        if (!ok) fail(what);
    }
    // The messages of the checks made for every element are built only when one fails: a
    // string for each of millions of numbers would cost more than reading them.
    [[noreturn]] void fail(const std::string& what) { throw ReadError{in_section() + what}; }
    void world_vertices(std::vector<int>& offsets, std::vector<Vec3>& vertices) {
        (*this)(offsets);
        (*this)(vertices);
    }

    template <class F>
    void section(const char* tag, F&& body) {
        need(4);
        char found[4];
        get(found, 4);
        if (std::memcmp(found, tag, 4) != 0) {
            throw ReadError{"section '" + std::string(tag, 4) + "' expected, found '" + printable(found, 4) + "'"};
        }
        const std::uint64_t len = raw<std::uint64_t>();
        need(len);
        const std::uint64_t outer_end = end_;
        end_ = pos_ + len;
        tag_ = tag;
        body();
        if (pos_ != end_) fail(std::to_string(end_ - pos_) + " bytes are left over at its end");
        end_ = outer_end;
        tag_.clear();
    }

    std::uint64_t left() const { return end_ - pos_; }

private:
    const char* mem_ = nullptr;
    Source* src_ = nullptr;
    std::uint64_t pos_;
    std::uint64_t end_;
    std::string tag_;

    void get(void* p, size_t n) {
        need(n);
        if (src_) src_->get(p, n);
        else std::memcpy(p, mem_ + pos_, n);
        pos_ += n;
    }
    std::string in_section() const { return tag_.empty() ? "" : "section '" + tag_ + "': "; }
    void need(std::uint64_t n) {
        if (left() < n) {
            throw ReadError{in_section() + "it ends early (" + std::to_string(n) + " bytes needed, " +
                            std::to_string(left()) + " left)"};
        }
    }
    size_t count(size_t min_element_bytes) {
        const std::uint64_t n = raw<std::uint64_t>();
        check(n <= left() / min_element_bytes,
              "an array claims " + std::to_string(n) + " elements but only " + std::to_string(left()) +
                  " bytes are left");
        return static_cast<size_t>(n);
    }
    static std::string printable(const char* p, size_t n) {
        std::string s;
        for (size_t i = 0; i < n; ++i) s += (p[i] >= 32 && p[i] < 127) ? p[i] : '?';
        return s;
    }
};

// True when the world vertex offsets and positions have the sizes the block shapes give.
bool world_vertices_match(const BlockSet& s) {
    const size_t n = s.id.size();
    if (s.shape.size() != n || s.vertex_offset.size() != n + 1 || s.vertex_offset[0] != 0) return false;
    for (size_t b = 0; b < n; ++b) {
        if (static_cast<long long>(s.vertex_offset[b + 1]) - s.vertex_offset[b] != s.shape[b].n_vertices()) return false;
    }
    return s.vertex_offset[n] >= 0 && static_cast<size_t>(s.vertex_offset[n]) == s.world_vertices.size();
}

// World vertices are derived from the blocks and rebuilt before anything reads them once
// blocks were added or removed (geometry_changed): until then they may be stale, as in a
// model right after 'delete'. Stale ones are neither written nor believed when read.
bool world_vertices_stale(const Model& m) { return m.geometry_changed && !world_vertices_match(m.blocks); }

// The zones, gridpoints and loaded faces of deformable blocks: lengths agree, every index
// points at something that exists, and the blocks and zones agree on which blocks are
// deformable. Block arrays are known to agree in length.
std::string check_zones_consistent(const Model& m) {
    const BlockSet& s = m.blocks;
    const ZoneSet& z = m.zones;
    const GridpointSet& g = m.gridpoints;
    const size_t n = s.id.size();
    const size_t nz = z.gp.size();
    // The gradients are empty until the cycle first needs them.
    if (z.block.size() != nz || z.model.size() != nz || z.state.size() != nz || z.stress.size() != nz ||
        z.volume.size() != nz || (!z.grad.empty() && z.grad.size() != nz)) {
        return "the zone arrays differ in length";
    }
    const size_t ng = g.pos.size();
    if (g.ref.size() != ng || g.vel.size() != ng || g.disp.size() != ng || g.force.size() != ng ||
        g.applied.size() != ng || g.traction.size() != ng || g.mass.size() != ng || g.stiffness.size() != ng ||
        g.force_scale.size() != ng || g.nmd_volume.size() != ng || g.nmd_rate.size() != ng ||
        g.block.size() != ng || g.vel_bc.size() != ng || g.vel_bc_value.size() != ng ||
        g.vel_bc_table.size() != ng || g.half_kick.size() != ng || g.inertial_mass.size() != ng ||
        g.applied_table.size() != ng) {
        return "the gridpoint arrays differ in length";
    }
    if (nz > static_cast<size_t>(std::numeric_limits<int>::max()) ||
        ng > static_cast<size_t>(std::numeric_limits<int>::max())) {
        return "there are more zones or gridpoints than odec can count";
    }
    auto gridpoint_ok = [&](int i) { return i >= 0 && static_cast<size_t>(i) < ng; };
    auto block_deformable = [&](int b) {
        return b >= 0 && static_cast<size_t>(b) < n && (s.flags[b] & kDeformable) != 0;
    };
    for (size_t b = 0; b < n; ++b) {
        const std::string w = "block " + std::to_string(s.id[b]);
        const auto& corners = s.corner_gp[b];
        if (s.flags[b] & kDeformable) {
            if (static_cast<int>(corners.size()) != s.shape[b].n_vertices()) {
                return w + " is deformable but has " + std::to_string(corners.size()) + " corner gridpoints for " +
                       std::to_string(s.shape[b].n_vertices()) + " vertices";
            }
            for (int c : corners) {
                if (!gridpoint_ok(c)) return w + " has a corner at gridpoint " + std::to_string(c) + ", which does not exist";
            }
            if (s.body[b] < 1) return w + " is deformable but belongs to no continuum";
        } else if (!corners.empty() || s.body[b] != 0) {
            return w + " is rigid but has corner gridpoints or a continuum";
        }
    }
    std::vector<char> zoned(n, 0);
    for (size_t i = 0; i < nz; ++i) {
        const std::string w = "zone " + std::to_string(i + 1);
        if (!block_deformable(z.block[i])) return w + " belongs to block index " + std::to_string(z.block[i]) + ", which is not a deformable block";
        zoned[z.block[i]] = 1;
        const auto& q = z.gp[i];
        for (int k = 0; k < 4; ++k) {
            if (!gridpoint_ok(q[k])) return w + " has a corner at gridpoint " + std::to_string(q[k]) + ", which does not exist";
            for (int j = 0; j < k; ++j) {
                if (q[j] == q[k]) return w + " has gridpoint " + std::to_string(q[k]) + " at two corners";
            }
        }
    }
    // Each corner of a deformable block is a corner of one of its own zones: removing other
    // blocks' zones (delete, gen again) keeps exactly the gridpoints that kept zones use. The
    // blocks' corners are listed and marked as the zones' corners are met: memory for the
    // corners of the blocks, a few per block, not for those of every zone.
    std::vector<std::pair<int, int>> corners; // (gridpoint, block) of every corner of a deformable block
    for (size_t b = 0; b < n; ++b) {
        if (s.flags[b] & kDeformable) {
            for (int c : s.corner_gp[b]) corners.emplace_back(c, static_cast<int>(b));
        }
    }
    std::sort(corners.begin(), corners.end());
    std::vector<char> met(corners.size(), 0);
    for (size_t i = 0; i < nz; ++i) {
        for (int c : z.gp[i]) {
            const auto r = std::equal_range(corners.begin(), corners.end(), std::make_pair(c, z.block[i]));
            for (auto it = r.first; it != r.second; ++it) met[static_cast<size_t>(it - corners.begin())] = 1;
        }
    }
    for (size_t b = 0; b < n; ++b) {
        if (!(s.flags[b] & kDeformable)) continue;
        const std::string w = "block " + std::to_string(s.id[b]);
        if (!zoned[b]) return w + " is deformable but has no zones";
        for (int c : s.corner_gp[b]) {
            const auto it = std::lower_bound(corners.begin(), corners.end(), std::make_pair(c, static_cast<int>(b)));
            if (!met[static_cast<size_t>(it - corners.begin())]) {
                return w + " has a corner at gridpoint " + std::to_string(c) + ", which none of its zones has";
            }
        }
    }
    for (size_t i = 0; i < ng; ++i) {
        if (!block_deformable(g.block[i])) {
            return "gridpoint " + std::to_string(i + 1) + " belongs to block index " + std::to_string(g.block[i]) +
                   ", which is not a deformable block";
        }
    }
    for (const BoundaryFace& f : m.stress_boundary.faces) {
        // Corners in increasing order, as the faces are kept (which also makes them distinct).
        if (!gridpoint_ok(f.gp[0]) || !gridpoint_ok(f.gp[1]) || !gridpoint_ok(f.gp[2])) {
            return "a face loaded by 'bound stress' has a corner at a gridpoint that does not exist";
        }
        if (!(f.gp[0] < f.gp[1] && f.gp[1] < f.gp[2])) {
            return "a face loaded by 'bound stress' does not have three distinct corners in order";
        }
    }
    return "";
}

// Sizes and indices that the cycle trusts without checking, so that a file which passed its
// checksum but was written wrongly cannot make the cycle read out of bounds.
// Cables: every array its length, every index in range, every number finite.
std::string check_cables_consistent(const Model& m) {
    const CableSet& cs = m.cables;
    const size_t nc = cs.id.size();
    if (cs.material.size() != nc) return "the cable arrays differ in length";
    if (nc == 0 ? !cs.node_offset.empty() : cs.node_offset.size() != nc + 1) return "the cable node offsets do not match the cables";
    const size_t nn = cs.pos.size();
    if (nc > 0 && (cs.node_offset[0] != 0 || static_cast<size_t>(cs.node_offset[nc]) != nn)) {
        return "the cable node offsets do not match the nodes";
    }
    for (size_t c = 0; c < nc; ++c) {
        if (cs.node_offset[c + 1] - cs.node_offset[c] < 2) return "a cable has fewer than two nodes";
        if (cs.id[c] < 1 || cs.id[c] >= cs.next_id || (c > 0 && cs.id[c] <= cs.id[c - 1])) return "the cable ids are not increasing";
        if (cs.material[c] < 1 || static_cast<size_t>(cs.material[c]) >= cs.materials.size()) {
            return "cable " + std::to_string(cs.id[c]) + " has a material that does not exist";
        }
    }
    const size_t nseg = nn - nc;
    if (cs.vel.size() != nn || cs.disp.size() != nn || cs.force.size() != nn || cs.length.size() != nn ||
        cs.mass.size() != nn || cs.inertial_mass.size() != nn || cs.stiffness.size() != nn ||
        cs.host_block.size() != nn || cs.host_lever.size() != nn || cs.host_gp.size() != nn ||
        cs.host_w.size() != nn || cs.grout_force.size() != nn || cs.slip.size() != nn || cs.state.size() != nn ||
        cs.vel_bc.size() != nn || cs.vel_bc_value.size() != nn || cs.axial.size() != nseg ||
        cs.rest_length.size() != nseg || cs.seg_state.size() != nseg) {
        return "the cable node and segment arrays differ in length";
    }
    for (size_t i = 0; i < nn; ++i) {
        if (cs.host_block[i] < 0) return "a cable node refers to a negative block id";
        for (int g : cs.host_gp[i]) {
            if (g < -1 || g >= m.gridpoints.size()) return "a cable node refers to a gridpoint that does not exist";
        }
        if (!cs.pos[i].allFinite() || !cs.vel[i].allFinite() || !cs.disp[i].allFinite() || !cs.force[i].allFinite() ||
            !cs.host_lever[i].allFinite() || !cs.vel_bc_value[i].allFinite() || !std::isfinite(cs.grout_force[i]) ||
            !std::isfinite(cs.slip[i]) || !(cs.length[i] > 0) || !(cs.mass[i] >= 0) || !(cs.inertial_mass[i] >= 0) ||
            !(cs.stiffness[i] >= 0) || !std::isfinite(cs.length[i] + cs.mass[i] + cs.inertial_mass[i] + cs.stiffness[i])) {
            return "a number of cable node " + std::to_string(i + 1) + " is not finite or out of range";
        }
        for (double w : cs.host_w[i]) {
            if (!std::isfinite(w)) return "a weight of cable node " + std::to_string(i + 1) + " is not a finite number";
        }
    }
    for (size_t k = 0; k < nseg; ++k) {
        if (!std::isfinite(cs.axial[k]) || !(cs.rest_length[k] > 0) || !std::isfinite(cs.rest_length[k])) {
            return "a number of cable segment " + std::to_string(k + 1) + " is not finite or out of range";
        }
    }
    for (const CableMaterial& p : cs.materials) {
        if (!(p.area >= 0 && p.e >= 0 && p.ytens >= 0 && p.ycomp >= 0 && p.kbond >= 0 && p.sbond >= 0 &&
              p.density >= 0) ||
            !std::isfinite(p.area + p.e + p.ytens + p.ycomp + p.kbond + p.sbond + p.density)) {
            return "a cable material has a number that is negative or not finite";
        }
    }
    return "";
}

// Liners: every array its length, every index in range, every number finite.
std::string check_liners_consistent(const Model& m) {
    const LinerSet& ls = m.liners;
    const size_t nl = ls.id.size();
    if (ls.material.size() != nl || ls.axis.size() != nl) return "the liner arrays differ in length";
    if (nl == 0 ? (!ls.node_offset.empty() || !ls.elem_offset.empty())
                : (ls.node_offset.size() != nl + 1 || ls.elem_offset.size() != nl + 1)) {
        return "the liner offsets do not match the liners";
    }
    const size_t nn = ls.pos.size(), ne = ls.elem.size();
    if (nl > 0 && (ls.node_offset[0] != 0 || static_cast<size_t>(ls.node_offset[nl]) != nn || ls.elem_offset[0] != 0 ||
                   static_cast<size_t>(ls.elem_offset[nl]) != ne)) {
        return "the liner offsets do not match the nodes and elements";
    }
    for (size_t c = 0; c < nl; ++c) {
        if (ls.node_offset[c + 1] - ls.node_offset[c] < 3 || ls.elem_offset[c + 1] - ls.elem_offset[c] < 1) {
            return "a liner has no element";
        }
        if (ls.id[c] < 1 || ls.id[c] >= ls.next_id || (c > 0 && ls.id[c] <= ls.id[c - 1])) return "the liner ids are not increasing";
        if (ls.material[c] < 1 || static_cast<size_t>(ls.material[c]) >= ls.materials.size() ||
            !ls.materials[ls.material[c]].defined || !(ls.materials[ls.material[c]].e > 0) ||
            !(ls.materials[ls.material[c]].thick > 0)) {
            return "liner " + std::to_string(ls.id[c]) + " has a material that does not exist";
        }
        if (!ls.axis[c].allFinite() || !(ls.axis[c].norm() > 0)) return "a liner axis is not a finite direction";
        for (int e = ls.elem_offset[c]; e < ls.elem_offset[c + 1]; ++e) {
            for (int i : ls.elem[e]) {
                if (i < ls.node_offset[c] || i >= ls.node_offset[c + 1]) return "a liner element refers to a node not its own";
            }
            const auto& n = ls.elem[e];
            if (n[0] == n[1] || n[1] == n[2] || n[0] == n[2] ||
                !((ls.pos0[n[1]] - ls.pos0[n[0]]).cross(ls.pos0[n[2]] - ls.pos0[n[0]]).norm() > 0)) {
                return "a liner element is degenerate";
            }
        }
    }
    if (ls.pos0.size() != nn || ls.vel.size() != nn || ls.spin.size() != nn || ls.u.size() != nn || ls.rot.size() != nn ||
        ls.disp.size() != nn || ls.force.size() != nn || ls.moment.size() != nn || ls.force_scale.size() != nn ||
        ls.area.size() != nn || ls.normal.size() != nn || ls.mass.size() != nn || ls.inertial_mass.size() != nn ||
        ls.inertial_moment.size() != nn || ls.host_block.size() != nn || ls.host_lever.size() != nn ||
        ls.host_gp.size() != nn || ls.host_w.size() != nn || ls.bond_n.size() != nn || ls.bond_s.size() != nn ||
        ls.state.size() != nn) {
        return "the liner node arrays differ in length";
    }
    for (size_t i = 0; i < nn; ++i) {
        if (ls.host_block[i] < 0) return "a liner node refers to a negative block id";
        for (int g : ls.host_gp[i]) {
            if (g < -1 || g >= m.gridpoints.size()) return "a liner node refers to a gridpoint that does not exist";
        }
        bool ok = ls.pos0[i].allFinite() && ls.pos[i].allFinite() && ls.vel[i].allFinite() && ls.spin[i].allFinite() &&
                  ls.u[i].allFinite() && ls.rot[i].allFinite() && ls.disp[i].allFinite() && ls.force[i].allFinite() &&
                  ls.moment[i].allFinite() && ls.host_lever[i].allFinite() && ls.bond_s[i].allFinite() &&
                  ls.normal[i].allFinite() && std::isfinite(ls.bond_n[i]) && ls.area[i] > 0 && ls.mass[i] >= 0 &&
                  ls.inertial_mass[i] >= 0 && ls.inertial_moment[i] >= 0 && ls.force_scale[i] >= 0 &&
                  std::isfinite(ls.area[i] + ls.mass[i] + ls.inertial_mass[i] + ls.inertial_moment[i] + ls.force_scale[i]);
        for (double w : ls.host_w[i]) ok = ok && std::isfinite(w);
        if (!ok) return "a number of liner node " + std::to_string(i + 1) + " is not finite or out of range";
    }
    for (const LinerMaterial& p : ls.materials) {
        if (!(p.e >= 0 && p.thick >= 0 && p.density >= 0 && p.kn >= 0 && p.ks >= 0 && p.sfric >= 0 && p.sfric < 90 &&
              p.nu > -1 && p.nu < 0.5) ||
            !std::isfinite(p.e + p.nu + p.thick + p.density + p.kn + p.ks + p.ncut + p.scoh + p.sfric)) {
            return "a liner material has a number that is out of range or not finite";
        }
    }
    return "";
}

std::string check_consistent(const Model& m) {
    const BlockSet& s = m.blocks;
    const size_t n = s.id.size();
    bool sizes_ok = true;
    auto same = [&](size_t k) { sizes_ok = sizes_ok && k == n; };
    same(s.shape.size()); same(s.centroid.size()); same(s.orientation.size()); same(s.vel.size());
    same(s.ang_vel.size()); same(s.accel.size()); same(s.ang_accel.size()); same(s.force.size());
    same(s.moment.size()); same(s.loads.size()); same(s.force_scale.size()); same(s.disp.size());
    same(s.ref_orientation.size()); same(s.volume.size()); same(s.mass.size()); same(s.inertia_body.size());
    same(s.inertia_unit.size()); same(s.material.size()); same(s.region.size()); same(s.group.size());
    same(s.flags.size()); same(s.vel_bc.size()); same(s.vel_bc_value.size()); same(s.vel_bc_table.size());
    same(s.half_kick.size()); same(s.cons.size()); same(s.corner_gp.size()); same(s.zone_edge.size());
    same(s.body.size()); same(s.inertial_mass.size()); same(s.inertial_moment.size()); same(s.clump.size());
    if (!sizes_ok) return "the block arrays differ in length";
    if (const std::string why = clumps_problem(s); !why.empty()) return why;
    if (!s.vertex_offset.empty() && !world_vertices_stale(m)) {
        if (s.vertex_offset.size() != n + 1 || s.vertex_offset[0] != 0) return "the world vertex offsets are wrong";
        for (size_t b = 0; b < n; ++b) {
            if (static_cast<long long>(s.vertex_offset[b + 1]) - s.vertex_offset[b] != s.shape[b].n_vertices()) {
                return "the world vertex offsets do not match the block shapes";
            }
        }
        if (static_cast<size_t>(s.vertex_offset[n]) != s.world_vertices.size()) return "the world vertices are missing";
    }
    for (size_t b = 0; b < n; ++b) {
        const Polyhedron& p = s.shape[b];
        const int nf = p.n_faces();
        if (nf > 0 && (p.face_offsets[0] != 0 ||
                       static_cast<size_t>(p.face_offsets[nf]) != p.face_vertices.size())) {
            return "the faces of block " + std::to_string(s.id[b]) + " are wrong";
        }
        for (int f = 0; f < nf; ++f) {
            if (p.face_offsets[f + 1] < p.face_offsets[f]) return "the faces of block " + std::to_string(s.id[b]) + " are wrong";
        }
        for (int v : p.face_vertices) {
            if (v < 0 || v >= p.n_vertices()) return "block " + std::to_string(s.id[b]) + " has a face vertex out of range";
        }
        if (!p.face_joint.empty() && static_cast<int>(p.face_joint.size()) != nf) {
            return "the face joint tags of block " + std::to_string(s.id[b]) + " are wrong";
        }
        if (s.group[b] < -1 || s.group[b] >= static_cast<int>(m.group_names.size())) {
            return "block " + std::to_string(s.id[b]) + " is in a group that does not exist";
        }
    }

    const ContactSet& c = m.contacts;
    const size_t nc = c.block_a.size();
    if (c.id.size() != nc || c.block_b.size() != nc || c.normal_code.size() != nc ||
        c.gap.size() != nc || c.joint.size() != nc) {
        return "the contact arrays differ in length";
    }
    const size_t ns = c.sub_code.size();
    if (c.sub_area.size() != ns || c.sub_point.size() != ns || c.sub_un.size() != ns ||
        (!c.sub_udil.empty() && c.sub_udil.size() != ns) ||
        c.sub_us.size() != ns || c.sub_ss.size() != ns ||
        (!c.sub_tri.empty() && c.sub_tri.size() != ns)) {
        return "the sub-contact arrays differ in length";
    }
    if (c.sub_offset.empty() ? (nc != 0 || ns != 0)
                             : (c.sub_offset.size() != nc + 1 || c.sub_offset[0] != 0 ||
                                static_cast<size_t>(c.sub_offset[nc]) != ns)) {
        return "the sub-contact offsets are wrong";
    }
    for (size_t k = 0; k < nc; ++k) {
        if (c.sub_offset[k + 1] < c.sub_offset[k]) return "the sub-contact offsets are wrong";
        if (c.block_a[k] < 0 || c.block_b[k] < 0 || static_cast<size_t>(c.block_a[k]) >= n ||
            static_cast<size_t>(c.block_b[k]) >= n) {
            return "contact " + std::to_string(c.id[k]) + " refers to a block that does not exist";
        }
    }
    if (c.ref_orientation.size() != c.ref_centroid.size()) return "the detection caches differ in length";
    if (c.ref_centroid.size() == n &&
        (c.geo_centroid.size() != n || c.geo_orientation.size() != n || c.radius.size() != n)) {
        return "the detection caches differ in length";
    }
    const std::string zones = check_zones_consistent(m);
    if (!zones.empty()) return zones;
    const std::string cables = check_cables_consistent(m);
    if (!cables.empty()) return cables;
    {
        const FlowSet& f = m.flow;
        if (f.pos.size() != f.pp.size() || f.fixed.size() != f.pp.size() ||
            (!f.last_volume.empty() && f.last_volume.size() != f.pp.size())) {
            return "the flow nodes' arrays differ in length";
        }
        for (double v : f.last_volume) {
            if (!(v >= 0) || !std::isfinite(v)) return "a flow node's volume is no finite number at or above 0";
        }
        if (!(f.density > 0) || !(f.viscosity > 0) || !(f.bulk > 0) || !std::isfinite(f.density + f.viscosity + f.bulk)) {
            return "the fluid's density, viscosity and bulk modulus must be finite numbers above 0";
        }
        if (f.substeps < 1 || f.substeps > 100000 || !std::isfinite(f.wtable) || !std::isfinite(f.time) || f.steps < 0) {
            return "the flow settings are out of range";
        }
        for (std::size_t i = 0; i < f.pp.size(); ++i) {
            if (!(f.pp[i] >= 0) || !std::isfinite(f.pp[i]) || !f.pos[i].allFinite() || f.fixed[i] > 1) {
                return "flow node " + std::to_string(i + 1) + " has a pressure or position that is no finite number";
            }
        }
        for (const JointMaterial& j : m.joint_materials) {
            if (!(j.azero >= 0) || !(j.ares >= 0) || !(j.amax >= 0) || !std::isfinite(j.azero + j.ares + j.amax)) {
                return "a joint material has a hydraulic aperture that is no finite number at or above 0";
            }
        }
    }
    const std::string liners = check_liners_consistent(m);
    if (!liners.empty()) return liners;
    const HistorySet& h = m.histories;
    for (const History& item : h.items) {
        if (item.first < 0 || static_cast<size_t>(item.first) > h.sample_steps.size() ||
            item.values.size() != h.sample_steps.size() - static_cast<size_t>(item.first)) {
            return "a history's samples do not match the model's";
        }
        if (item.kind == HistoryKind::Energy && !is_energy_term(item.source)) {
            return "an energy history records '" + item.source + "', which is no term of the energy account";
        }
        // -1: none; -2: removed with its block (the history samples 0).
        if (item.gridpoint < -2 || item.gridpoint >= m.gridpoints.size()) {
            return "a history refers to gridpoint " + std::to_string(item.gridpoint) + ", which does not exist";
        }
        if (item.zone < -2 || item.zone >= m.zones.size()) {
            return "a history refers to zone " + std::to_string(item.zone) + ", which does not exist";
        }
        for (int g : item.gridpoints) {
            if (g < 0 || g >= m.gridpoints.size()) {
                return "a reaction history refers to gridpoint " + std::to_string(g) + ", which does not exist";
            }
        }
        for (int id : item.blocks) {
            if (id < 1) return "a reaction history refers to block id " + std::to_string(id);
        }
    }
    return "";
}

// Every number of a restored model, checked as carefully as typed input: finite, within the
// limits the commands that set it would enforce, and indices, counts and ids consistent. A
// file edited and its checksum recomputed must not bring inf, NaN or a dangling index into a
// model that then cycles on. Returns what is wrong, or "".
// Where a number is, as the start of a message ("block 3: "): kept as a kind and a number, and
// made text only when a check fails. Checks run on every number of the model before each save;
// a string for each would cost more than the checks (and memory when it is short).
struct Where {
    const char* kind = nullptr;
    long long n = 0;
    std::string text() const { return kind ? std::string(kind) + " " + std::to_string(n) + ": " : std::string(); }
};

class ValueCheck {
public:
    std::string problem;
    bool ok() const { return problem.empty(); }
    bool fail(const std::string& what) {
        if (problem.empty()) problem = what;
        return false;
    }
    bool fail(const Where& w, const std::string& what) { return problem.empty() ? fail(w.text() + what) : false; }
    bool finite(double x, const char* what) { return finite(x, Where{}, what); }
    bool finite(double x, const Where& w, const char* what) {
        return std::isfinite(x) || fail(w, std::string(what) + " is not a finite number");
    }
    bool at_least(double x, double lo, const char* what) { return at_least(x, lo, Where{}, what); }
    bool at_least(double x, double lo, const Where& w, const char* what) {
        return (finite(x, w, what) && x >= lo) || fail(w, std::string(what) + " is " + num(x) + ", below " + num(lo));
    }
    bool between(double x, double lo, double hi, const char* what) {
        return (finite(x, what) && x >= lo && x <= hi) ||
               fail(std::string(what) + " is " + num(x) + ", outside " + num(lo) + " to " + num(hi));
    }
    bool angle(double x, const Where& w, const char* what) {
        return (finite(x, w, what) && x >= 0 && x < 90) ||
               fail(w, std::string(what) + " is " + num(x) + " degrees, outside 0 to 90");
    }
    bool vec(const Vec3& v, const char* what) { return vec(v, Where{}, what); }
    bool vec(const Vec3& v, const Where& w, const char* what) {
        return v.allFinite() || fail(w, std::string(what) + " is not a finite number");
    }
    bool mat(const Mat3& a, const Where& w, const char* what) {
        return a.allFinite() || fail(w, std::string(what) + " is not a finite number");
    }
    bool quat(const Quat& q, const char* what) { return quat(q, Where{}, what); }
    bool quat(const Quat& q, const Where& w, const char* what) {
        return (q.coeffs().allFinite() && std::abs(q.norm() - 1) < 1e-6) ||
               fail(w, std::string(what) + " is not a unit quaternion");
    }
    template <class T>
    bool all_vec(const std::vector<T>& v, const char* what) { return all_vec(v, Where{}, what); }
    template <class T>
    bool all_vec(const std::vector<T>& v, const Where& w, const char* what) {
        for (size_t i = 0; i < v.size(); ++i) {
            if (!v[i].allFinite()) return fail(w, std::string(what) + " " + std::to_string(i + 1) + " is not a finite number");
        }
        return true;
    }

private:
    static std::string num(double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6g", x);
        return buf;
    }
};

std::string check_values(const Model& m) {
    ValueCheck c;
    // The model itself.
    if (m.step < 0 || m.step > kMaxStep) c.fail("the step number is " + std::to_string(m.step) + ", outside 0 to 1e18");
    c.at_least(m.time, 0, "the model time");
    c.at_least(m.dt, 0, "the timestep");
    c.vec(m.gravity, "gravity");
    if (m.n_joint_sets < 0 || m.slivers_skipped < 0) c.fail("a count of joint sets or slivers is negative");
    // Settings, as 'set' limits them.
    const Settings& st = m.settings;
    c.at_least(st.dt_fixed, 0, "the forced timestep");
    if (c.finite(st.dtfrac, "dtfrac") && !(st.dtfrac > 0 && st.dtfrac <= 1)) c.fail("dtfrac is outside (0, 1]");
    c.at_least(st.ctol, 0, "the contact tolerance");
    c.at_least(st.ovtol, 0, "the overlap tolerance");
    if (st.default_jmat < 1 || st.default_jmat > 1000000) c.fail("the default joint material is out of range");
    if (st.default_jcons < 1 || st.default_jcons > 2) c.fail("the default joint model is out of range");
    c.at_least(st.mscale_dt, 0, "the mscale timestep");
    if (st.dynamic && !st.dyn_configured) c.fail("dynamic mode is on without 'config dyn'");
    // Damping, as 'damp' limits it.
    const Damping& d = m.damping;
    if (c.finite(d.local, "the local damping") && !(d.local >= 0 && d.local < 1)) c.fail("the local damping is outside [0, 1)");
    c.between(d.rayleigh_fraction, 0, 1, "the Rayleigh damping fraction");
    c.at_least(d.rayleigh_frequency, 0, "the Rayleigh damping frequency");
    c.at_least(d.auto_coefficient, 0, "the adaptive damping coefficient");
    c.finite(d.auto_after, "the adaptive damping's power of the last step");
    c.at_least(d.auto_inertia, 0, "the adaptive damping's inertia of the last step");
    c.at_least(d.auto_dt, 0, "the adaptive damping's timestep of the last step");
    // The energy account: finite sums, begun at a step taken.
    const EnergyAccount& e = m.energy;
    for (double x : {e.initial, e.given, e.gravity, e.load, e.velocity, e.damping, e.pending_gravity,
                     e.pending_load, e.pending_velocity, e.pending_damping, e.slip, e.plastic, e.kinetic,
                     e.mark_kinetic, e.mark_strain}) {
        c.finite(x, "a term of the energy account");
    }
    c.at_least(e.peak, 0, "the energy account's peak");
    if (e.start_step < 0 || e.start_step > m.step) c.fail("the energy account began at a step not yet taken");
    for (double t : m.profile.seconds) c.at_least(t, 0, "a profile time");
    if (m.profile.steps < 0 || m.profile.steps > kMaxStep) c.fail("the profiled step count is outside 0 to 1e18");
    // Materials, as 'prop' limits them (a material given only other properties has density 0).
    for (size_t k = 0; k < m.materials.size(); ++k) {
        const Material& x = m.materials[k];
        const Where w{"material", static_cast<long long>(k)};
        c.at_least(x.density, 0, w, "the density");
        c.at_least(x.bulk, 0, w, "the bulk modulus");
        c.at_least(x.shear, 0, w, "the shear modulus");
        c.at_least(x.cohesion, 0, w, "the cohesion");
        c.at_least(x.tension, 0, w, "the tension");
        c.angle(x.friction, w, "the friction angle");
        c.angle(x.dilation, w, "the dilation angle");
    }
    for (size_t k = 0; k < m.joint_materials.size(); ++k) {
        const JointMaterial& x = m.joint_materials[k];
        const Where w{"joint material", static_cast<long long>(k)};
        c.at_least(x.kn, 0, w, "the normal stiffness");
        c.at_least(x.ks, 0, w, "the shear stiffness");
        c.at_least(x.cohesion, 0, w, "the cohesion");
        c.at_least(x.tension, 0, w, "the tension");
        c.at_least(x.zdilation, 0, w, "the dilation limit");
        c.angle(x.friction, w, "the friction angle");
        c.angle(x.dilation, w, "the dilation angle");
        c.angle(x.res_friction, w, "the residual friction angle");
    }
    for (const JointPlane& p : m.joint_planes) {
        if (p.set < 1 || p.jmat < 0 || p.jmat > 1000000) c.fail("a joint plane is out of range");
    }
    // Blocks.
    const BlockSet& s = m.blocks;
    const int n = s.size();
    for (int b = 0; b < n && c.ok(); ++b) {
        const Where w{"block", s.id[b]};
        if (s.id[b] < 1 || (b > 0 && s.id[b] <= s.id[b - 1]) || s.id[b] >= m.next_block_id) {
            c.fail("the block ids are not unique, increasing and below the next id");
            break;
        }
        const Polyhedron& p = s.shape[b];
        if (p.n_vertices() < 4 || p.n_faces() < 4) c.fail(w, "its shape has too few vertices or faces");
        c.all_vec(p.vertices, w, "vertex");
        for (int f = 0; f < p.n_faces(); ++f) {
            if (p.face_size(f) < 3) c.fail(w, "a face has fewer than 3 vertices");
        }
        for (int j : p.face_joint) {
            if (j < 0 || j > static_cast<int>(m.joint_planes.size())) c.fail(w, "a face refers to a joint plane that does not exist");
        }
        c.vec(s.centroid[b], w, "the centroid");
        c.quat(s.orientation[b], w, "the orientation");
        c.vec(s.vel[b], w, "the velocity");
        c.vec(s.ang_vel[b], w, "the angular velocity");
        c.vec(s.accel[b], w, "the acceleration");
        c.vec(s.ang_accel[b], w, "the angular acceleration");
        c.vec(s.force[b], w, "the force");
        c.vec(s.moment[b], w, "the moment");
        for (const BlockLoad& l : s.loads[b]) {
            if (!c.vec(l.lever, w, "the point of an applied load") || !c.vec(l.force, w, "an applied force") ||
                !c.vec(l.couple, w, "an applied couple")) {
                break;
            }
            if (l.table < 0 || l.table > 1000000) {
                c.fail(w, "the table of an applied load is out of range");
                break;
            }
        }
        c.at_least(s.force_scale[b], 0, w, "the force scale");
        c.vec(s.disp[b], w, "the displacement");
        c.quat(s.ref_orientation[b], w, "the orientation at the last 'reset disp'");
        if (c.finite(s.volume[b], w, "the volume") && !(s.volume[b] > 0)) c.fail(w, "the volume is not positive");
        c.at_least(s.mass[b], 0, w, "the mass");
        // The integration divides by the inertial mass of every block that has a mass.
        if (c.at_least(s.inertial_mass[b], 0, w, "the inertial mass") && s.mass[b] > 0 && !(s.inertial_mass[b] > 0)) {
            c.fail(w, "the inertial mass is zero for a block with mass");
        }
        c.at_least(s.inertial_moment[b], 0, w, "the inertial moment");
        c.mat(s.inertia_body[b], w, "the inertia");
        c.mat(s.inertia_unit[b], w, "the unit inertia");
        if (s.material[b] < 1 || s.material[b] > 1000000) c.fail(w, "the material number is out of range");
        if (s.region[b] < 0) c.fail(w, "the region number is negative");
        if (s.flags[b] > (kFixed | kHidden | kExcavated | kDeformable) || s.vel_bc[b] > 7 || s.half_kick[b] > 1) {
            c.fail(w, "a flag is out of range");
        }
        if (s.cons[b] > kZoneMohrCoulomb) c.fail(w, "its zone model is " + std::to_string(s.cons[b]) + " (0 to 2 allowed)");
        // 'gen' zones a block again with the edge it was zoned with (0: none yet).
        c.at_least(s.zone_edge[b], 0, w, "its zone edge");
        // Zoning numbers new continua from the largest one there is, plus one.
        if (s.body[b] > 1000000000) c.fail(w, "its continuum number is out of range");
        c.vec(s.vel_bc_value[b], w, "the boundary velocity");
        if (s.vel_bc_table[b] < 0 || s.vel_bc_table[b] > 1000000) {
            c.fail(w, "the boundary velocity table is out of range");
        }
    }
    if (!c.ok()) return c.problem;
    if (!world_vertices_stale(m)) c.all_vec(s.world_vertices, "world vertex");
    // Zones, as 'change cons', 'insitu' and the cycle leave them.
    const ZoneSet& z = m.zones;
    for (int i = 0; i < z.size() && c.ok(); ++i) {
        const Where w{"zone", i + 1};
        if (z.model[i] > kZoneMohrCoulomb) c.fail(w, "its model is " + std::to_string(z.model[i]) + " (0 to 2 allowed)");
        if (z.state[i] > (kShearNow | kTensionNow | kShearPast | kTensionPast)) c.fail(w, "its state is out of range");
        for (double x : z.stress[i]) {
            if (!c.finite(x, w, "the stress")) break;
        }
        c.finite(z.volume[i], w, "the volume");
    }
    for (size_t i = 0; i < z.grad.size() && c.ok(); ++i) {
        for (double x : z.grad[i]) {
            if (!c.finite(x, Where{"zone", static_cast<long long>(i) + 1}, "a shape-function gradient")) break;
        }
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size() && c.ok(); ++i) {
        const Where w{"gridpoint", i + 1};
        c.vec(g.pos[i], w, "the position");
        c.vec(g.ref[i], w, "the reference position");
        c.vec(g.vel[i], w, "the velocity");
        c.vec(g.disp[i], w, "the displacement");
        c.vec(g.force[i], w, "the force");
        c.vec(g.applied[i], w, "the applied force");
        if (g.applied_table[i] < 0 || g.applied_table[i] > 1000000) c.fail(w, "the applied force's table is out of range");
        c.vec(g.traction[i], w, "the traction");
        c.at_least(g.mass[i], 0, w, "the mass");
        if (c.at_least(g.inertial_mass[i], 0, w, "the inertial mass") && g.mass[i] > 0 && !(g.inertial_mass[i] > 0)) {
            c.fail(w, "the inertial mass is zero for a gridpoint with mass");
        }
        c.at_least(g.stiffness[i], 0, w, "the stiffness");
        c.at_least(g.force_scale[i], 0, w, "the force scale");
        c.at_least(g.nmd_volume[i], 0, w, "the volume around it");
        c.finite(g.nmd_rate[i], w, "the volumetric rate around it");
        if (g.vel_bc[i] > 7 || g.half_kick[i] > 1) c.fail(w, "a flag is out of range");
        c.vec(g.vel_bc_value[i], w, "the boundary velocity");
        if (g.vel_bc_table[i] < 0 || g.vel_bc_table[i] > 1000000) c.fail(w, "the boundary velocity table is out of range");
    }
    for (const BoundaryFace& f : m.stress_boundary.faces) {
        if (!c.vec(f.force, "the force on a face loaded by 'bound stress'")) break;
        if (f.table < 0 || f.table > 1000000) {
            c.fail("the table of a face loaded by 'bound stress' is out of range");
            break;
        }
    }
    // Contacts.
    const ContactSet& cs = m.contacts;
    for (int k = 0; k < cs.size() && c.ok(); ++k) {
        const Where w{"contact", cs.id[k]};
        if (cs.id[k] < 1 || cs.id[k] >= cs.next_id) c.fail(w, "its id is out of range");
        if (!(cs.block_a[k] < cs.block_b[k])) c.fail(w, "its blocks are not in order (a < b)");
        if (std::abs(static_cast<long>(cs.normal_code[k].u)) > kNormalCodeLimit ||
            std::abs(static_cast<long>(cs.normal_code[k].v)) > kNormalCodeLimit) {
            c.fail(w, "the normal's code is out of range");
        }
        c.finite(cs.gap[k], w, "the gap");
        if (cs.jmat(k) > 1000000) c.fail(w, "the joint material is out of range");
        const double kn = contact_kn(m, k);
        for (int i = cs.sub_offset[k]; i < cs.sub_offset[k + 1] && c.ok(); ++i) {
            const int side = cs.sub_side(i);
            const int a = cs.block_a[k], b = cs.block_b[k];
            const bool deformable_pair = ((s.flags[a] | s.flags[b]) & kDeformable) != 0;
            // Right after 'gen' (geometry_changed) a pair of zoned blocks still has the vertex
            // sub-contacts it had as rigid blocks: they are rebuilt before anything cycles.
            const bool side_ok = side <= 4 && (side >= 3 ? deformable_pair : !deformable_pair || m.geometry_changed);
            if (!side_ok) c.fail(w, "a sub-contact side is out of range");
            if (side >= 3 && c.ok()) {
                // A gridpoint of its own block against the other's surface.
                const int own = side == 3 ? a : b, other = side == 3 ? b : a;
                const int ng = static_cast<int>(m.gridpoints.pos.size());
                if (!(s.flags[own] & kDeformable) || cs.sub_vertex(i) < 0 || cs.sub_vertex(i) >= ng) {
                    c.fail(w, "a sub-contact gridpoint is out of range");
                }
                if (cs.sub_key(i) != gridpoint_sub_key(side - 3, cs.sub_vertex(i))) {
                    c.fail(w, "a sub-contact key does not match its gridpoint");
                }
                const std::array<int, 3> t = cs.sub_triangle(i);
                const bool on_triangle = (s.flags[other] & kDeformable) != 0;
                for (int q : t) {
                    if (on_triangle ? (q < 0 || q >= ng) : q != -1) c.fail(w, "a sub-contact triangle is out of range");
                }
            } else if (c.ok()) {
                const int owner = side == 1 ? b : a;
                if (cs.sub_vertex(i) < -1 || cs.sub_vertex(i) >= s.shape[owner].n_vertices()) {
                    c.fail(w, "a sub-contact vertex is out of range");
                }
                for (int q : cs.sub_triangle(i)) {
                    if (q != -1) c.fail(w, "a sub-contact triangle is out of range");
                }
            }
            c.at_least(cs.sub_area[i], 0, w, "a sub-contact area");
            if (!point_code_valid(untagged_point(cs.sub_point[i]))) c.fail(w, "a sub-contact point's code is out of range");
            c.finite(cs.sub_un[i], w, "a normal closure");
            c.finite(cs.sub_dilation(i), w, "a dilation");
            c.finite(cs.sub_sn_for(k, i, kn), w, "a normal stress");
            c.vec(Vec3(cs.sub_us[i][0], cs.sub_us[i][1], 0), w, "a shear displacement");
            c.vec(Vec3(cs.sub_ss[i][0], cs.sub_ss[i][1], 0), w, "a shear stress");
        }
    }
    if (!c.ok()) return c.problem;
    // Ids in increasing order are distinct as they are; others are sorted in a copy (an int a
    // contact).
    if (std::adjacent_find(cs.id.begin(), cs.id.end(), std::greater_equal<int>()) != cs.id.end()) {
        std::vector<int> ids(cs.id.begin(), cs.id.end());
        std::sort(ids.begin(), ids.end());
        if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) return "two contacts have the same id";
    }
    c.at_least(cs.ctol, 0, "the contact tolerance in use");
    if (cs.n_detections < 0) c.fail("the detection count is negative");
    c.all_vec(cs.ref_centroid, "detection centroid");
    c.all_vec(cs.geo_centroid, "refresh centroid");
    for (const Quat& q : cs.ref_orientation) c.quat(q, "a detection orientation");
    for (const Quat& q : cs.geo_orientation) c.quat(q, "a refresh orientation");
    for (double r : cs.radius) c.at_least(r, 0, "a block radius");
    // In-situ fields kept for zones made later.
    for (size_t i = 0; i < m.insitu.size() && c.ok(); ++i) {
        const Where w{"in-situ field", static_cast<long long>(i) + 1};
        const StressField& f = m.insitu[i].field;
        for (const Sym6* t : {&f.s, &f.gx, &f.gy, &f.gz}) {
            for (double x : *t) {
                if (!c.finite(x, w, "a stress component")) break;
            }
        }
    }
    // Histories.
    const HistorySet& h = m.histories;
    if (h.ncyc < 1) c.fail("the history interval is below 1");
    for (size_t k = 0; k < h.sample_steps.size(); ++k) {
        if (h.sample_steps[k] < 0 || (k > 0 && h.sample_steps[k] < h.sample_steps[k - 1])) {
            c.fail("the history sample steps do not increase");
            break;
        }
    }
    for (size_t k = 0; k < h.items.size() && c.ok(); ++k) {
        const History& x = h.items[k];
        const Where w{"history", static_cast<long long>(k) + 1};
        c.vec(x.point, w, "the point");
        c.vec(x.body_offset, w, "the material point");
        if (x.block_id < 0 || x.contact_id < 0) c.fail(w, "it refers to a negative id");
        for (double v : x.values) {
            if (!std::isfinite(v)) {
                c.fail(w, "a value is not a finite number");
                break;
            }
        }
    }
    // Tables, as 'table' limits them.
    for (const auto& [number, t] : m.tables.tables) {
        const Where w{"table", number};
        if (number < 1 || number > 1000000) c.fail("a table number is out of range");
        if (t.points.empty()) c.fail(w, "it has no points");
        for (size_t k = 0; k < t.points.size(); ++k) {
            c.finite(t.points[k].first, w, "an x");
            c.finite(t.points[k].second, w, "a y");
            if (k > 0 && !(t.points[k].first > t.points[k - 1].first)) c.fail(w, "its x values do not increase");
        }
    }
    return c.problem;
}

// What restore would refuse in this model, or "": save and restore share one validation, so
// that every file odec writes can be read back.
std::string model_problem(const Model& m) {
    std::string why = check_consistent(m);
    if (why.empty()) why = check_values(m);
    return why;
}

std::string directory_of(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

// Write the model to `path` as it is: a temporary file beside it, written through a small
// buffer and flushed to disk, then renamed over `path`, so that `path` holds either its old
// bytes or all the new ones, never a part.
bool write_model(const Model& m, const std::string& path, std::string& error) {
    const std::string where = "cannot save to '" + path + "': ";
    // An existing file is replaced only when it is a writable regular file.
    struct stat st;
    if (::stat(path.c_str(), &st) == 0) {
        if (!S_ISREG(st.st_mode)) {
            error = where + "it is " + file_kind(st.st_mode) + ", not a regular file; nothing was written";
            return false;
        }
        if ((st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0) {
            error = "'" + path + "' is read-only: remove it or make it writable first; nothing was written";
            return false;
        }
    }
    // First pass: the length of every section, and of the payload, without storing a byte.
    SectionLengths lengths;
    Writer counter(nullptr, lengths);
    counter.drop_world_vertices = world_vertices_stale(m);
    model_sections(counter, m);
    const std::uint64_t payload = counter.written;
    const size_t n_sections = lengths.count;

    static std::atomic<unsigned> n_temporaries{0};
    const std::string tmp =
        path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(n_temporaries.fetch_add(1));
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
        error = where + "cannot create the temporary file '" + tmp + "': " + std::strerror(errno);
        return false;
    }
    auto give_up = [&](const std::string& why) {
        ::close(fd);
        ::unlink(tmp.c_str());
        error = where + why + " (the old file, if any, is unchanged)";
        return false;
    };
    // Second pass: the same walk, writing through the buffer and hashing.
    lengths.count = 0;
    try {
        Sink sink(fd);
        Writer w(&sink, lengths);
        w.drop_world_vertices = counter.drop_world_vertices;
        w.bytes(kMagic, kMagicSize);
        w.raw(kSaveFormatVersion);
        w(std::string(save_program_version()));
        w.raw(payload);
        const std::uint64_t payload_at = w.written;
        model_sections(w, m);
        if (w.lengths_differ || lengths.count != n_sections || w.written - payload_at != payload) {
            return give_up("the bytes written differ from those counted before writing");
        }
        const std::uint64_t checksum = sink.hash;
        sink.put(&checksum, sizeof checksum);
        sink.flush();
    } catch (const WriteFailure& f) {
        return give_up("writing '" + tmp + "' failed: " + std::strerror(f.error_number));
    }
    if (::fsync(fd) != 0) return give_up("writing '" + tmp + "' failed: " + std::strerror(errno));
    if (::close(fd) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        error = where + "writing '" + tmp + "' failed: " + std::strerror(e) + " (the old file, if any, is unchanged)";
        return false;
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        error = where + std::strerror(e) + " (the old file, if any, is unchanged)";
        return false;
    }
    // Make the rename itself durable; a failure here loses nothing already written.
    const int dfd = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return true;
}

// Whether `name` is "<something>.tmp-<pid>-<n>", the name of a save's temporary file; its
// process id in `pid`.
bool temporary_name(const std::string& name, long& pid) {
    const size_t dash = name.find_last_of('-');
    if (dash == std::string::npos || dash + 1 == name.size()) return false;
    for (size_t i = dash + 1; i < name.size(); ++i) {
        if (name[i] < '0' || name[i] > '9') return false;
    }
    const size_t tag = name.rfind(".tmp-", dash);
    if (tag == std::string::npos || tag == 0) return false;
    const size_t digits = tag + 5;
    if (digits >= dash || dash - digits > 9) return false;
    pid = 0;
    for (size_t i = digits; i < dash; ++i) {
        if (name[i] < '0' || name[i] > '9') return false;
        pid = pid * 10 + (name[i] - '0');
    }
    return pid > 0;
}

} // namespace

std::vector<std::string> remove_stale_save_temporaries(const std::string& dir) {
    std::vector<std::string> removed;
    DIR* d = ::opendir(dir.c_str());
    if (!d) return removed;
    const std::string prefix = dir == "." ? "" : dir.back() == '/' ? dir : dir + "/";
    const time_t now = ::time(nullptr);
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        long pid = 0;
        if (!temporary_name(name, pid)) continue;
        const std::string path = prefix + name;
        struct stat st;
        if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) continue;
        // Its process is gone (or is this one, which is not saving now: a process of an
        // earlier run with the same id) and it has not been written for a while; or it has
        // not been written for a day. A save under way writes its file continuously.
        const double idle = std::difftime(now, st.st_mtime);
        const bool gone = pid == ::getpid() || (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH);
        if (!((gone && idle >= kStaleTemporarySeconds) || idle >= 86400)) continue;
        // Only odec's own: empty (killed before its first write) or beginning as a save does.
        if (st.st_size > 0) {
            const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
            if (fd < 0) continue;
            char head[kMagicSize];
            const ssize_t k = ::pread(fd, head, sizeof head, 0);
            ::close(fd);
            const size_t want = std::min<size_t>(kMagicSize, static_cast<size_t>(st.st_size));
            if (k < 0 || static_cast<size_t>(k) < want || std::memcmp(head, kMagic, want) != 0) continue;
        }
        if (::unlink(path.c_str()) == 0) removed.push_back(path);
    }
    ::closedir(d);
    std::sort(removed.begin(), removed.end());
    return removed;
}

std::string stale_temporaries_note(const std::vector<std::string>& removed) {
    if (removed.empty()) return "";
    std::string note = "removed " + std::string(removed.size() == 1 ? "a temporary file" : std::to_string(removed.size()) + " temporary files") +
                       " left by a save that did not finish: ";
    const size_t shown = std::min<size_t>(removed.size(), 3);
    for (size_t i = 0; i < shown; ++i) note += (i > 0 ? ", '" : "'") + removed[i] + "'";
    if (removed.size() > shown) note += " and " + std::to_string(removed.size() - shown) + " more";
    return note;
}

std::string save_problem(const Model& m) { return model_problem(m); }

bool save_model(const Model& m, const std::string& path, std::string& error) {
    const std::string why = model_problem(m);
    if (!why.empty()) {
        error = "the model cannot be saved to '" + path + "': " + why + "; nothing was written";
        return false;
    }
    return write_model(m, path, error);
}

bool save_model_unchecked(const Model& m, const std::string& path, std::string& error) {
    return write_model(m, path, error);
}

namespace {

// Whether the files at a and b hold the same bytes, compared through two small buffers.
bool same_file_bytes(const std::string& a, const std::string& b, std::string& error) {
    std::string why;
    unsigned long long size_a = 0, size_b = 0;
    const int fa = open_regular_for_reading(a, size_a, why);
    if (fa < 0) {
        error = "cannot read '" + a + "': " + why;
        return false;
    }
    const int fb = open_regular_for_reading(b, size_b, why);
    if (fb < 0) {
        ::close(fa);
        error = "cannot read '" + b + "': " + why;
        return false;
    }
    bool same = size_a == size_b;
    std::unique_ptr<char[]> x(new char[kBufferBytes]), y(new char[kBufferBytes]);
    for (unsigned long long at = 0; same && at < size_a;) {
        const size_t n = static_cast<size_t>(std::min<unsigned long long>(kBufferBytes, size_a - at));
        same = ::pread(fa, x.get(), n, static_cast<off_t>(at)) == static_cast<ssize_t>(n) &&
               ::pread(fb, y.get(), n, static_cast<off_t>(at)) == static_cast<ssize_t>(n) &&
               std::memcmp(x.get(), y.get(), n) == 0;
        if (!same) {
            for (size_t i = 0; i < n; ++i) {
                if (x[i] != y[i]) {
                    error = "the two saves differ at byte " + std::to_string(at + i);
                    break;
                }
            }
        }
        at += n;
    }
    ::close(fa);
    ::close(fb);
    if (!same && error.empty()) {
        error = "the two saves differ in length (" + std::to_string(size_a) + " and " + std::to_string(size_b) + " bytes)";
    }
    return same;
}

} // namespace

bool check_save_round_trip(const Model& m, const std::string& dir, std::string& error) {
    const std::string first = dir + "/round-trip-" + std::to_string(::getpid()) + "-1.sav";
    const std::string second = dir + "/round-trip-" + std::to_string(::getpid()) + "-2.sav";
    bool ok = save_model(m, first, error);
    if (ok) {
        Model restored;
        ok = restore_model(first, restored, error) && save_model(restored, second, error) &&
             same_file_bytes(first, second, error);
    }
    ::unlink(first.c_str());
    ::unlink(second.c_str());
    return ok;
}

bool restore_model(const std::string& path, Model& out, std::string& error) {
    const std::string who = "cannot restore '" + path + "': ";
    auto refuse = [&](const std::string& what) {
        error = who + what;
        return false;
    };
    unsigned long long file_size = 0;
    std::string why;
    const int fd = open_regular_for_reading(path, file_size, why);
    if (fd < 0) return refuse(why);
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    const std::uint64_t size = file_size;
    // The header, at most this long: magic, format, program version, payload length.
    char head[kMagicSize + 4 + 8 + kMaxVersionText + 8];
    const size_t head_size = static_cast<size_t>(std::min<std::uint64_t>(size, sizeof head));
    for (size_t got = 0; got < head_size;) {
        const ssize_t k = ::pread(fd, head + got, head_size - got, static_cast<off_t>(got));
        if (k < 0 && errno == EINTR) continue;
        if (k < 0) return refuse(std::strerror(errno));
        if (k == 0) return refuse("the file became shorter while it was read");
        got += static_cast<size_t>(k);
    }
    auto truncated_header = [&] {
        return refuse("the file is truncated: it ends at byte " + std::to_string(size) + ", inside the header");
    };
    if (size == 0) return refuse("the file is empty");
    if (std::memcmp(head, kMagic, std::min<size_t>(head_size, kMagicSize)) != 0) {
        return refuse("it is not an odec save file (it does not begin with 'ODEC-SAVE')");
    }
    if (size < kMagicSize + 4) return truncated_header();
    Reader header(head + kMagicSize, head + head_size);
    std::string writer_version;
    std::uint32_t file_format = 0;
    try {
        const std::uint32_t format = header.raw<std::uint32_t>();
        file_format = format;
        // The program version is read before judging the format, to name the odec that wrote it.
        std::string version_note;
        if (header.left() >= 8) {
            const std::uint64_t n = header.raw<std::uint64_t>();
            if (n <= kMaxVersionText && header.left() >= n) {
                writer_version.resize(static_cast<size_t>(n));
                for (char& ch : writer_version) ch = header.raw<char>();
                version_note = " by odec " + writer_version;
            } else if (format <= kSaveFormatVersion && n > kMaxVersionText) {
                return refuse("the file is damaged: its header gives a program version of " + std::to_string(n) +
                              " bytes");
            }
        }
        if (format > kSaveFormatVersion) {
            return refuse("it was written" + version_note + " in save format " + std::to_string(format) +
                          ", newer than this odec (" + save_program_version() + ") reads (format " +
                          std::to_string(kSaveFormatVersion) + " and older); restore it with a newer odec");
        }
        if (format == 0) return refuse("the file is damaged: its header gives save format 0");
        if (version_note.empty() || header.left() < 8) return truncated_header();
    } catch (const ReadError&) {
        return truncated_header();
    }
    const std::uint64_t payload = header.raw<std::uint64_t>();
    const std::uint64_t header_size = head_size - header.left();
    if (payload > std::numeric_limits<std::uint64_t>::max() - header_size - kChecksumSize) {
        return refuse("the file is damaged: its header gives a payload of " + std::to_string(payload) + " bytes");
    }
    // The size the header promises, compared with the file's before any more of it is read.
    const std::uint64_t expected = header_size + payload + kChecksumSize;
    if (size < expected) {
        return refuse("the file is truncated: it has " + std::to_string(size) + " bytes, a complete save has " +
                      std::to_string(expected));
    }
    if (size > expected) {
        return refuse("the file is damaged: it has " + std::to_string(size - expected) +
                      " bytes after the end of the save");
    }
    // The checksum first, through a small buffer: nothing of the model is believed before it.
    std::uint64_t computed = 0, stored = 0;
    try {
        Source whole(fd);
        whole.get(nullptr, static_cast<size_t>(size - kChecksumSize));
        computed = whole.hash;
        whole.get(&stored, kChecksumSize);
    } catch (const ReadFailure& f) {
        return refuse(std::strerror(f.error_number));
    } catch (const ReadError& e) {
        return refuse(e.what);
    }
    if (stored != computed) {
        return refuse("the file is damaged: its checksum does not match its contents (stored " + hex(stored) +
                      ", computed " + hex(computed) + ")");
    }
    // Then the model, read again from the start.
    if (::lseek(fd, 0, SEEK_SET) != 0) return refuse(std::strerror(errno));
    Model fresh;
    try {
        Source src(fd);
        src.get(nullptr, static_cast<size_t>(header_size));
        Reader r(src, header_size, size - kChecksumSize);
        r.format = file_format;
        model_sections(r, fresh);
        if (r.left() != 0) {
            return refuse("the file is damaged: " + std::to_string(r.left()) + " bytes follow the last section");
        }
        if (src.hash != computed) return refuse("the file changed while it was read");
        if (file_format < 2) {
            for (History& h : fresh.histories.items) {
                const int b = fresh.block_index(h.block_id);
                if (b >= 0) h.body_offset = fresh.blocks.orientation[b].conjugate() * (h.point - fresh.blocks.centroid[b]);
            }
        }
        // Stale world vertices (older odecs wrote them) are dropped, not believed.
        if (world_vertices_stale(fresh)) {
            fresh.blocks.vertex_offset.clear();
            fresh.blocks.world_vertices.clear();
        }
        if (file_format < 3) {
            // Every block of an older file is rigid, with the zone model a new block gets.
            const size_t n = fresh.blocks.id.size();
            fresh.blocks.cons.assign(n, kZoneElastic);
            fresh.blocks.corner_gp.assign(n, {});
            fresh.blocks.zone_edge.assign(n, 0.0);
            fresh.blocks.body.assign(n, 0);
        }
        // Older files have no clumps: the pieces of a solid that is not convex stay glued by
        // their joined joint set, as they were saved.
        if (file_format < 12) fresh.blocks.clump.assign(fresh.blocks.id.size(), 0);
        if (file_format < 4) fresh.contacts.sub_tri.clear(); // no triangles: kept as none
        if (file_format < 7) fresh.gridpoints.applied_table.assign(fresh.gridpoints.pos.size(), 0);
        if (file_format < 9) {
            // A history made during a run had a NaN for each sample before it; a history with
            // fewer values than samples (its samples skipped while FISH changed the list) had
            // them last.
            const size_t samples = fresh.histories.sample_steps.size();
            for (History& h : fresh.histories.items) {
                size_t lead = 0;
                while (lead < h.values.size() && std::isnan(h.values[lead])) ++lead;
                h.values.erase(h.values.begin(), h.values.begin() + static_cast<long>(lead));
                h.first = h.values.size() <= samples ? static_cast<long>(samples - h.values.size()) : 0;
            }
        }
        if (file_format < 6) {
            // Computed with real masses and real time: they go on in dynamic mode.
            fresh.settings.dyn_configured = true;
            fresh.settings.dynamic = true;
            fresh.blocks.inertial_mass = fresh.blocks.mass;
            fresh.blocks.inertial_moment.assign(fresh.blocks.mass.size(), 0.0);
            fresh.gridpoints.inertial_mass = fresh.gridpoints.mass;
        }
    } catch (const ReadFailure& f) {
        return refuse(std::strerror(f.error_number));
    } catch (const ReadError& e) {
        return refuse("the file is damaged or was written wrongly (by odec " + writer_version + "): " + e.what);
    }
    why = model_problem(fresh);
    if (!why.empty()) return refuse("the file is damaged or was written wrongly (by odec " + writer_version + "): " + why);
    out = std::move(fresh);
    return true;
}

} // namespace odec
