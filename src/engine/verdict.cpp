#include "engine/verdict.h"

#include <algorithm>
#include <cmath>

namespace odec {

namespace {

// The thresholds of a mechanism (verdict.h).
constexpr double kLeast = 1e-5;        // net displacement over the window, times the block's size
constexpr double kSteady = 0.8;        // rate of the window's second half over its first
constexpr double kSameWay = 0.5;       // cosine between the two halves' displacements
constexpr double kAccumulating = 0.25; // rate of the second half over the speed at the end
constexpr double kDriven = 0.5;        // unbalanced force at the window's end over its start

// Where each block is: a rigid block's centroid, a deformable block's mean gridpoint position.
std::vector<Vec3> block_places(const Model& m) {
    const BlockSet& s = m.blocks;
    std::vector<Vec3> where(static_cast<size_t>(s.size()), Vec3::Zero());
    std::vector<int> count(static_cast<size_t>(s.size()), 0);
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        const int b = g.block[i];
        if (b < 0 || b >= s.size()) continue;
        where[b] += g.pos[i];
        ++count[b];
    }
    for (int b = 0; b < s.size(); ++b) {
        if ((s.flags[b] & kDeformable) && count[b] > 0) where[b] /= count[b];
        else where[b] = s.centroid[b];
    }
    return where;
}

// The unbalanced force on each block, N: a rigid block's, or the sum of the magnitudes of its
// gridpoints'.
std::vector<double> block_forces(const Model& m) {
    const BlockSet& s = m.blocks;
    std::vector<double> f(static_cast<size_t>(s.size()), 0.0);
    for (int b = 0; b < s.size(); ++b) {
        if (!(s.flags[b] & kDeformable)) f[b] = s.force[b].stableNorm();
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        const int b = g.block[i];
        if (b >= 0 && b < s.size() && (s.flags[b] & kDeformable)) f[b] += g.force[i].stableNorm();
    }
    return f;
}

bool rigid_free(const BlockSet& s, int b) {
    return !(s.flags[b] & (kFixed | kExcavated | kDeformable)) && s.vel_bc[b] == 0 && s.mass[b] > 0;
}

bool gridpoint_free(const GridpointSet& g, int i) { return g.vel_bc[i] == 0 && g.mass[i] > 0; }

} // namespace

const char* outcome_name(SolveOutcome o) {
    switch (o) {
    case SolveOutcome::Equilibrium: return "equilibrium";
    case SolveOutcome::Mechanism: return "mechanism";
    case SolveOutcome::NotConverged: return "not converged";
    case SolveOutcome::Interrupted: return "interrupted";
    }
    return "";
}

void block_speeds(const Model& m, std::vector<double>& speed, std::vector<char>& free) {
    const BlockSet& s = m.blocks;
    speed.assign(static_cast<size_t>(s.size()), 0.0);
    free.assign(static_cast<size_t>(s.size()), 0);
    for (int b = 0; b < s.size(); ++b) {
        if (!rigid_free(s, b)) continue;
        speed[b] = s.vel[b].stableNorm();
        free[b] = 1;
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        const int b = g.block[i];
        if (b < 0 || b >= s.size() || !(s.flags[b] & kDeformable) || (s.flags[b] & kExcavated)) continue;
        if (!gridpoint_free(g, i)) continue;
        free[b] = 1;
        speed[b] = std::max(speed[b], g.vel[i].stableNorm());
    }
}

void SolveRecorder::begin(const Model& m) { restart(m); }

void SolveRecorder::restart(const Model& m) {
    first_step_ = m.step;
    stride_ = kFirstStride;
    n_blocks_ = m.blocks.size();
    n_gridpoints_ = m.gridpoints.size();
    samples_.clear();
    snapshots_.clear();
    snapshots_.push_back({m.step - first_step_, m.time, block_places(m), block_forces(m)});
}

