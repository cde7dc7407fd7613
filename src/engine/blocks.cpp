#include "engine/blocks.h"
#include "engine/simd.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/parallel.h"
#include "engine/zones.h"

namespace odec {

// Every per-block array, so that adding and removing blocks cannot forget one.
template <class F>
static void for_each_array(BlockSet& s, F&& f) {
    f(s.id); f(s.shape); f(s.centroid); f(s.orientation); f(s.vel); f(s.ang_vel);
    f(s.accel); f(s.ang_accel); f(s.force); f(s.moment); f(s.loads); f(s.force_scale);
    f(s.disp); f(s.ref_orientation); f(s.volume); f(s.mass); f(s.inertia_body); f(s.inertia_unit);
    f(s.inertial_mass); f(s.inertial_moment);
    f(s.material); f(s.region); f(s.group); f(s.flags); f(s.vel_bc); f(s.vel_bc_value);
    f(s.vel_bc_table); f(s.half_kick); f(s.cons); f(s.corner_gp); f(s.zone_edge); f(s.body);
    f(s.clump);
}

int add_block(Model& m, const Polyhedron& world, int region, int group, int material) {
    const MassProperties mp = mass_properties(world);
    Polyhedron local = world;
    local.translate(-mp.centroid);
    BlockSet& s = m.blocks;
    s.id.push_back(m.next_block_id++);
    s.shape.push_back(std::move(local));
    s.centroid.push_back(mp.centroid);
    s.orientation.push_back(Quat::Identity());
    s.vel.push_back(Vec3::Zero());
    s.ang_vel.push_back(Vec3::Zero());
    s.accel.push_back(Vec3::Zero());
    s.ang_accel.push_back(Vec3::Zero());
    s.force.push_back(Vec3::Zero());
    s.moment.push_back(Vec3::Zero());
    s.loads.emplace_back();
    s.force_scale.push_back(0);
    s.disp.push_back(Vec3::Zero());
    s.ref_orientation.push_back(Quat::Identity());
    s.volume.push_back(mp.volume);
    s.mass.push_back(0);
    s.inertia_body.push_back(Mat3::Zero());
    s.inertia_unit.push_back(mp.inertia);
    s.inertial_mass.push_back(0);
    s.inertial_moment.push_back(0);
    s.material.push_back(material);
    s.region.push_back(region);
    s.group.push_back(group);
    s.flags.push_back(0);
    s.vel_bc.push_back(0);
    s.vel_bc_value.push_back(Vec3::Zero());
    s.vel_bc_table.push_back(0);
    s.half_kick.push_back(1);
    s.cons.push_back(kZoneElastic);
    s.corner_gp.emplace_back();
    s.zone_edge.push_back(0);
    s.body.push_back(0);
    s.clump.push_back(0);
    const int b = s.size() - 1;
    const int mat = material;
    const double rho = (mat > 0 && mat < static_cast<int>(m.materials.size())) ? m.materials[mat].density : 0.0;
    s.mass[b] = rho * mp.volume;
    s.inertia_body[b] = rho * mp.inertia;
    s.inertial_mass[b] = s.mass[b];
    m.geometry_changed = true;
    return b;
}

std::string block_numbers_problem(const MassProperties& mp, double density) {
    auto text = [](double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3g", x);
        return std::string(buf);
    };
    if (!std::isfinite(mp.volume) || !mp.centroid.allFinite()) {
        return std::isfinite(mp.volume) || std::isinf(mp.volume)
                   ? "the block is too large: its volume overflows (" + text(mp.volume) + " m^3)"
                   : std::string("the block is too large: its volume overflows");
    }
    if (!(mp.volume > 0) || !std::isnormal(mp.volume)) {
        return "the block is too small: its volume underflows (" + text(mp.volume) + " m^3)";
    }
    const double i_min = std::min({mp.inertia(0, 0), mp.inertia(1, 1), mp.inertia(2, 2)});
    if (!mp.inertia.allFinite()) return "the block is too large: its moment of inertia overflows";
    if (!(i_min > 0) || !std::isnormal(i_min)) return "the block is too small: its moment of inertia underflows";
    if (density > 0) {
        const double mass = density * mp.volume;
        if (!std::isfinite(mass) || !(density * mp.inertia).allFinite()) {
            return "its mass, density " + text(density) + " times volume " + text(mp.volume) +
                   " m^3, overflows";
        }
        if (!std::isnormal(mass) || !std::isnormal(density * i_min)) {
            return "its mass, density " + text(density) + " times volume " + text(mp.volume) +
                   " m^3, underflows";
        }
    }
    return "";
}

std::vector<int> replace_by_pieces(Model& m, int b, const std::vector<Polyhedron>& pieces, const Vec3& origin) {
    BlockSet& s = m.blocks;
    std::vector<MassProperties> mp;
    double total = 0;
    for (const Polyhedron& p : pieces) {
        mp.push_back(mass_properties(p));
        total += mp.back().volume;
    }
    const Vec3 v0 = s.vel[b];
    const Vec3 w0 = s.ang_vel[b];
    // b's loads: those at its centroid are shared by volume (each piece takes its share at its
    // own centroid); one at another point goes whole to the piece holding that point (or the
    // piece whose centroid is nearest), at the same material point.
    std::vector<BlockLoad> loads = std::move(s.loads[b]);
    s.loads[b].clear();
    // The parent's pose now and at the last 'reset disp'. Each piece's body frame is the world
    // axes, so its reference orientation is the parent's turned back by the parent's present
    // orientation, and its centroid's displacement is that of the parent's material point there:
    // every point of every piece keeps its exact displacement since the reset.
    const Vec3 c_parent = s.centroid[b];
    const Quat q_parent = s.orientation[b];
    const Vec3 d_parent = s.disp[b];
    const Quat q_ref = (s.ref_orientation[b] * q_parent.conjugate()).normalized();
    auto piece_disp = [&](const Vec3& c) { return Vec3(d_parent + (c - c_parent) - q_ref * (c - c_parent)); };
    std::vector<int> out{b};
    {
        // The first piece takes b's place, its body frame along the world axes.
        Polyhedron local = pieces[0];
        local.translate(-mp[0].centroid);
        s.shape[b] = std::move(local);
        s.centroid[b] = origin + mp[0].centroid;
        s.orientation[b] = Quat::Identity();
        s.ref_orientation[b] = q_ref;
        s.disp[b] = piece_disp(s.centroid[b]);
        s.volume[b] = mp[0].volume;
        s.inertia_unit[b] = mp[0].inertia;
        const int mat = s.material[b];
        const double rho = (mat > 0 && mat < static_cast<int>(m.materials.size())) ? m.materials[mat].density : 0.0;
        s.mass[b] = rho * mp[0].volume;
        s.inertia_body[b] = rho * mp[0].inertia;
        s.inertial_mass[b] = s.mass[b];
        s.inertial_moment[b] = 0;
        s.vel[b] = v0 + w0.cross(mp[0].centroid);
    }
    for (size_t k = 1; k < pieces.size(); ++k) {
        const int a = add_block(m, pieces[k], s.region[b], s.group[b], s.material[b]);
        // No element references are held across add_block, which grows every array.
        s.centroid[a] += origin; // the piece was given relative to origin
        s.vel[a] = v0 + w0.cross(mp[k].centroid);
        s.ang_vel[a] = w0;
        s.accel[a] = s.accel[b];
        s.ang_accel[a] = s.ang_accel[b];
        s.disp[a] = piece_disp(s.centroid[a]);
        s.ref_orientation[a] = q_ref;
        s.flags[a] = s.flags[b];
        s.vel_bc[a] = s.vel_bc[b];
        s.vel_bc_value[a] = s.vel_bc_value[b];
        s.vel_bc_table[a] = s.vel_bc_table[b];
        s.half_kick[a] = s.half_kick[b];
        s.cons[a] = s.cons[b];
        out.push_back(a);
    }
    for (const BlockLoad& l : loads) {
        if (l.lever.isZero(0)) {
            for (size_t k = 0; k < out.size(); ++k) {
                BlockLoad share = l;
                share.force *= mp[k].volume / total;
                share.couple *= mp[k].volume / total;
                s.loads[out[k]].push_back(share);
            }
            continue;
        }
        const Vec3 point = c_parent + q_parent * l.lever;
        size_t best = 0;
        double best_distance = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < pieces.size(); ++k) {
            const Vec3 local = point - origin;
            if (contains_point(pieces[k], local, 0)) {
                best = k;
                break;
            }
            const double d = (local - mp[k].centroid).squaredNorm();
            if (d < best_distance) {
                best_distance = d;
                best = k;
            }
        }
        BlockLoad moved = l;
        moved.lever = point - s.centroid[out[best]]; // the pieces' body frames are the world axes
        s.loads[out[best]].push_back(moved);
    }
    // The histories of the parent's material points follow them into the piece that holds them
    // (the nearest piece by centroid for a point outside the parent), in its frame.
    // The piece holding the parent's material point x (world), or -1.
    auto piece_holding = [&](const Vec3& x) {
        for (size_t k = 0; k < pieces.size(); ++k) {
            if (contains_point(pieces[k], x - origin, 1e-9)) return static_cast<int>(k);
        }
        return -1;
    };
    for (History& h : m.histories.items) {
        if (h.block_id != s.id[b] || h.gridpoint != -1) continue;
        const Vec3 x = c_parent + q_parent * h.body_offset;
        int best = piece_holding(x);
        if (best < 0) {
            best = 0;
            for (size_t k = 1; k < pieces.size(); ++k) {
                if ((s.centroid[out[k]] - x).stableNorm() < (s.centroid[out[best]] - x).stableNorm()) best = static_cast<int>(k);
            }
        }
        h.block_id = s.id[out[best]];
        h.body_offset = x - s.centroid[out[best]];
    }
    // Cable and liner nodes tied to the parent's material points stay tied to those points, now
    // in the piece that holds them and in its frame (the grout or bond keeps its force and slip:
    // the rock there is the same). A node whose point is in no piece keeps the parent's id with
    // the point's lever from the first piece: the tie no longer stands, and the next attach finds
    // the node the rock that holds it now.
    auto retie = [&](std::vector<int>& host_block, std::vector<Vec3>& host_lever,
                     const std::vector<std::array<int, 4>>& host_gp) {
        const int parent = s.id[b];
        for (size_t i = 0; i < host_block.size(); ++i) {
            if (host_block[i] != parent || host_gp[i][0] >= 0) continue;
            const Vec3 x = c_parent + q_parent * host_lever[i];
            const int best = piece_holding(x);
            const int piece = out[best < 0 ? 0 : best];
            host_block[i] = s.id[piece];
            host_lever[i] = x - s.centroid[piece]; // the pieces' body frames are the world axes
        }
    };
    retie(m.cables.host_block, m.cables.host_lever, m.cables.host_gp);
    retie(m.liners.host_block, m.liners.host_lever, m.liners.host_gp);
    return out;
}

