#include "mesh/tet_improve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "mesh/tet_mesh.h"

namespace odec {

namespace {

using Tet = std::array<int, 4>;

constexpr int kMaxRing = 10;   // edges with more tetrahedra around them are left alone
constexpr int kRounds = 8;     // passes over the bad tetrahedra of a solid
constexpr double kGain = 1e-6; // least rise of the worst quality that counts as one

// Radius ratio of a tetrahedron with these corners in this order, or -1 when its volume is
// not positive (flat, or inverted).
double oriented_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double six_v = (b - a).dot((c - a).cross(d - a));
    if (!(six_v > 0)) return -1;
    return radius_ratio(a, b, c, d);
}

// Whether (p0, p1, p2, p3), a permutation of the corners of t, is an even one: the same
// orientation as t.
bool even(const Tet& t, int p0, int p1, int p2, int p3) {
    const int p[4] = {p0, p1, p2, p3};
    int at[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) {
        for (int k = 0; k < 4; ++k) {
            if (t[k] == p[i]) at[i] = k;
        }
    }
    int inversions = 0;
    for (int i = 0; i < 4; ++i) {
        for (int j = i + 1; j < 4; ++j) inversions += at[i] > at[j];
    }
    return inversions % 2 == 0;
}

bool has(const Tet& t, int n) { return t[0] == n || t[1] == n || t[2] == n || t[3] == n; }

// A change of the mesh: tetrahedra out, tetrahedra in, and the worst quality before and after.
struct Change {
    std::vector<int> remove;
    std::vector<Tet> add;
    double before = -2, after = -2;
    int new_node = -1;  // a split: the node added (at new_position)
    Vec3 new_position = Vec3::Zero();
    bool better_than(const Change& o) const { return after - before > o.after - o.before; }
};

class Improver {
public:
    Improver(std::vector<Vec3>& x, double target, TetImproveStats& stats) : x_(x), target_(target), stats_(stats) {}

    void run(std::vector<Tet>& tets) {
        double worst = 1;
        for (const Tet& t : tets) worst = std::min(worst, quality(t));
        if (worst >= target_) return;
        t_.clear();
        q_.clear();
        dead_.clear();
        if (star_.size() < x_.size()) {
            star_.resize(x_.size());
            movable_.resize(x_.size(), -1);
        }
        for (const Tet& t : tets) add(t);
        for (int round = 0; round < kRounds; ++round) {
            std::vector<std::pair<double, int>> bad;
            for (int i = 0; i < static_cast<int>(t_.size()); ++i) {
                if (!dead_[i] && q_[i] < target_) bad.emplace_back(q_[i], i);
            }
            if (bad.empty()) break;
            std::sort(bad.begin(), bad.end());
            bool changed = false;
            for (const auto& [q0, i] : bad) {
                if (dead_[i] || q_[i] >= target_) continue;
                if (flip(i) || move_corners(i) || split(i)) changed = true;
            }
            if (!changed) break;
        }
        tets.clear();
        for (size_t i = 0; i < t_.size(); ++i) {
            if (!dead_[i]) tets.push_back(t_[i]);
        }
        // Leave the node tables empty for the next solid.
        for (const Tet& t : t_) {
            for (int n : t) {
                star_[n].clear();
                movable_[n] = -1;
            }
        }
    }

private:
    std::vector<Vec3>& x_;
    const double target_;
    TetImproveStats& stats_;
    std::vector<Tet> t_;
    std::vector<double> q_;
    std::vector<char> dead_;
    std::vector<std::vector<int>> star_;  // by node: the live tetrahedra that have it
    std::vector<signed char> movable_;    // by node: 1 inside the solid, 0 on its surface, -1 not known yet

    double quality(const Tet& t) const { return oriented_quality(x_[t[0]], x_[t[1]], x_[t[2]], x_[t[3]]); }
    // The quality of t with node v at p.
    double quality_with(const Tet& t, int v, const Vec3& p) const {
        auto at = [&](int n) -> const Vec3& { return n == v ? p : x_[n]; };
        return oriented_quality(at(t[0]), at(t[1]), at(t[2]), at(t[3]));
    }

    void add(const Tet& t) {
        const int i = static_cast<int>(t_.size());
        t_.push_back(t);
        q_.push_back(quality(t));
        dead_.push_back(0);
        for (int n : t) star_[n].push_back(i);
    }
    void remove(int i) {
        dead_[i] = 1;
        for (int n : t_[i]) {
            auto& s = star_[n];
            s.erase(std::find(s.begin(), s.end(), i));
        }
    }
    void apply(const Change& c) {
        if (c.new_node >= 0) {
            x_.push_back(c.new_position);
            star_.emplace_back();
            movable_.push_back(1);
        }
        for (int i : c.remove) remove(i);
        for (const Tet& t : c.add) add(t);
    }

    // The live tetrahedron other than `not_this` with face (a, b, c), or -1 (a face on the surface).
    int across(int a, int b, int c, int not_this) const {
        for (int i : star_[a]) {
            if (i != not_this && has(t_[i], b) && has(t_[i], c)) return i;
        }
        return -1;
    }