SolveSample SolveRecorder::sample(const Model& m, long rel) const {
    SolveSample x;
    x.step = rel;
    x.time = m.time;
    x.ratio = unbalanced_ratio(m);
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (!rigid_free(s, b)) continue;
        const double v = s.vel[b].stableNorm();
        const Mat3 r = s.orientation[b].toRotationMatrix();
        const Vec3 w = s.ang_vel[b];
        x.kinetic += 0.5 * s.mass[b] * v * v + 0.5 * w.dot(r * s.inertia_body[b] * r.transpose() * w);
        x.max_speed = std::max(x.max_speed, v);
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (!gridpoint_free(g, i)) continue;
        const double v = g.vel[i].stableNorm();
        x.kinetic += 0.5 * g.mass[i] * v * v;
        x.max_speed = std::max(x.max_speed, v);
    }
    return x;
}

bool SolveRecorder::same_blocks(const Model& m) const {
    return m.blocks.size() == n_blocks_ && m.gridpoints.size() == n_gridpoints_;
}

void SolveRecorder::observe(const Model& m) {
    if (!same_blocks(m)) {
        restart(m);
        return;
    }
    const long rel = m.step - first_step_;
    if (rel <= 0 || rel % stride_ != 0) return;
    samples_.push_back(sample(m, rel));
    if (rel % (stride_ * kSamplesPerSnapshot) == 0) snapshots_.push_back({rel, m.time, block_places(m), block_forces(m)});
    if (static_cast<int>(samples_.size()) < kSamples) return;
    // Full: keep every other sample (and snapshot), twice as far apart.
    stride_ *= 2;
    const long every = stride_, snap_every = stride_ * kSamplesPerSnapshot;
    samples_.erase(std::remove_if(samples_.begin(), samples_.end(),
                                  [every](const SolveSample& q) { return q.step % every != 0; }),
                   samples_.end());
    snapshots_.erase(std::remove_if(snapshots_.begin(), snapshots_.end(),
                                    [snap_every](const Snapshot& q) { return q.step % snap_every != 0; }),
                     snapshots_.end());
}

void SolveRecorder::finish(const Model& m) {
    if (!same_blocks(m)) {
        restart(m);
        return;
    }
    const long rel = m.step - first_step_;
    if (rel > 0 && (samples_.empty() || samples_.back().step != rel)) samples_.push_back(sample(m, rel));
}

