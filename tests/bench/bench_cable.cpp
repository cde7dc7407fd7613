// Cable benchmark: a slab of zoned rock (2n x n x 1 m) under gravity, crossed by a row of rock
// bolts (every 0.5 m across it, each 1 m long in 10 segments), run with and without the bolts.
// Prints the time per step of each and the cables stage's share, per segment.
// Usage: bench_cable [--edge e] [--n n] [--steps s]   (default 0.25 m, n = 4, 500 steps)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "commands.h"
#include "engine/cable.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "lang/interpreter.h"

using namespace odec;

namespace {

struct Run {
    double seconds_per_step = 0, cable_per_step = 0;
    int zones = 0, cables = 0, nodes = 0;
};

Run run(double edge, int n, long steps, bool bolts) {
    Model m;
    std::ostringstream out, err;
    Interpreter in(m, command_table(), out, err);
    in.quiet = true;
    std::ostringstream s;
    s << "new\npoly brick 0 " << 2 * n << " 0 " << n << " 0 1\n"
      << "prop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
      << "gen edge " << edge << "\n"
      << "bound xvel 0 yvel 0 zvel 0 range z -0.01 0.01\n"
      << "grav 0 0 -10\n";
    if (bolts) {
        s << "prop mat=2 cb_area=5e-4 cb_e=200e9 cb_yield=2e5 cb_kbond=1e8 cb_sbond=2e5 cb_dens=7800\n";
        for (double x = 0.25; x < 2 * n; x += 0.5)
            for (double y = 0.25; y < n; y += 0.5) s << "cable " << x << "," << y << ",0.05 " << x << "," << y << ",0.95 seg 10 prop 2\n";
    }
    if (!in.run_text("bench_cable", s.str(), false)) {
        std::fprintf(stderr, "%s", err.str().c_str());
        std::exit(1);
    }
    in.run_text("bench_cable", "step 10\n", false); // prepared: masses, timestep
    const double before = m.profile.seconds[static_cast<int>(Stage::Cables)];
    const auto t0 = std::chrono::steady_clock::now();
    in.run_text("bench_cable", "step " + std::to_string(steps) + "\n", false);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Run r;
    r.seconds_per_step = wall / static_cast<double>(steps);
    r.cable_per_step = (m.profile.seconds[static_cast<int>(Stage::Cables)] - before) / static_cast<double>(steps);
    r.zones = m.zones.size();
    r.cables = m.cables.size();
    r.nodes = m.cables.n_nodes();
    return r;
}

} // namespace

int main(int argc, char** argv) {
    double edge = 0.25;
    int n = 4;
    long steps = 500;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--edge")) edge = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--n")) n = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--steps")) steps = std::atol(argv[i + 1]);
    }
    set_thread_count(1);
    const Run bare = run(edge, n, steps, false);
    const Run bolted = run(edge, n, steps, true);
    const int segments = bolted.nodes - bolted.cables;
    std::printf("slab %d x %d x 1 m, edge %g m: %d zones; %d cables, %d nodes, %d segments; %ld steps, one thread\n", 2 * n,
                n, edge, bolted.zones, bolted.cables, bolted.nodes, segments, steps);
    std::printf("  without cables %.3g ms/step, with %.3g ms/step\n", 1e3 * bare.seconds_per_step, 1e3 * bolted.seconds_per_step);
    std::printf("  cables stage %.3g ms/step = %.3g us per segment per step, %.1f %% of the step\n", 1e3 * bolted.cable_per_step,
                1e6 * bolted.cable_per_step / std::max(1, segments), 100 * bolted.cable_per_step / bolted.seconds_per_step);
    return 0;
}
