// CalculiX benchmark: an elastic cube settling under its own weight, solved by odec and, when it
// is installed, by CalculiX (`ccx`) on the same mesh. Prints the wall and CPU seconds of each
// (user + system), the largest settlement of each, their difference, and the analytic settlement
// of the top of a laterally free column under its own weight, rho g H^2 / (2 E), for reference.
//
// Model: a 10 m cube (one deformable block, x, y and z in [0, 10] m) zoned by 'gen edge 0.5'
// (37,380 tetrahedral zones, 7,467 gridpoints); density 2500 kg/m^3, E 10 GPa, nu 0.25; gravity
// 10 m/s^2; the gridpoints of the base (z = 0) held in x, y and z; sides and top free.
//   odec      static mode (density scaling), 'solve ratio 1e-5', large strain (the default),
//             twice: with local damping 0.8 (the default) and with adaptive damping ('damp
//             auto'); timed: the solve, the model built and zoned beforehand.
//   CalculiX  odec's gridpoints (where they were zoned) as nodes and its zones as C3D4 elements,
//             linear elastic, one *STATIC step with *DLOAD GRAV, the nodes odec holds fixed in
//             all three directions; timed: the whole ccx run (input read, assembly, solution,
//             output).
// Both run on one thread (odec: set_thread_count(1); ccx: OMP_NUM_THREADS=1).
// The base is held laterally as well, so the analytic figure is a reference, not the answer.
//
// Usage: bench_ccx [--edge e] [--keep] [--no-ccx]
//        (--edge: zone edge, m, default 0.5; --keep: keep the CalculiX files and print where)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "commands.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "engine/zones.h"
#include "lang/interpreter.h"
#include "peer_run.h"

using namespace odec;
using odec_bench::process_cpu_seconds;

namespace {

constexpr double kSide = 10;       // m
constexpr double kDensity = 2500;  // kg/m^3
constexpr double kYoung = 10e9;    // Pa
constexpr double kPoisson = 0.25;
constexpr double kGravity = 10;    // m/s^2

// The CalculiX input for the zones and gridpoints of `m`: nodes at the gridpoints' positions when
// zoned (numbered from 1 in gridpoint order), one C3D4 element per zone (numbered from 1 in zone
// order, corners ordered so that the fourth lies on the positive side of the first three), the
// gridpoints held in x, y and z fixed, gravity on every element, and the nodes' displacements
// printed to the .dat file.
std::string calculix_input(const Model& m) {
    const GridpointSet& g = m.gridpoints;
    const ZoneSet& z = m.zones;
    std::ostringstream o;
    o.precision(17);
    o << "*HEADING\nElastic cube under gravity (odec bench_ccx)\n";
    o << "*NODE, NSET=NALL\n";
    for (int i = 0; i < g.size(); ++i) o << i + 1 << ", " << g.ref[i].x() << ", " << g.ref[i].y() << ", " << g.ref[i].z() << "\n";
    o << "*ELEMENT, TYPE=C3D4, ELSET=EALL\n";
    for (int e = 0; e < z.size(); ++e) {
        std::array<int, 4> c = z.gp[e];
        const Vec3 a = g.ref[c[1]] - g.ref[c[0]], b = g.ref[c[2]] - g.ref[c[0]], d = g.ref[c[3]] - g.ref[c[0]];
        if (a.cross(b).dot(d) < 0) std::swap(c[1], c[2]);
        o << e + 1 << ", " << c[0] + 1 << ", " << c[1] + 1 << ", " << c[2] + 1 << ", " << c[3] + 1 << "\n";
    }
    o << "*NSET, NSET=NFIX\n";
    int n_fixed = 0;
    for (int i = 0; i < g.size(); ++i) {
        if (g.vel_bc[i] != 7 || g.vel_bc_value[i] != Vec3::Zero()) continue;
        o << (n_fixed == 0 ? "" : n_fixed % 16 == 0 ? "\n" : ", ") << i + 1; // at most 16 a line
        ++n_fixed;
    }
    o << "\n";
    o << "*BOUNDARY\nNFIX, 1, 3\n";
    o << "*MATERIAL, NAME=ROCK\n*ELASTIC\n" << kYoung << ", " << kPoisson << "\n*DENSITY\n" << kDensity << "\n";
    o << "*SOLID SECTION, ELSET=EALL, MATERIAL=ROCK\n";
    o << "*STEP\n*STATIC\n*DLOAD\nEALL, GRAV, " << kGravity << ", 0., 0., -1.\n";
    o << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
    return o.str();
}

// The nodes' displacements printed by *NODE PRINT in CalculiX's .dat file, by node number - 1;
// false when they are not all there.
bool read_displacements(const std::string& path, int n_nodes, std::vector<Vec3>* u) {
    std::ifstream in(path);
    std::string line;
    u->assign(n_nodes, Vec3::Zero());
    std::vector<char> seen(n_nodes, 0);
    bool in_block = false;
    while (std::getline(in, line)) {
        if (line.find("displacements") != std::string::npos) {
            in_block = true;
            continue;
        }
        if (!in_block) continue;
        int node;
        double x, y, zz;
        if (std::sscanf(line.c_str(), "%d %lf %lf %lf", &node, &x, &y, &zz) == 4 && node >= 1 && node <= n_nodes) {
            (*u)[node - 1] = Vec3(x, y, zz);
            seen[node - 1] = 1;
        }
    }
    return std::all_of(seen.begin(), seen.end(), [](char s) { return s != 0; });
}

} // namespace