SolveVerdict judge_solve(const SolveRecorder& rec, const Model& m, StopReason reason, const CycleLimits& lim,
                         long steps) {
    SolveVerdict v;
    v.stop = reason;
    v.ratio_limit = lim.ratio;
    v.step_limit = lim.max_steps;
    v.time_limit = lim.max_time;
    v.end_step = m.step;
    v.steps = steps;
    v.ratio = unbalanced_ratio(m);
    if (reason == StopReason::Ratio) {
        v.outcome = SolveOutcome::Equilibrium;
        return v;
    }
    if (reason == StopReason::Interrupted) {
        v.outcome = SolveOutcome::Interrupted;
        return v;
    }
    v.outcome = SolveOutcome::NotConverged;
    const auto& snaps = rec.snapshots();
    const long end_rel = m.step - rec.first_step();
    if (snaps.empty() || end_rel <= 0 || snaps[0].where.size() != static_cast<size_t>(m.blocks.size())) return v;

    // The window: the last fifth of the run, from the snapshot at or before its start, with a
    // snapshot inside it to split it in halves.
    const long target = end_rel - std::max(1L, std::lround(0.2 * static_cast<double>(end_rel)));
    int i0 = 0;
    for (int i = 0; i < static_cast<int>(snaps.size()); ++i) {
        if (snaps[i].step <= target) i0 = i;
    }
    auto interior = [&](int i) { return i < static_cast<int>(snaps.size()) && snaps[i].step < end_rel; };
    if (!interior(i0 + 1) && i0 > 0) --i0;
    int mid = -1;
    const double half = 0.5 * static_cast<double>(snaps[i0].step + end_rel);
    for (int i = i0 + 1; interior(i); ++i) {
        if (mid < 0 || std::abs(snaps[i].step - half) < std::abs(snaps[mid].step - half)) mid = i;
    }
    const long start = snaps[i0].step;
    v.window_steps = end_rel - start;

    // The ratio's trend: least squares of log10(ratio) against the step.
    const auto& samples = rec.samples();
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    const SolveSample* first = nullptr;
    const SolveSample* last = nullptr;
    for (const SolveSample& q : samples) {
        if (q.step < start) continue;
        if (!first) first = &q;
        last = &q;
        if (!(q.ratio > 0) || !std::isfinite(q.ratio)) continue;
        const double x = static_cast<double>(q.step - start), y = std::log10(q.ratio);
        n += 1;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double den = n * sxx - sx * sx;
    if (n >= 4 && den > 0 && mid >= 0) {
        v.trend_known = true;
        v.decades_per_step = (n * sxy - sx * sy) / den;
        const double a = (sy - v.decades_per_step * sx) / n;
        v.ratio_from = std::pow(10.0, a);
        v.ratio_to = std::pow(10.0, a + v.decades_per_step * static_cast<double>(v.window_steps));
        if (lim.ratio > 0 && v.decades_per_step < 0 && v.ratio > lim.ratio) {
            const double more = (std::log10(lim.ratio) - std::log10(v.ratio)) / v.decades_per_step;
            if (more < 1e15) v.steps_to_limit = static_cast<long>(std::ceil(more));
        }
    }
    if (first) {
        v.speed_from = first->max_speed;
        v.kinetic_from = first->kinetic;
        v.speed_to = last->max_speed;
        v.kinetic_to = last->kinetic;
    }
    if (mid < 0) return v;

    // Each free block's motion over the two halves of the window.
    const bool ratio_falling = v.trend_known && v.decades_per_step * static_cast<double>(v.window_steps) < -0.02;
    std::vector<double> speed;
    std::vector<char> free;
    block_speeds(m, speed, free);
    const std::vector<Vec3> now = block_places(m);
    const std::vector<double> force_now = block_forces(m);
    const auto& f0 = snaps[i0].force;
    const auto& p0 = snaps[i0].where;
    const auto& p1 = snaps[mid].where;
    const double h1 = snaps[mid].time - snaps[i0].time, h2 = m.time - snaps[mid].time;
    if (!(h1 > 0) || !(h2 > 0)) return v;
    struct Candidate {
        MovingBlock block;
        double r1, r2, f0, f;
    };
    std::vector<Candidate> candidates;
    double f0_sum = 0, f_sum = 0;
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (!free[b] || !(speed[b] > 0)) continue;
        const Vec3 d1 = p1[b] - p0[b], d2 = now[b] - p1[b];
        const double r1 = d1.stableNorm() / h1, r2 = d2.stableNorm() / h2;
        const double moved = (now[b] - p0[b]).stableNorm();
        const double size = std::cbrt(std::max(s.volume[b], 0.0));
        if (!(moved >= kLeast * size) || !std::isfinite(moved) || !(r1 > 0)) continue;
        // Steady or growing; a rate a little lower is steady only while the ratio does not fall.
        const double growth = r2 / r1;
        const bool steady = growth >= 1 || (growth >= kSteady && !ratio_falling);
        // One way: the two halves' displacements point alike, and add up to about the speed.
        const bool one_way = d1.dot(d2) >= kSameWay * d1.stableNorm() * d2.stableNorm();
        const bool accumulating = r2 >= kAccumulating * speed[b];
        if (!steady || !one_way || !accumulating) continue;
        candidates.push_back({{s.id[b], speed[b], moved, growth}, r1, r2, f0[b], force_now[b]});
        f0_sum += f0[b];
        f_sum += force_now[b];
    }
    // Still driven: a block swinging back toward a place of rest (a slow sway of a whole wall)
    // speeds up too, but the force on it dies away as it nears that place. The blocks together
    // keep at least half their unbalanced force, and so does each block named.
    if (candidates.empty() || !(f_sum >= kDriven * f0_sum)) return v;
    double rate1 = 0, rate2 = 0;
    for (const Candidate& c : candidates) {
        if (!(c.f >= kDriven * c.f0)) continue;
        v.moving.push_back(c.block);
        v.moving_speed = std::max(v.moving_speed, c.block.speed);
        rate1 += c.r1;
        rate2 += c.r2;
    }
    if (!v.moving.empty()) {
        v.outcome = SolveOutcome::Mechanism;
        v.moving_growth = rate1 > 0 ? rate2 / rate1 : 1e30;
    }
    return v;
}

} // namespace odec