void remove_blocks(Model& m, std::vector<int> idx) {
    std::sort(idx.begin(), idx.end());
    idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
    if (idx.empty()) return;
    const int n = m.blocks.size();
    std::vector<char> gone(n, 0);
    for (int b : idx) gone[b] = 1;
    remove_zones(m, idx);
    std::vector<int> new_index(n, -1);
    for (int r = 0, w = 0; r < n; ++r) {
        if (!gone[r]) new_index[r] = w++;
    }
    for (int& b : m.zones.block) b = new_index[b];
    for (int& b : m.gridpoints.block) b = new_index[b];
    for_each_array(m.blocks, [&](auto& v) {
        int w = 0;
        for (int r = 0; r < n; ++r) {
            if (!gone[r]) {
                if (w != r) v[w] = std::move(v[r]);
                ++w;
            }
        }
        v.resize(w);
    });
    // The joints between the blocks that stay keep their state (they used to be found afresh,
    // every joint of the model losing its in-situ load, shear and damage).
    renumber_contacts(m, &new_index, nullptr);
    m.geometry_changed = true;
}

void update_masses(Model& m) {
    BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        const int mat = s.material[b];
        const double rho = (mat > 0 && mat < static_cast<int>(m.materials.size())) ? m.materials[mat].density : 0.0;
        s.mass[b] = rho * s.volume[b];
        s.inertia_body[b] = rho * s.inertia_unit[b];
        s.inertial_mass[b] = s.mass[b];
        s.inertial_moment[b] = 0;
    }
    m.geometry_changed = true;
}

