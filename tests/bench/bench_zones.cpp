// Zone benchmark: an elastic (or Mohr-Coulomb) deformable cube of n x n x n m, each cubic
// metre divided into six tetrahedra (a structured mesh, so that the mesher's time is not
// counted), settling under gravity on a fixed base. Prints zones, gridpoints, bytes per zone
// (its arrays and its share of the gridpoints'), steps per second, zone updates per second and
// the share of each cycle stage, and the peak resident memory of the run (zoning and cycling, the
// mesh given to the zoning included) per zone, with what the process held before it subtracted.
// With --jointed b, the cube is cut into separate blocks of b x b x b m, each zoned on its own
// (gridpoints of their own), which touch through the contacts of their surface gridpoints
// (joints kn = ks = 1e10 Pa/m, friction 30): the figures then include the contacts.
// Usage: bench_zones [n ...] [--steps s] [--mc] [--jointed b]
//        (default n = 26 55: about 1e5 and 1e6 zones)
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <vector>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/memory.h"
#include "engine/cycle.h"
#include "engine/model.h"
#include "engine/zones.h"
#include "memory.h"

using namespace odec;

namespace {

double cpu_seconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

template <class V>
double bytes_of(const V& v) {
    return static_cast<double>(v.capacity() * sizeof(typename V::value_type));
}

void run(int n, long steps, bool mc, int jointed) {
    bench::reset_peak_rss();
    const double rss_start = bench::rss_bytes();
    Model m;
    m.materials.resize(2);
    Material& mat = m.materials[1];
    mat.defined = true;
    mat.density = 2700;
    mat.bulk = 50e9;
    mat.shear = 30e9;
    mat.cohesion = 1e6;
    mat.friction = 35;
    mat.tension = 1e6;
    m.gravity = Vec3(0, 0, -10);
    const int bs = jointed > 0 && n % jointed == 0 ? jointed : n; // block size, m
    const int nb = n / bs;
    for (int k = 0; k < nb; ++k)
        for (int j = 0; j < nb; ++j)
            for (int i = 0; i < nb; ++i) {
                const int b = add_block(m, make_brick(i * bs, (i + 1) * bs, j * bs, (j + 1) * bs, k * bs, (k + 1) * bs), 0,
                                        -1, 1);
                m.blocks.cons[b] = mc ? kZoneMohrCoulomb : kZoneElastic;
            }
    if (nb > 1) {
        m.joint_materials.resize(2);
        JointMaterial& jm = m.joint_materials[1];
        jm.defined = true;
        jm.kn = 1e10;
        jm.ks = 1e10;
        jm.friction = 30;
        m.settings.default_jmat = 1;
    }
    // Nodes of the grid, and six tetrahedra per cell around its main diagonal (Kuhn's split,
    // which conforms across cells).
    BlockMesh mesh;
    const int np = n + 1;
    auto node = [&](int i, int j, int k) { return (k * np + j) * np + i; };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) mesh.nodes.emplace_back(i, j, k);
    const int n_blocks = m.blocks.size();
    mesh.tets.resize(n_blocks);
    const int paths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                for (const auto& p : paths) {
                    int c[3] = {i, j, k};
                    std::array<int, 4> t;
                    t[0] = node(c[0], c[1], c[2]);
                    for (int s = 0; s < 3; ++s) {
                        ++c[p[s]];
                        t[s + 1] = node(c[0], c[1], c[2]);
                    }
                    const Vec3 &a = mesh.nodes[t[0]], &b1 = mesh.nodes[t[1]], &c1 = mesh.nodes[t[2]], &d = mesh.nodes[t[3]];
                    if ((b1 - a).dot((c1 - a).cross(d - a)) < 0) std::swap(t[2], t[3]);
                    mesh.tets[((k / bs) * nb + j / bs) * nb + i / bs].push_back(t);
                }
            }
    // Each block's corners, in the order of its polyhedron's vertices; each block its own body.
    std::vector<int> blocks, bodies;
    for (int b = 0; b < n_blocks; ++b) {
        std::vector<int> corners;
        for (const Vec3& v : m.blocks.shape[b].vertices) {
            const Vec3 x = m.blocks.centroid[b] + v;
            corners.push_back(node(static_cast<int>(std::lround(x.x())), static_cast<int>(std::lround(x.y())),
                                   static_cast<int>(std::lround(x.z()))));
        }
        mesh.corner_node.push_back(corners);
        blocks.push_back(b);
        bodies.push_back(b + 1);
    }
    zone_blocks(m, blocks, bodies, mesh);
    GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (g.pos[i].z() < 1e-9) g.vel_bc[i] = 7;
    }
    const std::string problem = prepare_cycle(m);
    if (!problem.empty()) {
        std::fprintf(stderr, "bench_zones: %s\n", problem.c_str());
        std::exit(1);
    }
    CycleLimits lim;
    lim.max_steps = 10;
    cycle(m, lim);  // warm-up
    m.profile = Profile();
    lim.max_steps = steps;
    // Processor time of this process: on a machine shared with other work, wall time would
    // count the waiting too.
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_seconds();
    cycle(m, lim);
    const double seconds = cpu_seconds() - c0;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const ZoneSet& z = m.zones;
    double bytes = bytes_of(z.gp) + bytes_of(z.block) + bytes_of(z.model) + bytes_of(z.state) +
                   bytes_of(z.stress) + bytes_of(z.volume) + bytes_of(z.grad);
    bytes += bytes_of(g.pos) + bytes_of(g.ref) + bytes_of(g.vel) + bytes_of(g.disp) + bytes_of(g.force) +
             bytes_of(g.applied) + bytes_of(g.traction) + bytes_of(g.mass) + bytes_of(g.stiffness) +
             bytes_of(g.force_scale) + bytes_of(g.nmd_volume) + bytes_of(g.nmd_rate) + bytes_of(g.block) +
             bytes_of(g.vel_bc) + bytes_of(g.vel_bc_value) + bytes_of(g.vel_bc_table) + bytes_of(g.half_kick);
    const double zones = z.size();
    std::printf("%s cube %d^3 m", mc ? "Mohr-Coulomb" : "elastic", n);
    if (nb > 1) {
        std::printf(" in %d blocks of %d^3 m, %d contacts, %d sub-contacts", n_blocks, bs, m.contacts.size(),
                    m.contacts.n_subs());
    }
    const double peak = bench::peak_rss_bytes();
    std::printf(": %d zones, %d gridpoints, %.0f bytes per zone\n", z.size(), g.size(), bytes / zones);
    std::printf("  resident: %.1f MB at the start, peak %.1f MB: %.0f bytes per zone above the start (%.0f with it)\n",
                rss_start / 1e6, peak / 1e6, (peak - rss_start) / zones, peak / zones);
    std::printf("  %ld steps in %.3f s of processor time (%.3f s wall): %.1f steps/s, %.3g zone updates/s "
                "(%.1f ns per zone-step)\n",
                steps, seconds, wall, steps / seconds, zones * steps / seconds, 1e9 * seconds / (zones * steps));
    if (nb > 1) {
        std::printf("  %.3g sub-contact updates/s (with the zones of the same steps)\n",
                    static_cast<double>(m.contacts.n_subs()) * steps / seconds);
    }
    const Profile& p = m.profile;
    double total = 0;
    for (double s : p.seconds) total += s;
    std::printf("  stages:");
    for (int s = 0; s < static_cast<int>(Stage::Count); ++s) {
        std::printf(" %s %.1f%%", stage_name(static_cast<Stage>(s)), total > 0 ? 100.0 * p.seconds[s] / total : 0.0);
    }
    std::printf("\n");
}

} // namespace

int main(int argc, char** argv) {
    tune_allocator(); // as odec does
    std::vector<int> sizes;
    long steps = 0;
    bool mc = false;
    int jointed = 0;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
            steps = std::atol(argv[++i]);
        } else if (!std::strcmp(argv[i], "--jointed") && i + 1 < argc) {
            jointed = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--mc")) {
            mc = true;
        } else {
            sizes.push_back(std::atoi(argv[i]));
        }
    }
    if (sizes.empty()) sizes = {26, 55};
    for (int n : sizes) run(n, steps > 0 ? steps : (n <= 30 ? 200 : 40), mc, jointed);
    return 0;
}
