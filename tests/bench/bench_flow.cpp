// Fluid flow benchmark: a cube of jointed rock, n x n x n m cut by three orthogonal joint sets of
// spacing 1 m into n^3 blocks on a fixed base, settling under gravity with water in its joints (a
// water table at mid height, steady flow, one flow sub-step per step). The same model is run with
// flow off and on; prints blocks, sub-contacts, flow nodes and links, the time per step of each and
// what the flow adds per step and per flow node, and the share of the flow stage.
// With --zoned: the jointed tunnel of examples/tutorial/jointed-tunnel-insitu.dat (zoned blocks,
// 1 m zones), with gravity and a water table 10 m above it, started at rest by 'insitu', run with
// flow off and on: the flow between zoned blocks (gridpoint nodes, faces that follow).
// Usage: bench_flow [n ...] [--steps s] [--zoned]   (default n = 5 10 15, 500 steps)
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "commands.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/flow.h"
#include "engine/jset.h"
#include "engine/model.h"
#include "engine/range.h"
#include "lang/interpreter.h"

using namespace odec;

namespace {

Model build(int n, bool flow) {
    Model m;
    m.materials.resize(2);
    m.materials[1].defined = true;
    m.materials[1].density = 2700;
    m.joint_materials.resize(2);
    JointMaterial& j = m.joint_materials[1];
    j.defined = true;
    j.kn = 1e9;
    j.ks = 1e9;
    j.friction = 35;
    j.azero = 2e-4;
    j.ares = 2e-5;
    m.gravity = Vec3(0, 0, -10);
    const int base = add_block(m, make_brick(-1, n + 1, -1, n + 1, -1, 0), 0, -1, 1);
    m.blocks.flags[base] |= kFixed;
    add_block(m, make_brick(0, n, 0, n, 0, n), 0, -1, 1);
    Range not_base;
    Filter f;
    f.kind = FilterKind::Id;
    f.lo = f.hi = m.blocks.id[base];
    f.negate = true;
    not_base.filters.push_back(f);
    const double sets[3][2] = {{0, 0}, {90, 90}, {90, 0}};
    for (const auto& s : sets) {
        if (n < 2) break;
        JointSetSpec js;
        js.dip = s[0];
        js.dd = s[1];
        js.origin = Vec3(0.5 * n, 0.5 * n, 0.5 * n);
        js.spacing = 1.0;
        js.number = n - 1;
        cut_joint_set(m, js, not_base, 1e-6);
    }
    if (flow) {
        m.flow.configured = true;
        m.flow.on = true;
        m.flow.has_wtable = true;
        m.flow.wtable = 0.5 * n;
    }
    return m;
}

double seconds_per_step(Model& m, long steps) {
    const std::string err = prepare_cycle(m);
    if (!err.empty()) {
        std::printf("cannot cycle: %s\n", err.c_str());
        std::exit(1);
    }
    CycleLimits lim;
    lim.max_steps = 1;
    cycle(m, lim); // the first step sizes the buffers and makes the flow nodes
    m.profile = Profile{};
    lim.max_steps = steps;
    const auto t0 = std::chrono::steady_clock::now();
    const CycleResult r = cycle(m, lim);
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.reason != StopReason::Steps) std::printf("  stopped early: %s\n", r.message.c_str());
    return t / steps;
}

