// Plot options kept between pictures: `plot set size ... view ... background ... map ...`
// (and later `set plot ...`, which forwards to it).
//
// They belong to a session, not to the model: `new` keeps them, like `set echo`. Until the
// Interpreter holds them itself, plot.cpp keeps one PlotSettings per Interpreter, looked
// up by its address.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Dense>

namespace odec {

class Interpreter;

struct PlotSettings {
    int width = 1024, height = 768;          // pixels
    std::string view = "iso";                // iso, x, -x, y, -y, z, -z or eye
    Eigen::Vector3d eye = Eigen::Vector3d::Zero(); // m, when view is "eye"
    bool view_set = false;                   // a stored view wins over a cut's own view
    std::string background = "white";        // white, black or grey
    std::string map = "auto";                // auto (rainbow, or cool-warm for signed), rainbow, coolwarm, viridis, grey
};

// The settings of this session (made with the defaults on first use).
PlotSettings& plot_settings(const Interpreter& interp);
// Drop this session's settings (for an Interpreter that is going away).
void forget_plot_settings(const Interpreter& interp);

} // namespace odec