namespace {

// out[i] = c + r body[i] for i < n, with Eigen's bits for that expression (c_k plus the row's
// products summed as a0 + (a1 + a2)), four vertices at a time: their twelve coordinates in three
// vectors, each output lane given its vertex's coordinates and its row of r by shuffles.
[[gnu::always_inline]] inline void place_vertices(const Mat3& r, const Vec3& c, const Vec3* body, int n, Vec3* out) {
    using simd::V4;
    static_assert(sizeof(Vec3) == 3 * sizeof(double), "vertices packed as x y z");
    const double* in = body->data();
    double* to = out->data();
    int i = 0;
    if (n >= 4) {
        // Lane p of output vector q is coordinate (4q + p) % 3 of vertex (4q + p) / 3.
        auto row = [&](int k0, int k1, int k2, int k3, int col) ODEC_INLINE { return V4{r(k0, col), r(k1, col), r(k2, col), r(k3, col)}; };
        const V4 ra0 = row(0, 1, 2, 0, 0), rb0 = row(0, 1, 2, 0, 1), rc0 = row(0, 1, 2, 0, 2), c0 = V4{c[0], c[1], c[2], c[0]};
        const V4 ra1 = row(1, 2, 0, 1, 0), rb1 = row(1, 2, 0, 1, 1), rc1 = row(1, 2, 0, 1, 2), c1 = V4{c[1], c[2], c[0], c[1]};
        const V4 ra2 = row(2, 0, 1, 2, 0), rb2 = row(2, 0, 1, 2, 1), rc2 = row(2, 0, 1, 2, 2), c2 = V4{c[2], c[0], c[1], c[2]};
        for (; i + 4 <= n; i += 4) {
            const V4 p0 = simd::load4(in + 3 * i), p1 = simd::load4(in + 3 * i + 4), p2 = simd::load4(in + 3 * i + 8);
            // p0 = x0 y0 z0 x1, p1 = y1 z1 x2 y2, p2 = z2 x3 y3 z3.
            const V4 x0 = simd::shuffle<0, 0, 0, 3>(p0, p0), y0 = simd::shuffle<1, 1, 1, 4>(p0, p1),
                     z0 = simd::shuffle<2, 2, 2, 5>(p0, p1);
            const V4 x1 = simd::shuffle<3, 3, 6, 6>(p0, p1), y1 = simd::shuffle<0, 0, 3, 3>(p1, p1),
                     z1 = simd::shuffle<1, 1, 4, 4>(p1, p2);
            const V4 x2 = simd::shuffle<2, 5, 5, 5>(p1, p2), y2 = simd::shuffle<3, 6, 6, 6>(p1, p2),
                     z2 = simd::shuffle<0, 3, 3, 3>(p2, p2);
            simd::store4(to + 3 * i, c0 + simd::sum3(ra0 * x0, rb0 * y0, rc0 * z0));
            simd::store4(to + 3 * i + 4, c1 + simd::sum3(ra1 * x1, rb1 * y1, rc1 * z1));
            simd::store4(to + 3 * i + 8, c2 + simd::sum3(ra2 * x2, rb2 * y2, rc2 * z2));
        }
    }
    for (; i < n; ++i) out[i] = c + r * body[i];
}

// Blocks [b0, b1): their rotation matrices (Eigen's toRotationMatrix, four at a time where
// four blocks follow).
// (The vector kernels read four blocks' orientations as sixteen doubles in a row.)
static_assert(sizeof(Quat) == 4 * sizeof(double), "quaternions packed as x y z w");

ODEC_SIMD_CLONES
void place_rotations(BlockSet& s, int b0, int b1) {
    using simd::V4;
    int b = b0;
    for (; b + 4 <= b1; b += 4) {
        const simd::Quat4 q = simd::load_quats4(s.orientation[b].coeffs().data());
        const V4 x = q.x, y = q.y, z = q.z, w = q.w;
        const V4 two = simd::splat(2.0), one = simd::splat(1.0);
        const V4 tx = two * x, ty = two * y, tz = two * z;
        const V4 twx = tx * w, twy = ty * w, twz = tz * w;
        const V4 txx = tx * x, txy = ty * x, txz = tz * x;
        const V4 tyy = ty * y, tyz = tz * y, tzz = tz * z;
        // Column-major, as Eigen keeps a matrix: (row, column) at row + 3 column.
        const V4 r[9] = {one - (tyy + tzz), txy + twz, txz - twy, txy - twz, one - (txx + tzz),
                         tyz + twx, txz + twy, tyz - twx, one - (txx + tyy)};
        for (int l = 0; l < 4; ++l) {
            for (int i = 0; i < 9; ++i) s.rotation[b + l].data()[i] = r[i][l];
        }
    }
    for (; b < b1; ++b) s.rotation[b] = s.orientation[b].toRotationMatrix();
}

// The world vertices of blocks [b0, b1) by their rotation matrices; a deformable block's are its
// gridpoints' (refresh_deformable_vertices).
ODEC_SIMD_CLONES
void place_rigid_vertices(BlockSet& s, int b0, int b1) {
    for (int b = b0; b < b1; ++b) {
        if (s.flags[b] & kDeformable) continue;
        const std::vector<Vec3>& body = s.shape[b].vertices;
        place_vertices(s.rotation[b], s.centroid[b], body.data(), static_cast<int>(body.size()),
                       s.world_vertices.data() + s.vertex_offset[b]);
    }
}

// f(b0, b1) for the blocks in chunks of fixed size, on the threads in a large model.
template <class F>
void each_chunk(int n, F&& f) {
    constexpr int kChunk = 256;
    const int n_chunks = (n + kChunk - 1) / kChunk;
    parallel_for(n_chunks, thread_count(), n >= kParallelMinBlocks,
                 [&](int ch) { f(ch * kChunk, std::min(n, (ch + 1) * kChunk)); });
}

// The blocks' offsets, rotation matrices and deformable corners, and with `vertices` the rigid
// blocks' world vertices.
void place_all(Model& m, bool vertices) {
    BlockSet& s = m.blocks;
    const int n = s.size();
    s.vertex_offset.resize(n + 1);
    int total = 0;
    for (int b = 0; b < n; ++b) {
        s.vertex_offset[b] = total;
        total += s.shape[b].n_vertices();
    }
    s.vertex_offset[n] = total;
    s.world_vertices.resize(total);
    s.rotation.resize(n);
    each_chunk(n, [&](int b0, int b1) {
        place_rotations(s, b0, b1);
        if (vertices) place_rigid_vertices(s, b0, b1);
    });
    refresh_deformable_vertices(m);
    s.vertices_behind = !vertices;
}

} // namespace

