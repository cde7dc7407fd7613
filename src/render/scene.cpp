#include "render/scene.h"

#include <algorithm>
#include <cmath>

namespace odec::render {

namespace {

// Control points, evenly spaced over 0..1, interpolated linearly in RGB.
const std::vector<Rgb>& control_points(ColourMap map) {
    // Blue to red through cyan, green and yellow: the map engineers expect for magnitudes.
    static const std::vector<Rgb> rainbow{{0, 0, 1}, {0, 1, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    // Moreland's diverging map, for signed quantities (stress, opening/closing).
    static const std::vector<Rgb> cool_warm{{0.230, 0.299, 0.754}, {0.552, 0.690, 0.996},
                                            {0.865, 0.865, 0.865}, {0.958, 0.604, 0.481},
                                            {0.706, 0.016, 0.150}};
    static const std::vector<Rgb> viridis{{0.267, 0.005, 0.329}, {0.283, 0.141, 0.458},
                                          {0.254, 0.265, 0.530}, {0.207, 0.372, 0.553},
                                          {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551},
                                          {0.135, 0.659, 0.518}, {0.267, 0.749, 0.441},
                                          {0.478, 0.821, 0.318}, {0.741, 0.873, 0.150},
                                          {0.993, 0.906, 0.144}};
    static const std::vector<Rgb> grey{{0.15, 0.15, 0.15}, {0.95, 0.95, 0.95}};
    switch (map) {
    case ColourMap::CoolWarm: return cool_warm;
    case ColourMap::Viridis: return viridis;
    case ColourMap::Grey: return grey;
    default: return rainbow;
    }
}

} // namespace

Rgb category_colour(int k) {
    static const Rgb palette[] = {{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
                                  {0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                                  {0.890, 0.467, 0.761}, {0.498, 0.498, 0.498}, {0.737, 0.741, 0.133},
                                  {0.090, 0.745, 0.812}, {0.682, 0.780, 0.910}, {1.000, 0.733, 0.471}};
    const int n = static_cast<int>(sizeof palette / sizeof palette[0]);
    return palette[((k % n) + n) % n];
}

Rgb category_colour(const ColourScale& scale, int k) {
    if (k >= 0 && k < static_cast<int>(scale.colours.size())) return scale.colours[k];
    return category_colour(k);
}

Rgb colour_at(ColourMap map, double t) {
    if (map == ColourMap::Categorical) return category_colour(static_cast<int>(std::lround(t)));
    const auto& cp = control_points(map);
    if (!(t > 0)) t = 0; // NaN too
    if (t > 1) t = 1;
    const double x = t * static_cast<double>(cp.size() - 1);
    const int i = std::min(static_cast<int>(x), static_cast<int>(cp.size()) - 2);
    const double f = x - i;
    Rgb c;
    for (int k = 0; k < 3; ++k) c[k] = cp[i][k] * (1 - f) + cp[i + 1][k] * f;
    return c;
}

Rgb scale_colour(const ColourScale& scale, double v) {
    if (scale.map == ColourMap::Categorical) return category_colour(scale, static_cast<int>(std::lround(v)));
    const double span = scale.hi - scale.lo;
    return colour_at(scale.map, span > 0 ? (v - scale.lo) / span : 0.0);
}

} // namespace odec::render