int main(int argc, char** argv) {
    double edge = 0.5;
    bool keep = false, with_ccx = true;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--edge") && i + 1 < argc) edge = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--keep")) keep = true;
        else if (!std::strcmp(argv[i], "--no-ccx")) with_ccx = false;
        else {
            std::fprintf(stderr, "usage: bench_ccx [--edge e] [--keep] [--no-ccx]\n");
            return 2;
        }
    }
    set_thread_count(1);
    char text[1024];
    std::snprintf(text, sizeof text,
                  "new\npoly brick 0 %g 0 %g 0 %g\nprop mat=1 dens=%g ymod=%g prat=%g\ngen edge %g\n"
                  "fix range z -0.001 0.001\ngrav 0 0 %g\n",
                  kSide, kSide, kSide, kDensity, kYoung, kPoisson, edge, -kGravity);
    // odec's two ways, each on a model of its own; the mesh is the same bits in both.
    struct Run {
        const char* name = "";
        const char* damping = "";
        Model m;
        double cpu = 0, wall = 0, settlement = 0;
    };
    Run runs[2];
    runs[0].name = "odec, damp local";
    runs[1].name = "odec, damp auto";
    runs[1].damping = "damp auto\n";
    for (Run& r : runs) {
        std::ostringstream out, err;
        Interpreter in(r.m, command_table(), out, err);
        in.quiet = true;
        const double b0 = process_cpu_seconds();
        const bool built = in.run_text("bench_ccx", std::string(text) + r.damping, false);
        const double build_cpu = process_cpu_seconds() - b0;
        if (!built) {
            std::printf("odec could not build the model: %s\n", err.str().c_str());
            return 1;
        }
        if (&r == &runs[0]) {
            std::printf("elastic cube %g m, zone edge %g m: %d zones, %d gridpoints; one thread each; cpu = user + "
                        "system seconds\n",
                        kSide, edge, r.m.zones.size(), r.m.gridpoints.size());
            std::printf("odec model built and zoned (not counted below): cpu %.2f s\n", build_cpu);
            std::fflush(stdout);
        }
        const double c0 = process_cpu_seconds();
        const auto w0 = std::chrono::steady_clock::now();
        const bool solved = in.run_text("bench_ccx", "solve ratio 1e-5\n", false);
        r.cpu = process_cpu_seconds() - c0;
        r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        if (!solved) {
            std::printf("%s: solve failed: %s\n", r.name, err.str().c_str());
            return 1;
        }
        for (int i = 0; i < r.m.gridpoints.size(); ++i) r.settlement = std::max(r.settlement, -r.m.gridpoints.disp[i].z());
        std::printf("%-17s %6ld steps   wall %7.2f s   cpu %7.2f s   largest settlement %.6e m\n", r.name, r.m.step,
                    r.wall, r.cpu, r.settlement);
        std::fflush(stdout);
    }
    const Model& m = runs[0].m;
    const GridpointSet& g = m.gridpoints;
    const double analytic = kDensity * kGravity * kSide * kSide / (2 * kYoung);

    const std::string ccx = with_ccx ? odec_bench::find_program("ccx") : "";
    if (ccx.empty()) {
        std::printf("ccx %s: skipped\n", with_ccx ? "not installed" : "not asked for");
    } else {
        char dir_template[] = "/tmp/bench_ccx.XXXXXX";
        const char* dir = mkdtemp(dir_template);
        if (!dir) {
            std::printf("ccx: cannot make a directory for its files: skipped\n");
        } else {
            const std::string job = "cube";
            const std::string base = std::string(dir) + "/" + job;
            {
                std::ofstream f(base + ".inp");
                f << calculix_input(m);
            }
            const odec_bench::ChildRun r =
                odec_bench::run_program({ccx, job}, dir, {"OMP_NUM_THREADS=1", "CCX_NPROC_EQUATION_SOLVER=1"});
            std::vector<Vec3> u;
            if (r.status != 0 || !read_displacements(base + ".dat", g.size(), &u)) {
                std::printf("ccx failed (exit status %d), its output:\n%s\n", r.status, r.output.c_str());
                keep = true;
            } else {
                double ccx_max = 0;
                for (const Vec3& x : u) ccx_max = std::max(ccx_max, -x.z());
                std::printf("%-17s %6s         wall %7.2f s   cpu %7.2f s   largest settlement %.6e m\n", "ccx", "",
                            r.wall, r.cpu, ccx_max);
                for (const Run& o : runs) {
                    std::printf("%s against ccx: largest settlement %+.3e m (%+.3f%% of ccx's); cpu %.2f, wall %.2f "
                                "times ccx's\n",
                                o.name, o.settlement - ccx_max, 100.0 * (o.settlement - ccx_max) / ccx_max,
                                o.cpu / r.cpu, o.wall / r.wall);
                }
            }
            if (keep) {
                std::printf("CalculiX files kept in %s\n", dir);
            } else {
                for (const char* ext : {".inp", ".dat", ".frd", ".sta", ".cvg", ".12d"}) std::remove((base + ext).c_str());
                std::remove((std::string(dir) + "/spooles.out").c_str());
                if (rmdir(dir) != 0) std::printf("CalculiX files left in %s\n", dir);
            }
        }
    }
    std::printf("analytic, top of a laterally free column: rho g H^2 / (2 E) = %.6e m (here the base is held "
                "laterally too)\n",
                analytic);
    return 0;
}