void refresh_world_vertices(Model& m) { place_all(m, true); }

void refresh_block_rotations(Model& m) { place_all(m, false); }

void catch_up_world_vertices(Model& m) {
    BlockSet& s = m.blocks;
    if (!s.vertices_behind) return;
    const int n = s.size();
    if (static_cast<int>(s.vertex_offset.size()) != n + 1 || static_cast<int>(s.rotation.size()) != n ||
        s.vertex_offset[n] != static_cast<int>(s.world_vertices.size())) {
        refresh_world_vertices(m); // (the blocks changed since: all of it again)
        return;
    }
    s.vertices_behind = false;
    each_chunk(n, [&](int b0, int b1) { place_rigid_vertices(s, b0, b1); });
}

Polyhedron world_shape(const Model& m, int b) {
    Polyhedron p = m.blocks.shape[b];
    if (m.blocks.flags[b] & kDeformable) {
        const auto& corners = m.blocks.corner_gp[b];
        for (size_t v = 0; v < corners.size(); ++v) p.vertices[v] = m.gridpoints.pos[corners[v]];
        return p;
    }
    const Mat3 r = m.blocks.orientation[b].toRotationMatrix();
    for (Vec3& v : p.vertices) v = m.blocks.centroid[b] + r * v;
    return p;
}

