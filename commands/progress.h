// Progress of a long `step` or `solve`: a line at most every few seconds of wall time, with
// the step, the model time, the unbalanced ratio and, when the run has a known end (a
// number of steps or a model time), an estimate of the wall time left. Short runs print
// nothing; --quiet and 'set echo off' silence it.
#pragma once

#include <chrono>
#include <cstdio>
#include <ostream>

#include "engine/cycle.h"
#include "engine/model.h"

namespace odec {

class ProgressReporter {
public:
    using Clock = std::chrono::steady_clock;

    // `interval` seconds of wall time between lines; `target_steps` / `target_time` (> 0)
    // give the end of the run for the estimate of the time left.
    ProgressReporter(std::ostream& out, double interval, long first_step, long target_steps, double first_time,
                     double target_time)
        : out_(out), interval_(interval), first_step_(first_step), target_steps_(target_steps),
          first_time_(first_time), target_time_(target_time), start_(Clock::now()), last_(start_) {}

    // Called every few steps by the cycle.
    void operator()(const Model& m) {
        const Clock::time_point now = Clock::now();
        if (std::chrono::duration<double>(now - last_).count() < interval_) return;
        last_ = now;
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        double done = -1; // fraction of the run done, when its end is known
        if (target_steps_ > 0) done = static_cast<double>(m.step - first_step_) / target_steps_;
        else if (target_time_ > 0) done = (m.time - first_time_) / target_time_;
        char buf[200];
        std::snprintf(buf, sizeof buf, "  ... step %ld  time %.6g s  ratio %.3e", m.step, m.time, unbalanced_ratio(m));
        out_ << buf;
        if (done > 0 && done < 1) {
            std::snprintf(buf, sizeof buf, "  %.0f %% done, about %.0f s left", 100 * done,
                          elapsed * (1 - done) / done);
            out_ << buf;
        } else {
            std::snprintf(buf, sizeof buf, "  %.0f s so far", elapsed);
            out_ << buf;
        }
        out_ << "\n";
        out_.flush();
        ++lines_;
    }
    int lines() const { return lines_; }

private:
    std::ostream& out_;
    double interval_;
    long first_step_, target_steps_;
    double first_time_, target_time_;
    Clock::time_point start_, last_;
    int lines_ = 0;
};

} // namespace odec
