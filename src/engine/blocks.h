// Creating, removing and looking up rigid blocks.
#pragma once

#include <string>
#include <vector>

#include "engine/model.h"

namespace odec {

// Add a rigid block whose vertices are given in world coordinates. Its mass comes from
// its material's density (0 until `prop mat=n dens=...`). Returns the new block's index.
int add_block(Model& m, const Polyhedron& world_shape, int region, int group, int material);

// Why a block of these mass properties and this density cannot be computed with, or "":
// a volume or inertia that underflows to zero or overflows to infinity (sizes far outside
// what doubles can square and cube), or a mass or inertia that overflows with the density.
std::string block_numbers_problem(const MassProperties& mp, double density);

// Replace block b by pieces cut from it, given in world axes relative to the point `origin`
// (usually b's centroid, so that far from the world's origin the cut keeps its digits). The
// first piece keeps b's index and id, the others become new blocks at the end. Each piece is
// stored with its body frame along the world axes and keeps b's attributes, conditions and
// accumulated records; it moves with b's rigid-body motion (its velocity is b's at its own
// centroid). Its loads at the centroid are shared by volume, each piece taking its share at
// its own centroid; a load at another point goes to the piece holding that point, at the
// same material point. Returns the pieces' indices.
std::vector<int> replace_by_pieces(Model& m, int b, const std::vector<Polyhedron>& pieces, const Vec3& origin);

// Remove the blocks with these indices for good (their ids are not reused).
void remove_blocks(Model& m, std::vector<int> block_indices);

// Recompute mass and inertia of every block from its material's density.
void update_masses(Model& m);

// World positions of all block vertices into blocks.world_vertices (and the rotation matrices).
void refresh_world_vertices(Model& m);

// The cycle's form of it: the rotation matrices and the deformable blocks' corners now, the
// rigid blocks' world vertices only when something reads them (BlockSet::vertices_behind):
// catch_up_world_vertices places them, and the cycle catches up before anything outside its
// stages sees the model, so that between commands they are always in step.
void refresh_block_rotations(Model& m);
void catch_up_world_vertices(Model& m);

// World shape of one block.
Polyhedron world_shape(const Model& m, int block_index);

// Whether a face of one block is against another: the point just outside the face at x (outward
// unit normal n) lies in another block that is not excavated, or within a thousandth of that
// block's size of it (a joint under compression overlaps; one barely open still faces its
// partner). 'bound stress' loads only the faces this finds uncovered, rigid or zoned. The
// blocks' shapes as they stand are taken once, at construction, with a grid of their boxes.
class FaceCover {
public:
    explicit FaceCover(const Model& m);
    bool covered(int block, const Vec3& x, const Vec3& n) const;

private:
    const Model& m_;
    std::vector<Polyhedron> shape_;
    std::vector<Vec3> lo_, hi_;
    Vec3 origin_ = Vec3::Zero();
    double cell_ = 1;
    int nx_ = 0, ny_ = 0, nz_ = 0;
    std::vector<int> cell_offset_, cell_block_;
    int cell_index(const Vec3& x) const;
};

// Velocity of a block at the time of its position (the integrator stores it half a step back).
Vec3 velocity_at_t(const Model& m, int block_index);
// Velocity at t of the material point at `lever` (world vector from the centroid).
Vec3 velocity_at_point(const Model& m, int block_index, const Vec3& lever);

// Spin (angular velocity) of a block at the time of its position, rad/s about the world axes.
Vec3 spin_at_t(const Model& m, int block_index);

// Displacement since the last `reset disp` of the material point of a rigid block at body-frame
// offset `body_offset` from its centroid: where it is now less where it was then, exact for any
// rotation.
Vec3 point_displacement(const Model& m, int block_index, const Vec3& body_offset);

// The turn of a rigid block since the last `reset disp`, as a rotation vector: the axis (world
// axes, right-hand rule) times the angle, rad, 0 to pi. Exact for any rotation.
Vec3 rotation_since_reset(const Model& m, int block_index);

// A rotation R (such as a block's turn since the reset) as angles (a, b, c), rad, with
// R = Rx(a) Ry(b) Rz(c): a about x, then b about the turned y, then c about the twice-turned z
// (equally: c about the world z, then b about the world y, then a about the world x). a and c
// in (-pi, pi], b in [-pi/2, pi/2]; where b is +-pi/2 the split between a and c is free, and
// c is taken as 0.
Vec3 euler_xyz(const Mat3& r);

// The block containing point x, or the one whose centroid is nearest; -1 when there are none.
int find_block_at(const Model& m, const Vec3& x);

} // namespace odec