Vec3 velocity_at_t(const Model& m, int b) {
    if (m.blocks.flags[b] & kDeformable) {
        // A zoned block moves with its gridpoints: the mean velocity of its corners, as its
        // displacement is the mean of theirs (refresh_deformable_vertices).
        const auto& corners = m.blocks.corner_gp[b];
        Vec3 v = Vec3::Zero();
        for (int g : corners) v += gridpoint_velocity_at_t(m, g);
        return corners.empty() ? v : Vec3(v / static_cast<double>(corners.size()));
    }
    if ((m.blocks.flags[b] & kFixed) && !m.blocks.vel_bc[b]) return Vec3::Zero();
    if (m.blocks.half_kick[b]) return m.blocks.vel[b];
    return m.blocks.vel[b] + 0.5 * m.dt * m.blocks.accel[b];
}

Vec3 spin_at_t(const Model& m, int b) {
    const BlockSet& s = m.blocks;
    if (s.flags[b] & kFixed) return Vec3::Zero(); // a fixed block does not turn
    return s.half_kick[b] ? s.ang_vel[b] : Vec3(s.ang_vel[b] + 0.5 * m.dt * s.ang_accel[b]);
}

Vec3 velocity_at_point(const Model& m, int b, const Vec3& lever) {
    return velocity_at_t(m, b) + spin_at_t(m, b).cross(lever);
}