    // Whether node v is inside the solid: no face around it is on the solid's surface.
    bool movable(int v) {
        if (movable_[v] < 0) {
            movable_[v] = 1;
            for (int i : star_[v]) {
                for (int k = 0; k < 4 && movable_[v]; ++k) {
                    if (t_[i][k] == v) continue;
                    int o[2], m = 0;
                    for (int j = 0; j < 4; ++j) {
                        if (j != k && t_[i][j] != v) o[m++] = t_[i][j];
                    }
                    if (across(v, o[0], o[1], i) < 0) movable_[v] = 0;
                }
            }
        }
        return movable_[v] == 1;
    }

    // The tetrahedra around edge (a, b) in order, with the ring of their other corners: tetrahedron
    // k is (a, b, ring[k], ring[k+1]) in orientation. False for an edge on the surface (an open
    // ring) or with too many tetrahedra around it.
    bool edge_ring(int a, int b, std::vector<int>& tets, std::vector<int>& ring) const {
        std::vector<int> around;
        for (int i : star_[a]) {
            if (has(t_[i], b)) around.push_back(i);
        }
        const int n = static_cast<int>(around.size());
        if (n < 3 || n > kMaxRing) return false;
        std::vector<std::pair<int, int>> cd(n);
        for (int k = 0; k < n; ++k) {
            const Tet& t = t_[around[k]];
            int o[2], m = 0;
            for (int j = 0; j < 4; ++j) {
                if (t[j] != a && t[j] != b) o[m++] = t[j];
            }
            if (!even(t, a, b, o[0], o[1])) std::swap(o[0], o[1]);
            cd[k] = {o[0], o[1]};
        }
        tets.assign(1, around[0]);
        ring.assign(1, cd[0].first);
        std::vector<char> used(n, 0);
        used[0] = 1;
        int next = cd[0].second;
        for (int step = 1; step < n; ++step) {
            int found = -1;
            for (int k = 0; k < n; ++k) {
                if (!used[k] && cd[k].first == next) found = k;
            }
            if (found < 0) return false;
            used[found] = 1;
            tets.push_back(around[found]);
            ring.push_back(next);
            next = cd[found].second;
        }
        return next == ring[0];
    }

    double worst_of(const std::vector<int>& tets) const {
        double w = 1;
        for (int i : tets) w = std::min(w, q_[i]);
        return w;
    }

    // Face flip: tetrahedron i and its neighbour across the face opposite corner k become three
    // around the edge joining their far corners.
    bool face_flip(int i, int k, Change& c) const {
        const Tet& t = t_[i];
        const int d = t[k];
        int f[3], m = 0;
        for (int j = 0; j < 4; ++j) {
            if (j != k) f[m++] = t[j];
        }
        if (!even(t, f[0], f[1], f[2], d)) std::swap(f[0], f[1]);
        const int o = across(f[0], f[1], f[2], i);
        if (o < 0) return false;
        int e = -1;
        for (int n : t_[o]) {
            if (n != f[0] && n != f[1] && n != f[2]) e = n;
        }
        c = Change();
        c.remove = {i, o};
        c.before = std::min(q_[i], q_[o]);
        c.after = 1;
        for (int j = 0; j < 3; ++j) {
            const Tet nt = {e, d, f[j], f[(j + 1) % 3]};
            c.after = std::min(c.after, quality(nt));
            c.add.push_back(nt);
        }
        return true;
    }

    // Edge removal: the n tetrahedra around edge (a, b) become 2n - 4 (3 into 2, 4 into 4, ...),
    // the triangulation of the ring of their corners with the best worst tetrahedron.
    bool edge_removal(int a, int b, Change& c) const {
        std::vector<int> tets, ring;
        if (!edge_ring(a, b, tets, ring)) return false;
        const int n = static_cast<int>(ring.size());
        // Triangle (i, k, j) of the ring, i < k < j: tetrahedra with b above and a below.
        auto triangle = [&](int i, int k, int j) {
            return std::min(quality({ring[i], ring[k], ring[j], b}), quality({ring[i], ring[j], ring[k], a}));
        };
        double best[kMaxRing][kMaxRing];
        int cut[kMaxRing][kMaxRing];
        for (int len = 2; len < n; ++len) {
            for (int i = 0; i + len < n; ++i) {
                const int j = i + len;
                best[i][j] = -2;
                cut[i][j] = -1;
                for (int k = i + 1; k < j; ++k) {
                    double v = triangle(i, k, j);
                    if (k - i >= 2) v = std::min(v, best[i][k]);
                    if (j - k >= 2) v = std::min(v, best[k][j]);
                    if (v > best[i][j]) {
                        best[i][j] = v;
                        cut[i][j] = k;
                    }
                }
            }
        }
        c = Change();
        c.remove = tets;
        c.before = worst_of(tets);
        c.after = best[0][n - 1];
        std::vector<std::pair<int, int>> todo = {{0, n - 1}};
        while (!todo.empty()) {
            const auto [i, j] = todo.back();
            todo.pop_back();
            const int k = cut[i][j];
            c.add.push_back({ring[i], ring[k], ring[j], b});
            c.add.push_back({ring[i], ring[j], ring[k], a});
            if (k - i >= 2) todo.emplace_back(i, k);
            if (j - k >= 2) todo.emplace_back(k, j);
        }
        return true;
    }

