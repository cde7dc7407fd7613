// The range phrase as the engine sees it: a conjunction of filters on blocks.
// Each filter tests a block's centroid, region, group or id; `not` inverts one.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec {

struct Model;

enum class FilterKind { X, Y, Z, Region, Group, Id, Sphere, Cylinder, PlaneAbove, PlaneBelow, AnyOf };

struct Range;

struct Filter {
    FilterKind kind = FilterKind::X;
    bool negate = false;
    double lo = 0, hi = 0;            // X/Y/Z interval; Id range (inclusive); Region (lo only)
    std::string name;                 // Group
    Eigen::Vector3d a = Eigen::Vector3d::Zero(); // sphere centre; cylinder end 1; plane origin
    Eigen::Vector3d b = Eigen::Vector3d::Zero(); // cylinder end 2; plane upward normal
    double radius = 0;                // sphere/cylinder
    std::vector<Range> any_of;        // AnyOf: passes when one of these ranges holds (named ranges' union)
};

struct Range {
    std::vector<Filter> filters;      // all must hold; empty selects everything
    bool empty() const { return filters.empty(); }
    // True when block `block_index` of m passes every filter.
    bool contains_block(const Model& m, int block_index) const;
    // True when a contact at `point` between blocks a and b passes every filter: location
    // filters test the point; region, group and id filters pass if either block does.
    bool contains_contact(const Model& m, const Eigen::Vector3d& point, int block_a, int block_b) const;
    // True when a point of block b (a gridpoint, a zone centroid, a boundary face) passes:
    // location filters test the point, region, group and id filters the block.
    bool contains_point(const Model& m, const Eigen::Vector3d& point, int block) const;
};

// Indices of the blocks that r selects (excavated blocks are skipped unless asked).
std::vector<int> select_blocks(const Model& m, const Range& r, bool include_excavated = false);

} // namespace odec