Vec3 point_displacement(const Model& m, int b, const Vec3& p) {
    const BlockSet& s = m.blocks;
    return s.disp[b] + (s.orientation[b] * p - s.ref_orientation[b] * p);
}

Vec3 rotation_since_reset(const Model& m, int b) {
    const BlockSet& s = m.blocks;
    const Eigen::AngleAxisd turn((s.orientation[b] * s.ref_orientation[b].conjugate()).normalized());
    return turn.angle() * turn.axis();
}

Vec3 euler_xyz(const Mat3& r) {
    // R = Rx(a) Ry(b) Rz(c) has R(0,2) = sin b, R(1,2) = -sin a cos b, R(2,2) = cos a cos b,
    // R(0,1) = -cos b sin c, R(0,0) = cos b cos c.
    const double sb = std::clamp(r(0, 2), -1.0, 1.0);
    const double cb = std::hypot(r(0, 0), r(0, 1));
    if (cb > 1e-12) return Vec3(std::atan2(-r(1, 2), r(2, 2)), std::atan2(sb, cb), std::atan2(-r(0, 1), r(0, 0)));
    // Gimbal lock: only a + c (b = pi/2) or a - c (b = -pi/2) is fixed; with c = 0, R(2,1) = sin a
    // and R(1,1) = cos a.
    return Vec3(std::atan2(r(2, 1), r(1, 1)), sb > 0 ? M_PI / 2 : -M_PI / 2, 0.0);
}

int find_block_at(const Model& m, const Vec3& x) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int b = 0; b < m.blocks.size(); ++b) {
        const Vec3 local = m.blocks.orientation[b].conjugate() * (x - m.blocks.centroid[b]);
        if (contains_point(m.blocks.shape[b], local, 1e-9)) return b;
        // Far points (1e308) overflow the squared distance: compare scaled norms, and take
        // some block even then.
        const double d = (m.blocks.centroid[b] - x).stableNorm();
        if (best < 0 || d < best_d) {
            best_d = d;
            best = b;
        }
    }
    return best;
}

namespace {

// A block's size for the tolerances of FaceCover: the cube root of its volume, or the largest
// extent of its box when the volume is no positive number.
double cover_size(double volume, const Vec3& lo, const Vec3& hi) {
    const double c = std::cbrt(volume);
    if (std::isfinite(c) && c > 0) return c;
    const double e = (hi - lo).maxCoeff();
    return std::isfinite(e) && e > 0 ? e : 0.0;
}

} // namespace