    // The best flip that removes tetrahedron i and raises the worst quality of those it replaces.
    bool flip(int i) {
        Change best, c;
        bool any = false;
        for (int k = 0; k < 4; ++k) {
            if (face_flip(i, k, c) && c.after > c.before + kGain && (!any || c.better_than(best))) {
                best = c;
                any = true;
            }
        }
        static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
        for (const auto& e : edges) {
            if (edge_removal(t_[i][e[0]], t_[i][e[1]], c) && c.after > c.before + kGain &&
                (!any || c.better_than(best))) {
                best = c;
                any = true;
            }
        }
        if (!any) return false;
        apply(best);
        ++stats_.flips;
        return true;
    }

    // Where node v raises the worst of `tets` (which have it) most, starting from `start`: the
    // centroid of its neighbours, then steps up the gradient of the worst tetrahedron.
    Vec3 best_position(const std::vector<Tet>& tets, int v, const Vec3& start, double& worst) const {
        auto worst_at = [&](const Vec3& p, int* which) {
            double w = 2;
            for (size_t k = 0; k < tets.size(); ++k) {
                const double q = quality_with(tets[k], v, p);
                if (q < w) {
                    w = q;
                    if (which) *which = static_cast<int>(k);
                }
            }
            return w;
        };
        Vec3 p = start;
        worst = worst_at(p, nullptr);
        Vec3 centroid = Vec3::Zero();
        double length = 0;
        int count = 0;
        for (const Tet& t : tets) {
            for (int n : t) {
                if (n == v) continue;
                centroid += x_[n];
                length += (x_[n] - start).norm();
                ++count;
            }
        }
        if (count == 0) return p;
        centroid /= count;
        length /= count;
        const double w_centroid = worst_at(centroid, nullptr);
        if (w_centroid > worst) {
            worst = w_centroid;
            p = centroid;
        }
        const double h = 1e-6 * length;
        for (int iter = 0; iter < 30; ++iter) {
            int k = 0;
            worst_at(p, &k);
            Vec3 g;
            for (int d = 0; d < 3; ++d) {
                Vec3 lo = p, hi = p;
                lo[d] -= h;
                hi[d] += h;
                g[d] = (quality_with(tets[k], v, hi) - quality_with(tets[k], v, lo)) / (2 * h);
            }
            if (!(g.norm() > 0)) break;
            g.normalize();
            bool moved = false;
            for (double step = 0.2 * length; step > 1e-4 * length; step *= 0.5) {
                const Vec3 trial = p + step * g;
                const double w = worst_at(trial, nullptr);
                if (w > worst + 1e-9) {
                    worst = w;
                    p = trial;
                    moved = true;
                    break;
                }
            }
            if (!moved) break;
        }
        return p;
    }

    // Moves the corners of tetrahedron i that are inside the solid, where that raises the worst
    // tetrahedron around them.
    bool move_corners(int i) {
        bool any = false;
        const Tet t = t_[i];
        for (int v : t) {
            if (!movable(v)) continue;
            std::vector<Tet> around;
            for (int j : star_[v]) around.push_back(t_[j]);
            const double before = worst_of(star_[v]);
            double after = 0;
            const Vec3 p = best_position(around, v, x_[v], after);
            if (after > before + kGain) {
                x_[v] = p;
                for (int j : star_[v]) q_[j] = quality(t_[j]);
                ++stats_.moves;
                any = true;
            }
        }
        return any;
    }

    // Splits the edge of tetrahedron i that gains most at a new node inside the solid, placed
    // where the tetrahedra around it are best.
    bool split(int i) {
        Change best, c;
        bool any = false;
        static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
        const int m = static_cast<int>(x_.size());
        for (const auto& e : edges) {
            const int a = t_[i][e[0]], b = t_[i][e[1]];
            std::vector<int> tets, ring;
            if (!edge_ring(a, b, tets, ring)) continue;
            c = Change();
            c.remove = tets;
            c.before = worst_of(tets);
            const int n = static_cast<int>(ring.size());
            for (int k = 0; k < n; ++k) {
                c.add.push_back({a, m, ring[k], ring[(k + 1) % n]});
                c.add.push_back({m, b, ring[k], ring[(k + 1) % n]});
            }
            c.new_node = m;
            c.new_position = best_position(c.add, m, 0.5 * (x_[a] + x_[b]), c.after);
            if (c.after > c.before + kGain && (!any || c.better_than(best))) {
                best = c;
                any = true;
            }
        }
        if (!any) return false;
        apply(best);
        ++stats_.splits;
        return true;
    }
};

} // namespace

TetImproveStats improve_tets(std::vector<Vec3>& nodes, std::vector<std::vector<std::array<int, 4>>>& tets,
                             double target) {
    TetImproveStats stats;
    Improver improver(nodes, target, stats);
    for (auto& solid : tets) improver.run(solid);
    return stats;
}

} // namespace odec
