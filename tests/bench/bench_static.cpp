// Static-solution benchmark: steps and CPU seconds to equilibrium of the project's static
// examples in three ways: dynamic mode (real masses, what odec did before density scaling),
// static mode with local damping (the default) and static mode with adaptive damping ('damp
// auto'). Prints, per model and way: steps, CPU seconds, the timestep, and the answer the
// example is checked on, beside its analytic value.
// Usage: bench_static [--quick] [--auto-only] [model ...]
//        (--auto-only: only static mode with damp auto)
//        (models: kirsch tunnel-stress prandtl footing-slab jointed-tunnel)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "engine/zones.h"
#include "lang/interpreter.h"

using namespace odec;

namespace {

double cpu_seconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

enum class Way { Dynamic, StaticLocal, StaticAuto };
const char* way_name(Way w) {
    return w == Way::Dynamic ? "dynamic (real masses)" : w == Way::StaticLocal ? "static, damp local" : "static, damp auto";
}

// The example's text made to run one way: without pictures, without its own 'damp auto', with
// 'config dyn' after 'new' (dynamic) or 'damp auto' before the first solve or step.
std::string variant(const std::string& text, Way way) {
    std::istringstream in(text);
    std::string line, out;
    bool damped = false;
    while (std::getline(in, line)) {
        std::string word = line.substr(0, line.find_first_of(" \t"));
        if (word == "plot" || word == "damp" || word == "config") continue;
        if (way == Way::StaticAuto && !damped && (word == "solve" || word == "step")) {
            out += "damp auto\n";
            damped = true;
        }
        out += line + "\n";
        if (word == "new" && way == Way::Dynamic) out += "config dyn\n";
    }
    return out;
}

struct Model_ {
    const char* name;
    std::string file;           // under examples/
    const char* quantity;       // what is compared
    double analytic;
    std::function<double(const Model&)> answer;
};

double gp_disp(const Model& m, Vec3 x, int k) { return m.gridpoints.disp[find_gridpoint_near(m, x)][k]; }

} // namespace

int main(int argc, char** argv) {
    bool quick = false, auto_only = false;
    std::vector<std::string> only;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) quick = true;
        else if (!std::strcmp(argv[i], "--auto-only")) auto_only = true;
        else only.push_back(argv[i]);
    }
    const std::string ex = std::string(ODEC_SOURCE_DIR) + "/examples/";
    const double prandtl = (2 + M_PI) * 1e5;
    // The footing of the static-solution issue: a smooth strip footing 2 m wide pushed at 0.01 m/s
    // into a 10 x 0.2 x 5 m cohesive slab zoned at 0.125 m, to 4.4 mm in static mode (twice the
    // time in dynamic mode, whose step is half as long); the pressure then against (2 + pi) c.
    const std::string slab =
        "new\ntitle 'Smooth strip footing on a cohesive slab'\nset small\npoly brick 0 10 0 0.2 -5 0\n"
        "prop mat=1 dens=2000 k=8.33e8 g=3.85e8 coh=1e5 fric=0 ten=1e10 dil=0\nchange cons=2\ngen edge 0.125\n"
        "bound xvel 0 range x -0.001 0.001\nbound xvel 0 range x 9.999 10.001\nbound yvel 0 range y -0.001 0.001\n"
        "bound yvel 0 range y 0.199 0.201\nfix range z -5.001 -4.999\n"
        "bound zvel -0.01 range x 3.999 6.001 z -0.001 0.001\nhist zreaction range x 3.999 6.001 z -0.001 0.001\n"
        "hist ncyc 100\nSTEPS\n";
    std::vector<Model_> models = {
        {"kirsch", "verification/kirsch.dat", "crown displacement, m", 6.91e-3,
         [](const Model& m) { return -gp_disp(m, {0, 0.25, 1}, 2); }},
        {"tunnel-stress", "tutorial/tunnel-stress.dat", "crown displacement, m", 0,
         [](const Model& m) { return -gp_disp(m, {0, 0.25, 1}, 2); }},
        {"prandtl", "verification/footing-prandtl.dat", "bearing pressure at the end, Pa", prandtl,
         [](const Model& m) { return m.histories.items.at(0).values.back() / 0.1; }},
        {"footing-slab", "", "bearing pressure at 4.4 mm, Pa", prandtl,
         [](const Model& m) { return m.histories.items.at(0).values.back() / 0.4; }},
        {"jointed-tunnel", "tutorial/jointed-tunnel-insitu.dat", "crown displacement after excavation, m", 0,
         [](const Model& m) { return -gp_disp(m, {0, 0.5, 3}, 2); }},
    };
    std::printf("threads: %d (ODEC_THREADS; cpu s sums them)\n", thread_count());
    std::printf("%-14s %-24s %9s %9s %9s %11s %14s %12s  %s\n", "model", "way", "steps", "cpu s", "wall s", "dt s",
                "answer", "analytic", "quantity");
    for (const Model_& mod : models) {
        if (!only.empty() && std::find(only.begin(), only.end(), mod.name) == only.end()) continue;
        if (quick && std::string(mod.name) != "tunnel-stress") continue;
        std::string text = mod.file.empty() ? slab : slurp(ex + mod.file);
        if (std::string(mod.name) == "jointed-tunnel") {
            // After the excavation: solve to 1e-5 (at most 30,000 steps) instead of 200 steps.
            const size_t at = text.find("step 200");
            if (at != std::string::npos) text.replace(at, 8, "solve ratio 1e-5 cycles 30000");
        }
        for (Way way : {Way::Dynamic, Way::StaticLocal, Way::StaticAuto}) {
            if (auto_only && way != Way::StaticAuto) continue;
            Model m;
            std::ostringstream out, err;
            Interpreter in(m, command_table(), out, err);
            in.quiet = true;
            const double t0 = cpu_seconds();
            const auto w0 = std::chrono::steady_clock::now();
            std::string script = text;
            if (mod.file.empty()) {
                const size_t at = script.find("STEPS");
                script.replace(at, 5, way == Way::Dynamic ? "step 15200" : "step 7200");
            }
            script = variant(script, way);
            const bool ok = in.run_text(mod.file.empty() ? "footing-slab" : mod.file, script, false);
            const double t = cpu_seconds() - t0;
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
            if (!ok) {
                std::printf("%-14s %-24s failed: %s\n", mod.name, way_name(way), err.str().c_str());
                continue;
            }
            std::printf("%-14s %-24s %9ld %9.2f %9.2f %11.4g %14.6g %12.6g  %s\n", mod.name, way_name(way), m.step, t,
                        wall, m.dt, mod.answer(m), mod.analytic, mod.quantity);
            std::fflush(stdout);
        }
    }
    return 0;
}