FaceCover::FaceCover(const Model& m) : m_(m) {
    const BlockSet& s = m.blocks;
    const int nb = s.size();
    shape_.resize(nb);
    lo_.assign(nb, Vec3::Zero());
    hi_.assign(nb, Vec3::Zero());
    std::vector<int> live;
    std::vector<double> extent;
    Vec3 glo = Vec3::Constant(std::numeric_limits<double>::infinity()), ghi = -glo;
    for (int b = 0; b < nb; ++b) {
        if (s.flags[b] & kExcavated) continue;
        shape_[b] = world_shape(m, b);
        if (shape_[b].vertices.empty()) continue;
        Vec3 lo = shape_[b].vertices[0], hi = lo;
        for (const Vec3& v : shape_[b].vertices) {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
        const double tol = 1e-3 * cover_size(s.volume[b], lo, hi);
        lo -= Vec3::Constant(tol);
        hi += Vec3::Constant(tol);
        if (!lo.allFinite() || !hi.allFinite()) continue;
        lo_[b] = lo;
        hi_[b] = hi;
        live.push_back(b);
        extent.push_back((hi - lo).maxCoeff());
        glo = glo.cwiseMin(lo);
        ghi = ghi.cwiseMax(hi);
    }
    if (live.empty()) return;
    // Cells of the median block's size, fewer than about 8 per block in all.
    std::nth_element(extent.begin(), extent.begin() + extent.size() / 2, extent.end());
    const Vec3 span = ghi - glo;
    cell_ = std::max({extent[extent.size() / 2], 1e-9 * span.maxCoeff(), std::numeric_limits<double>::min()});
    const double budget = 8.0 * static_cast<double>(live.size()) + 64;
    auto cells = [&](double c) {
        double n = 1;
        for (int k = 0; k < 3; ++k) n *= std::max(1.0, std::ceil(span[k] / c));
        return n;
    };
    while (!(cells(cell_) <= budget)) cell_ *= 2;
    nx_ = static_cast<int>(std::max(1.0, std::ceil(span.x() / cell_)));
    ny_ = static_cast<int>(std::max(1.0, std::ceil(span.y() / cell_)));
    nz_ = static_cast<int>(std::max(1.0, std::ceil(span.z() / cell_)));
    origin_ = glo;
    // Each block in every cell its box meets (counting sort: blocks in index order per cell).
    auto range = [&](int b, int lo3[3], int hi3[3]) {
        const int n[3] = {nx_, ny_, nz_};
        for (int k = 0; k < 3; ++k) {
            lo3[k] = std::clamp(static_cast<int>(std::floor((lo_[b][k] - origin_[k]) / cell_)), 0, n[k] - 1);
            hi3[k] = std::clamp(static_cast<int>(std::floor((hi_[b][k] - origin_[k]) / cell_)), 0, n[k] - 1);
        }
    };
    const size_t n_cells = static_cast<size_t>(nx_) * ny_ * nz_;
    cell_offset_.assign(n_cells + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<int> fill;
        if (pass == 1) {
            for (size_t c = 0; c < n_cells; ++c) cell_offset_[c + 1] += cell_offset_[c];
            cell_block_.resize(cell_offset_[n_cells]);
            fill.assign(cell_offset_.begin(), cell_offset_.end() - 1);
        }
        for (int b : live) {
            int lo3[3], hi3[3];
            range(b, lo3, hi3);
            for (int i = lo3[0]; i <= hi3[0]; ++i) {
                for (int j = lo3[1]; j <= hi3[1]; ++j) {
                    for (int k = lo3[2]; k <= hi3[2]; ++k) {
                        const size_t c = (static_cast<size_t>(k) * ny_ + j) * nx_ + i;
                        if (pass == 0) ++cell_offset_[c + 1];
                        else cell_block_[fill[c]++] = b;
                    }
                }
            }
        }
    }
}

int FaceCover::cell_index(const Vec3& x) const {
    const int n[3] = {nx_, ny_, nz_};
    int ijk[3];
    for (int k = 0; k < 3; ++k) {
        const double f = std::floor((x[k] - origin_[k]) / cell_);
        if (!(f >= 0 && f < n[k])) return -1;
        ijk[k] = static_cast<int>(f);
    }
    return (ijk[2] * ny_ + ijk[1]) * nx_ + ijk[0];
}

bool FaceCover::covered(int block, const Vec3& x, const Vec3& n) const {
    if (nx_ == 0) return false;
    const BlockSet& s = m_.blocks;
    const double size = std::max(1e-3, cover_size(s.volume[block], lo_[block], hi_[block]));
    const Vec3 probe = x + n * (1e-6 * size);
    const int c = cell_index(probe);
    if (c < 0) return false;
    for (int k = cell_offset_[c]; k < cell_offset_[c + 1]; ++k) {
        const int o = cell_block_[k];
        if (o == block) continue;
        if ((probe.array() < lo_[o].array()).any() || (probe.array() > hi_[o].array()).any()) continue;
        const double tol = 1e-3 * cover_size(s.volume[o], lo_[o], hi_[o]);
        if (contains_point(shape_[o], probe, tol)) return true;
    }
    return false;
}

} // namespace odec
