#include "verdict_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace odec {

namespace {

// A figure to `digits` significant digits: plainly between 1e-3 and 1e5 ("0.12", "26",
// "100"), else with an exponent ("3.1e-05").
std::string fig(double x, int digits = 2) {
    char buf[48];
    const double a = std::abs(x);
    if (a >= 1e-3 && a < 1e5) {
        const int decimals = std::max(0, digits - 1 - static_cast<int>(std::floor(std::log10(a))));
        std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
        return buf;
    }
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    return buf;
}

// "%.*g" of a number: ratios, limits ("3.1e-05", "0.2").
std::string g(double x, int digits) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    return buf;
}

// A count of steps rounded to two significant digits, as a whole number ("7000", "1.2e+06").
std::string about_steps(double n) {
    if (!(n < 1e7)) return fig(n);
    if (n < 100) return std::to_string(static_cast<long>(std::ceil(n)));
    const double p = std::pow(10.0, std::floor(std::log10(n)) - 1);
    return std::to_string(static_cast<long>(std::round(n / p) * p));
}

std::string plural(long n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); }

// "fell from A to B", "rose from A to B" or "stayed near A" (changes under 12 % are noise),
// each figure written by `text`.
template <class Text>
std::string change(double from, double to, Text text) {
    if (!(from > 0) || !(to > 0)) return "was " + text(to);
    const double r = to / from;
    if (r < 1 / 1.12) return "fell from " + text(from) + " to " + text(to);
    if (r > 1.12) return "rose from " + text(from) + " to " + text(to);
    return "stayed near " + text(to);
}

} // namespace

std::string id_list(std::vector<int> ids, int most) {
    std::sort(ids.begin(), ids.end());
    std::string s;
    int runs = 0;
    for (size_t i = 0; i < ids.size();) {
        size_t j = i;
        while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
        if (runs == most) {
            s += ", ...";
            break;
        }
        if (runs) s += ", ";
        s += std::to_string(ids[i]);
        if (j == i + 1) s += ", " + std::to_string(ids[j]);
        else if (j > i) s += "-" + std::to_string(ids[j]);
        ++runs;
        i = j + 1;
    }
    return s;
}

std::string mechanism_text(const SolveVerdict& v) {
    if (v.moving.empty()) return "";
    std::vector<int> ids;
    double moved = 0;
    for (const MovingBlock& b : v.moving) {
        ids.push_back(b.id);
        moved = std::max(moved, b.moved);
    }
    const long n = static_cast<long>(ids.size());
    return plural(n, "block", "blocks") + " (" + (n == 1 ? "id " : "ids ") + id_list(ids) +
           ") still moving at up to " + fig(v.moving_speed) + " m/s, " +
           (v.moving_growth >= 1.05 ? "speeding up" : v.moving_growth >= 0.95 ? "steady" : "nearly steady") + " over the last " +
           plural(v.window_steps, "step", "steps") + " (moved " + (n == 1 ? "" : "up to ") + fig(moved) +
           " m in them)";
}

std::string verdict_text(const SolveVerdict& v) {
    switch (v.stop) {
    case StopReason::Ratio:
        return "equilibrium, ratio " + g(v.ratio, 6) + " < " + g(v.ratio_limit, 6) + " after " +
               plural(v.steps, "step", "steps");
    case StopReason::Interrupted: return "interrupted after " + plural(v.steps, "step", "steps");
    case StopReason::Time:
        return "reached the time limit, ratio " + g(v.ratio, 6) + " after " + plural(v.steps, "step", "steps");
    default: break;
    }
    if (v.outcome == SolveOutcome::Mechanism) {
        return "mechanism at the step limit (" + plural(v.steps, "step", "steps") + "): " + mechanism_text(v) +
               "; ratio " + g(v.ratio, 3);
    }
    std::string s = "not converged within the step limit (" + plural(v.steps, "step", "steps") + "): ratio " + g(v.ratio, 3);
    if (!v.trend_known) return s + "; too few steps to judge its trend";
    const double decades = v.decades_per_step * static_cast<double>(v.window_steps);
    s += "; over the last " + plural(v.window_steps, "step", "steps") + " the ratio " +
         change(v.ratio_from, v.ratio_to, [](double x) { return g(x, 2); });
    if (decades < -0.05) {
        s += ", about a decade every " + about_steps(-1 / v.decades_per_step) + " steps";
        if (v.steps_to_limit >= 0) {
            s += ": at this rate " + g(v.ratio_limit, 3) + " in about " + about_steps(static_cast<double>(v.steps_to_limit)) +
                 " more steps";
        }
    } else if (v.ratio_limit > 0) {
        s += ", no trend toward " + g(v.ratio_limit, 3);
    }
    s += "; the largest speed " + change(v.speed_from, v.speed_to, [](double x) { return fig(x); }) + " m/s";
    if (v.speed_to < v.speed_from / 1.12) s += " (settling; no block moves steadily)";
    else if (v.speed_to > v.speed_from * 1.12) s += " (speeding up, but no block moves as a mechanism yet)";
    else s += " (no block moves steadily)";
    return s;
}

std::string criteria_text(const SolveVerdict& v) {
    return (v.ratio_limit > 0 ? "ratio limit " + g(v.ratio_limit, 6) : std::string("no ratio limit")) + ", " +
           (v.step_limit > 0 ? "step limit " + std::to_string(v.step_limit) : std::string("no step limit")) + ", " +
           (v.time_limit > 0 ? "time limit " + g(v.time_limit, 6) + " s" : std::string("no time limit"));
}

} // namespace odec
