// FISH benchmark: a function walking every contact of a 100,000-contact model summing their
// normal forces (target: under 50 ms), and a 1,000,000-iteration arithmetic loop (target:
// under 0.2 s). Prints each time and the result. Usage: bench_fish [n_contacts]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "engine/model.h"
#include "fish/runtime.h"
#include "lang/interpreter.h"

using namespace odec;

int main(int argc, char** argv) {
    const int n = argc > 1 ? std::atoi(argv[1]) : 100000;
    Model m;
    std::ostringstream out, err;
    Interpreter in(m, command_table(), out, err);
    in.quiet = true;
    if (!in.run_text("bench", "poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nprop mat=1 dens=2000", false)) {
        std::cerr << err.str();
        return 1;
    }
    // n contacts of 4 sub-contacts each, as detection would leave them.
    ContactSet& c = m.contacts;
    c.clear();
    c.sub_offset.clear();
    for (int k = 0; k < n; ++k) {
        c.id.push_back(k + 1);
        c.block_a.push_back(0);
        c.block_b.push_back(1);
        c.normal_code.push_back(odec::encode_normal(Eigen::Vector3d::UnitZ()));
        c.gap.push_back(0);
        c.joint.push_back(odec::ContactSet::joint_word(1, 1, false));
        c.sub_offset.push_back(4 * k);
        for (int s = 0; s < 4; ++s) {
            c.push_key(s);
            c.sub_area.push_back(0.25);
            c.sub_point.push_back(odec::TaggedPointCode{});
            c.sub_un.push_back(0);
            c.sub_us.push_back(Eigen::Vector2d::Zero());
            c.sub_ss.push_back(Eigen::Vector2d::Zero());
        }
    }
    c.sub_offset.push_back(4 * n);
    c.detected = true;
    m.geometry_changed = false;
    const char* defs =
        "def sum_forces\n"
        "  local ci = contact_head\n"
        "  local total = 0.0\n"
        "  loop while ci # 0\n"
        "    total = total + c_nforce(ci)\n"
        "    ci = c_next(ci)\n"
        "  endloop\n"
        "  sum_forces = total\n"
        "end\n"
        "def arithmetic\n"
        "  local x = 0.0\n"
        "  loop i (1, 1000000)\n"
        "    x = x + i * 0.5 - x / 3.0\n"
        "  endloop\n"
        "  arithmetic = x\n"
        "end\n";
    if (!in.run_text("bench", defs, false)) {
        std::cerr << err.str();
        return 1;
    }
    using Clock = std::chrono::steady_clock;
    for (const char* f : {"sum_forces", "arithmetic"}) {
        double best = 1e30;
        fish::Value v;
        for (int rep = 0; rep < 5; ++rep) {
            const auto t0 = Clock::now();
            v = in.fish().value_for_command(f, SourceLoc{});
            best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
        }
        std::printf("%-12s %9.2f ms (best of 5)  value %s\n", f, best * 1e3, fish::to_text(v).c_str());
    }
    std::printf("contacts: %d, expected sum %.1f N\n", n, n * 1000.0);
    return 0;
}
