// Stack benchmark: rigid 1 m cubes settling in columns on a fixed base, in odec and, when it is
// installed, in YADE (its polyhedra: tests/bench/bench_stack_yade.py), at the same fixed
// timestep for the same number of steps. Prints, per stack, the steps per CPU second of each
// code (user + system seconds of the process over the steps alone: odec's contact detection
// and cycling, YADE's O.run), their ratio, odec's share of time per cycle stage, and, to show
// that both settled, the mean height of the cubes' centroids, their kinetic energy and the
// largest speed and spin of a cube.
//
// Layout (the same in both codes). A stack "n x n columns of h" has n * n * h cubes:
//   base     a fixed block, x and y in [-1, n p + 1], z in [-1, 0]
//   column   (i, j), i and j in 0..n-1: x in [i p, i p + 1], y in [j p, j p + 1], pitch
//            p = 1.02 m (0.02 m between neighbouring columns)
//   cube     k in 0..h-1 of a column: z in [z_k, z_k + 1], z_k = g + k (1 + g), g = 0.001 m, so
//            that each cube starts 1 mm above the one below it (the lowest 1 mm above the base)
//            and all of them fall and land.
// The stacks: 100 cubes = 5 x 5 columns of 4, 500 cubes = 10 x 10 columns of 5. Settled (rigid
// cubes, no gaps), the centroids' mean height is h / 2 m: 2 and 2.5 m.
// Materials: density 2700 kg/m^3; joints kn = ks = 1e9 Pa/m, friction 30 degrees, no cohesion
// or tension; local damping 0.8; gravity 10 m/s^2; timestep 2.5e-5 s; 8000 steps (0.2 s). odec
// runs in dynamic mode (real masses, as YADE integrates them) on one thread; YADE runs with -j1.
// The timestep is the one YADE's cubes need to come to rest: at 1e-4 s the 100 cubes land at
// the same height as odec's but keep rocking (spins of about 0.01 rad/s, kinetic energy about
// 0.5 J after 0.2 s and no less 0.4 s later), at 5e-5 s the 100 come to rest but the 500 still
// rock (1.1 J, 0.006 rad/s after 0.2 s). odec's automatic step for these cubes is 3.3e-4 s.
// odec's run, a fraction of a second, is made again and again from the start while YADE runs on
// the other core (`repeat` times at least, 5 unless told): one short run takes whatever a shared
// machine does in its moment (its speed drifts by tens of percent from one minute to the next),
// while YADE's run, minutes long, averages over it; run side by side, both meet the same machine.
// odec's row is then measured as YADE's is: all its runs' steps over all their CPU seconds (its
// times are the mean run's). The median run and the spread are printed beside it (a machine that
// switches between a fast and a slow state puts the median in one of them, where the sum, like
// YADE's, takes both), and the runs must end in the same state, bit for bit.
// A run of both stacks takes YADE about 10 CPU minutes.
// YADE's law is volumetric (normal force kn times the overlap volume, shear force ks times the
// shear displacement); bench_stack_yade.py chooses its moduli so that a full face contact
// between two cubes has the normal and shear stiffness of odec's joint.
//
// Usage: bench_stack [cubes ...] [--steps s] [--dt t] [--repeat k] [--no-yade]
//        (cubes: 100 or 500; default both)
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "engine/blocks.h"
#include "engine/cycle.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "peer_run.h"

using namespace odec;
using odec_bench::process_cpu_seconds;

