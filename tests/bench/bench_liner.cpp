// Liner benchmark: the cost per step of a liner (liner.h). A deformable slab of 2n x n x 1 m,
// zoned by 'gen edge e', held at its base, with a liner laid on its top face (two triangles per
// square of the top's zone faces) and weighed down by gravity. Steps are run without the liner
// and then with it; prints the zones, the liner's elements and nodes, the seconds per step of
// each run, the time of the liners stage per step and per element, and its share of the step.
// One thread.
// Usage: bench_liner [--edge e] [--n n] [--steps s]   (defaults 0.25, 4, 500)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "commands.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "lang/interpreter.h"

using namespace odec;

namespace {

struct Run {
    double seconds_per_step = 0, liner_per_step = 0;
    int zones = 0, elements = 0, nodes = 0;
};

Run run(double edge, int n, long steps, bool liner) {
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
    if (liner) {
        s << "prop mat=2 li_e=30e9 li_nu=0.2 li_thick=0.2 li_dens=2500 li_kn=1e10 li_ks=1e10 li_ncut=1e6 li_scoh=2e6 "
             "li_sfric=35\n"
          << "liner range z 0.99 1.01 prop 2\n";
    }
    if (!in.run_text("bench_liner", s.str(), false)) {
        std::fprintf(stderr, "%s", err.str().c_str());
        std::exit(1);
    }
    in.run_text("bench_liner", "step 10\n", false); // prepared: masses, timestep, stiffness
    const double before = m.profile.seconds[static_cast<int>(Stage::Liners)];
    const auto t0 = std::chrono::steady_clock::now();
    in.run_text("bench_liner", "step " + std::to_string(steps) + "\n", false);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Run r;
    r.seconds_per_step = wall / static_cast<double>(steps);
    r.liner_per_step = (m.profile.seconds[static_cast<int>(Stage::Liners)] - before) / static_cast<double>(steps);
    r.zones = m.zones.size();
    r.elements = m.liners.n_elements();
    r.nodes = m.liners.n_nodes();
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
    const Run lined = run(edge, n, steps, true);
    std::printf("slab %d x %d x 1 m, edge %g m: %d zones; liner %d elements, %d nodes; %ld steps, one thread\n", 2 * n, n,
                edge, lined.zones, lined.elements, lined.nodes, steps);
    std::printf("  without liner %.3g ms/step, with %.3g ms/step\n", 1e3 * bare.seconds_per_step,
                1e3 * lined.seconds_per_step);
    std::printf("  liners stage %.3g ms/step = %.3g us per element per step, %.1f %% of the step\n",
                1e3 * lined.liner_per_step, 1e6 * lined.liner_per_step / lined.elements,
                100 * lined.liner_per_step / lined.seconds_per_step);
    return 0;
}
