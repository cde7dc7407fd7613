#include "engine/table.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace odec {

double Table::at(double x) const {
    if (points.empty()) return 0;
    if (x <= points.front().first) return points.front().second;
    if (x >= points.back().first) return points.back().second;
    for (std::size_t k = 1; k < points.size(); ++k) {
        const auto& [x1, y1] = points[k];
        if (x <= x1) {
            const auto& [x0, y0] = points[k - 1];
            return x1 > x0 ? y0 + (y1 - y0) * (x - x0) / (x1 - x0) : y1;
        }
    }
    return points.back().second;
}

double Table::max_abs() const {
    double m = 0;
    for (const auto& p : points) m = std::max(m, std::abs(p.second));
    return m;
}

} // namespace odec
