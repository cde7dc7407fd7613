// Contact benchmark: a cube of jointed rock, n x n x n unit bricks (a cube cut by three
// orthogonal joint sets), settling under gravity on a fixed base. Prints blocks, contacts,
// sub-contacts, steps per second, sub-contact updates per second and the share of time in
// each cycle stage. Usage: bench_contacts [n ...] [--steps s]   (default n = 10 20 30)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/model.h"

using namespace odec;

namespace {

void run(int n, long steps) {
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
    m.gravity = Vec3(0, 0, -10);
    const int base = add_block(m, make_brick(-1, n + 1, -1, n + 1, -1, 0), 0, -1, 1);
    m.blocks.flags[base] |= kFixed;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) add_block(m, make_brick(x, x + 1, y, y + 1, z, z + 1), 0, -1, 1);

    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const std::string err = prepare_cycle(m);
    if (!err.empty()) {
        std::printf("cannot cycle: %s\n", err.c_str());
        return;
    }
    const double t_detect = std::chrono::duration<double>(Clock::now() - t0).count();
    m.profile = Profile{};
    CycleLimits lim;
    lim.max_steps = steps;
    const auto t1 = Clock::now();
    cycle(m, lim);
    const double t = std::chrono::duration<double>(Clock::now() - t1).count();
    const double total_stage = [&] {
        double s = 0;
        for (double x : m.profile.seconds) s += x;
        return s;
    }();
    std::printf("blocks %d  contacts %d  sub-contacts %d  first detection %.3f s\n", m.blocks.size(), m.contacts.size(),
                m.contacts.n_subs(), t_detect);
    std::printf("  %ld steps in %.3f s: %.1f steps/s, %.3g s/step, %.3g sub-contact updates/s, detections %ld\n", steps,
                t, steps / t, t / steps, static_cast<double>(m.contacts.n_subs()) * steps / t, m.contacts.n_detections);
    std::printf("  stages:");
    for (int s = 0; s < static_cast<int>(Stage::Count); ++s) {
        std::printf(" %s %.1f%%", stage_name(static_cast<Stage>(s)), 100.0 * m.profile.seconds[s] / total_stage);
    }
    std::printf("\n  unbalanced ratio %.3g, largest unbalanced force %.3g N\n", unbalanced_ratio(m),
                max_unbalanced_force(m));
}

} // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    long steps = 200;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) steps = std::atol(argv[++i]);
        else sizes.push_back(std::atoi(argv[i]));
    }
    if (sizes.empty()) sizes = {10, 20, 30};
    for (int n : sizes) run(n, steps);
    return 0;
}
