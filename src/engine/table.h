// Piecewise-linear tables (`table n x1 y1 x2 y2 ...`) for load and velocity histories.
#pragma once

#include <map>
#include <utility>
#include <vector>

namespace odec {

struct Table {
    std::vector<std::pair<double, double>> points; // (n_points) x increasing
    // Value at x: linear between points, held constant beyond the ends; 0 when empty.
    double at(double x) const;
    // Largest |y| (what a load or velocity it scales can reach); 0 when empty.
    double max_abs() const;
};

struct TableSet {
    std::map<int, Table> tables; // by table number
    const Table* find(int n) const {
        auto it = tables.find(n);
        return it == tables.end() ? nullptr : &it->second;
    }
};

} // namespace odec