namespace {

constexpr double kPitch = 1.02;    // m, column spacing
constexpr double kGap = 0.001;     // m, between a cube and the one below
constexpr double kDensity = 2700;  // kg/m^3
constexpr double kStiffness = 1e9; // Pa/m, joint normal and shear stiffness
constexpr double kFriction = 30;   // degrees
constexpr double kDamping = 0.8;   // local damping
constexpr double kGravity = 10;    // m/s^2

struct Stack {
    int n = 0;  // n x n columns
    int h = 0;  // of h cubes
};

struct Figures {
    bool ok = false;
    int cubes = 0;
    int contacts = 0;
    int touching = 0;    // contacts that press
    double cpu = 0;      // s over the steps
    double wall = 0;     // s over the steps
    double mean_z = 0;   // m, the cubes' centroids
    double kinetic = 0;  // J, translation and rotation of the cubes
    double speed = 0;    // m/s, the largest of a cube's centroid
    double spin = 0;     // rad/s, the largest of a cube
    long steps = 0;
};

// (verbose: prints the timestep, the stages' shares and the contact counts.)
Figures run_odec(const Stack& st, long steps, double dt, bool verbose) {
    Figures f;
    Model m;
    m.materials.resize(2);
    m.materials[1].defined = true;
    m.materials[1].density = kDensity;
    m.joint_materials.resize(2);
    JointMaterial& j = m.joint_materials[1];
    j.defined = true;
    j.kn = kStiffness;
    j.ks = kStiffness;
    j.friction = kFriction;
    m.gravity = Vec3(0, 0, -kGravity);
    m.damping.mode = DampingMode::Local;
    m.damping.local = kDamping;
    m.settings.dyn_configured = true; // 'config dyn': real masses and real time
    m.settings.dynamic = true;
    m.settings.dt_fixed = dt;         // 'set dt'
    const double w = st.n * kPitch;
    const int base = add_block(m, make_brick(-1, w + 1, -1, w + 1, -1, 0), 0, -1, 1);
    m.blocks.flags[base] |= kFixed;
    std::vector<int> cubes;
    for (int i = 0; i < st.n; ++i)
        for (int jj = 0; jj < st.n; ++jj)
            for (int k = 0; k < st.h; ++k) {
                const double z0 = kGap + k * (1 + kGap);
                cubes.push_back(add_block(
                    m, make_brick(i * kPitch, i * kPitch + 1, jj * kPitch, jj * kPitch + 1, z0, z0 + 1), 0, -1, 1));
            }
    if (verbose) std::printf("  odec's automatic timestep with real masses: %.3g s\n", real_mass_timestep(m));
    const double c0 = process_cpu_seconds();
    const auto w0 = std::chrono::steady_clock::now();
    const std::string err = prepare_cycle(m);
    if (!err.empty()) {
        std::printf("  odec cannot cycle: %s\n", err.c_str());
        return f;
    }
    m.profile = Profile{};
    CycleLimits lim;
    lim.max_steps = steps;
    const CycleResult r = cycle(m, lim);
    f.cpu = process_cpu_seconds() - c0;
    f.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    if (r.reason != StopReason::Steps) {
        std::printf("  odec stopped after %ld steps: %s\n", r.steps, r.message.c_str());
        return f;
    }
    f.ok = true;
    f.steps = r.steps;
    f.cubes = static_cast<int>(cubes.size());
    f.contacts = m.contacts.size();
    const ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        bool presses = false;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) presses = presses || sub_normal_stress(m, c, k) > 0;
        f.touching += presses ? 1 : 0;
    }
    const BlockSet& s = m.blocks;
    for (int b : cubes) {
        f.mean_z += s.centroid[b].z() / f.cubes;
        const Vec3 spin = s.orientation[b].conjugate() * s.ang_vel[b]; // body frame
        f.kinetic += 0.5 * s.mass[b] * s.vel[b].squaredNorm() + 0.5 * spin.dot(s.inertia_body[b] * spin);
        f.speed = std::max(f.speed, s.vel[b].norm());
        f.spin = std::max(f.spin, s.ang_vel[b].norm());
    }
    if (!verbose) return f;
    double total = 0;
    for (double x : m.profile.seconds) total += x;
    std::printf("  odec stages:");
    for (int k = 0; k < static_cast<int>(Stage::Count); ++k) {
        std::printf(" %s %.1f%%", stage_name(static_cast<Stage>(k)), 100.0 * m.profile.seconds[k] / total);
    }
    std::printf("\n  odec: sub-contacts %d, detections %ld\n", m.contacts.n_subs(), m.contacts.n_detections);
    return f;
}

// YADE's command for the stack.
std::vector<std::string> yade_argv(const std::string& yade, const Stack& st, long steps, double dt) {
    char num[64];
    std::vector<std::string> argv = {yade, "-n", "-j1", "-x", std::string(ODEC_SOURCE_DIR) + "/tests/bench/bench_stack_yade.py"};
    for (double x : {double(st.n), double(st.n), double(st.h), kPitch, kGap, double(steps), dt, kDensity, kStiffness,
                     kStiffness, kFriction, kDamping, kGravity}) {
        std::snprintf(num, sizeof num, "%.17g", x);
        argv.push_back(num);
    }
    return argv;
}

// YADE's figures from its run's output.
Figures yade_figures(const odec_bench::ChildRun& r, double* process_cpu) {
    Figures f;
    *process_cpu = r.cpu;
    const size_t at = r.output.find("RESULT ");
    if (r.status != 0 || at == std::string::npos ||
        std::sscanf(r.output.c_str() + at, "RESULT %d %d %d %ld %lf %lf %lf %lf %lf %lf", &f.cubes, &f.contacts,
                    &f.touching, &f.steps, &f.cpu, &f.wall, &f.mean_z, &f.kinetic, &f.speed, &f.spin) != 10) {
        std::printf("  yade failed (exit status %d):\n%s\n", r.status, r.output.c_str());
        return f;
    }
    // Its warnings without their colours, each printed once with how many times it came.
    std::vector<std::pair<std::string, int>> warnings;
    for (size_t p = r.output.find("WARNING"); p != std::string::npos; p = r.output.find("WARNING", p + 1)) {
        const size_t end = r.output.find('\n', p);
        const std::string line = r.output.substr(p, end == std::string::npos ? std::string::npos : end - p);
        std::string plain;
        for (size_t k = 0; k < line.size(); ++k) {
            if (line[k] == '\033') {
                while (k < line.size() && line[k] != 'm') ++k;
            } else {
                plain += line[k];
            }
        }
        auto it = std::find_if(warnings.begin(), warnings.end(), [&](const auto& w) { return w.first == plain; });
        if (it == warnings.end()) warnings.emplace_back(plain, 1);
        else ++it->second;
    }
    for (const auto& w : warnings) std::printf("  yade warned %d times: %s\n", w.second, w.first.c_str());
    const size_t engines = r.output.find("ENGINES ");
    if (engines != std::string::npos) {
        std::printf("  yade engines: %s\n", r.output.substr(engines + 8, r.output.find('\n', engines) - engines - 8).c_str());
    }
    f.ok = true;
    return f;
}