// The zoned jointed tunnel, flow on or off: seconds per step, and the model for its counts.
double zoned_tunnel(Model& m, bool flow, long steps) {
    std::ostringstream out, err;
    Interpreter in(m, command_table(), out, err);
    in.quiet = true;
    const std::string zgrad = "bound stress -5e6 -5e6 -10e6 0 0 0 zgrad 13000 13000 26000 0 0 0 range ";
    std::string s = std::string("new\n") + (flow ? "config flow\n" : "") +
                    "set small\npoly tunnel a (0,0,0) b (0,1,0) radius 3 box 20 ntheta 16 nrad 4\n"
                    "jset dip 60 dd 90 spacing 7 number 6 origin 1.5,0,0.3\njset dip 60 dd 270 spacing 7 number 6 origin -1.4,0,0.2\n"
                    "prop mat=1 dens=2600 k=10e9 g=6e9\nprop jmat=1 jkn=2e10 jks=1e10 jfric=35" +
                    std::string(flow ? " azero=2e-4 ares=2e-5" : "") + "\nchange jmat=1\ngen edge 1\ngrav 0 0 -10\n" +
                    (flow ? "insitu wtable 30\n" : "") +
                    "insitu stress -5e6 -5e6 -10e6 0 0 0 zgrad 13000 13000 26000 0 0 0\n" + zgrad + "x 19.99 20.01\n" + zgrad +
                    "x -20.01 -19.99\n" + zgrad + "z 19.99 20.01\n" + zgrad + "z -20.01 -19.99\n" +
                    "bound yvel 0 range y -0.01 0.01\nbound yvel 0 range y 0.99 1.01\nexcavate range group 'tunnel'\nstep 10\n";
    if (!in.run_text("bench_flow", s, false)) {
        std::fprintf(stderr, "%s", err.str().c_str());
        std::exit(1);
    }
    m.profile = Profile{};
    const auto t0 = std::chrono::steady_clock::now();
    in.run_text("bench_flow", "step " + std::to_string(steps) + "\n", false);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / static_cast<double>(steps);
}

} // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    long steps = 500;
    bool zoned = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atol(argv[++i]);
        else if (!std::strcmp(argv[i], "--zoned")) zoned = true;
        else sizes.push_back(std::atoi(argv[i]));
    }
    if (zoned) {
        Model dry, wet;
        const double t_dry = zoned_tunnel(dry, false, steps);
        const double t_wet = zoned_tunnel(wet, true, steps);
        double total = 0;
        for (double x : wet.profile.seconds) total += x;
        const double flow_share = total > 0 ? wet.profile.seconds[static_cast<int>(Stage::Flow)] / total : 0;
        const FlowSet& f = wet.flow;
        int followers = 0;
        for (int i = 0; i + 1 < static_cast<int>(f.follow_offset.size()); ++i) followers += f.follow_offset[i + 1] > f.follow_offset[i];
        std::printf("zoned jointed tunnel: blocks %d, zones %d, gridpoints %d, sub-contacts %d, flow nodes %d (%d following "
                    "the other face), links %d, nodes made %ld times\n",
                    wet.blocks.size(), wet.zones.size(), wet.gridpoints.size(), wet.contacts.n_subs(), f.n_nodes(), followers,
                    f.n_links(), f.rebuilds);
        std::printf("  %ld steps: %.3g s/step without flow, %.3g s/step with flow (x%.2f); the flow stage %.3g s/step "
                    "(%.1f %% of the cycle), %.3g us per flow node per step\n",
                    steps, t_dry, t_wet, t_wet / t_dry, flow_share * t_wet, 100 * flow_share,
                    1e6 * flow_share * t_wet / std::max(1, f.n_nodes()));
        return 0;
    }
    if (sizes.empty()) sizes = {5, 10, 15};
    for (int n : sizes) {
        Model dry = build(n, false);
        const double t_dry = seconds_per_step(dry, steps);
        Model wet = build(n, true);
        const double t_wet = seconds_per_step(wet, steps);
        double total = 0;
        for (double x : wet.profile.seconds) total += x;
        const double flow_share = total > 0 ? wet.profile.seconds[static_cast<int>(Stage::Flow)] / total : 0;
        const FlowSet& f = wet.flow;
        std::printf("n %d: blocks %d, sub-contacts %d (dry %d), flow nodes %d, links %d, nodes made %ld times\n", n,
                    wet.blocks.size(), wet.contacts.n_subs(), dry.contacts.n_subs(), f.n_nodes(), f.n_links(), f.rebuilds);
        std::printf("  %ld steps: %.3g s/step without flow, %.3g s/step with flow (x%.2f); the flow stage %.3g s/step "
                    "(%.1f %% of the cycle), %.3g us per flow node per step\n",
                    steps, t_dry, t_wet, t_wet / t_dry, flow_share * t_wet, 100 * flow_share,
                    1e6 * flow_share * t_wet / std::max(1, f.n_nodes()));
    }
    return 0;
}