void print_row(const char* code, const Figures& f) {
    std::printf("  %-5s %4d cubes, %5d contacts (%4d pressing), %ld steps: cpu %7.2f s, wall %7.2f s, %8.1f steps per "
                "cpu s\n",
                code, f.cubes, f.contacts, f.touching, f.steps, f.cpu, f.wall, f.steps / f.cpu);
    std::printf("  %-5s at the end: mean height %.6f m, kinetic energy %.3g J, largest speed %.3g m/s, largest spin "
                "%.3g rad/s\n",
                code, f.mean_z, f.kinetic, f.speed, f.spin);
}

} // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    long steps = 8000;
    double dt = 2.5e-5;
    bool with_yade = true;
    int repeat = 5;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atol(argv[++i]);
        else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--dt") && i + 1 < argc) dt = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--no-yade")) with_yade = false;
        else sizes.push_back(std::atoi(argv[i]));
    }
    if (sizes.empty()) sizes = {100, 500};
    set_thread_count(1);
    const std::string yade = with_yade ? odec_bench::find_program("yade") : "";
    std::printf("odec on %d thread; timestep %g s, %ld steps; cpu = user + system seconds over the steps\n",
                thread_count(), dt, steps);
    if (yade.empty()) std::printf("yade %s: skipped\n", with_yade ? "not installed" : "not asked for");
    for (int cubes : sizes) {
        Stack st;
        if (cubes == 100) st = {5, 4};
        else if (cubes == 500) st = {10, 5};
        else {
            std::printf("%d cubes: no such stack (100 or 500)\n", cubes);
            continue;
        }
        std::printf("stack of %d cubes: %d x %d columns of %d; settled mean height %.1f m\n", cubes, st.n, st.n, st.h,
                    0.5 * st.h);
        std::fflush(stdout);
        // YADE started first (from this one thread), then odec's runs on the other core until it
        // has finished, `repeat` of them at least.
        odec_bench::Spawned child;
        std::atomic<bool> yade_done{yade.empty()};
        odec_bench::ChildRun yade_run;
        std::thread collector;
        if (!yade.empty()) {
            child = odec_bench::spawn_program(yade_argv(yade, st, steps, dt), "", {"OMP_NUM_THREADS=1"});
            collector = std::thread([&] {
                yade_run = odec_bench::collect_program(child);
                yade_done = true;
            });
        }
        std::vector<Figures> runs;
        constexpr size_t kMostRuns = 100000;
        while (runs.size() < kMostRuns && (runs.size() < static_cast<size_t>(repeat) || !yade_done)) {
            runs.push_back(run_odec(st, steps, dt, runs.empty()));
            if (!runs.back().ok) break;
        }
        if (collector.joinable()) collector.join();
        Figures o = runs.back();
        if (o.ok) {
            bool same = true;
            for (const Figures& f : runs) {
                same = same && f.mean_z == o.mean_z && f.kinetic == o.kinetic && f.speed == o.speed && f.spin == o.spin;
            }
            if (!same) std::printf("  odec's runs did not end in the same state: not deterministic\n");
            auto rate = [](const Figures& f) { return f.steps / f.cpu; };
            double cpu = 0, wall = 0;
            for (const Figures& f : runs) {
                cpu += f.cpu;
                wall += f.wall;
            }
            o.cpu = cpu / runs.size();
            o.wall = wall / runs.size();
            std::sort(runs.begin(), runs.end(), [&](const Figures& a, const Figures& b) { return rate(a) < rate(b); });
            std::printf("  odec's row: %zu runs%s, their steps over their cpu seconds (steps per cpu s of one run: least "
                        "%.0f, quartiles %.0f, median %.0f, %.0f, most %.0f)\n",
                        runs.size(), yade.empty() ? "" : ", made while yade ran on the other core", rate(runs.front()),
                        rate(runs[runs.size() / 4]), rate(runs[runs.size() / 2]), rate(runs[(3 * runs.size()) / 4]),
                        rate(runs.back()));
            print_row("odec", o);
        }
        std::fflush(stdout);
        if (yade.empty()) continue;
        double yade_process = 0;
        const Figures y = yade_figures(yade_run, &yade_process);
        if (!y.ok) continue;
        print_row("yade", y);
        std::printf("  yade process in all (start-up and model building too): cpu %.2f s\n", yade_process);
        if (o.ok) std::printf("  odec / yade, steps per cpu s: %.1f\n", (o.steps / o.cpu) / (y.steps / y.cpu));
        std::fflush(stdout);
    }
    return 0;
}
