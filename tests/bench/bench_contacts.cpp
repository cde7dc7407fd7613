// Contact benchmark: a cube of jointed rock, n x n x n m cut by three orthogonal joint sets
// of spacing 1 m into n^3 blocks (by the same code as `jset`), settling under gravity on a
// fixed base. Prints blocks, contacts,
// sub-contacts, steps per second, sub-contact updates per second, the refresh passes (contacts
// rebuilt without a full detection; the seconds spent building their contacts on the threads and
// writing them into the set on one) and the share of time in
// each cycle stage, and memory: heap in use after the blocks are made (bytes per block), the
// heap the contacts add at its largest (bytes per sub-contact, their per-contact records
// included) and the peak resident memory of the process, phase by phase (cutting, first
// detection, cycling: each phase's own peak), and the peak while detecting and cycling less the
// resident memory before it, per sub-contact.
// Usage: bench_contacts [n ...] [--steps s]   (default n = 10 20 30)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/memory.h"
#include "engine/cycle.h"
#include "engine/jset.h"
#include "engine/range.h"
#include "engine/model.h"
#include "memory.h"

using namespace odec;

namespace {

using bench::heap_bytes;
using bench::peak_rss_bytes;
using bench::reset_peak_rss;
using bench::rss_bytes;

void run(int n, long steps) {
    reset_peak_rss();
    const double rss_start = rss_bytes();
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
    const int rock = add_block(m, make_brick(0, n, 0, n, 0, n), 0, -1, 1);
    (void)rock;
    const double sizes[3][2] = {{0, 0}, {90, 90}, {90, 0}}; // horizontal, x = const, y = const
    Range not_base;
    Filter f;
    f.kind = FilterKind::Id;
    f.lo = f.hi = m.blocks.id[base];
    f.negate = true;
    not_base.filters.push_back(f);
    const auto c0 = std::chrono::steady_clock::now();
    for (const auto& dip_dd : sizes) {
        if (n < 2) break;
        JointSetSpec js;
        js.dip = dip_dd[0];
        js.dd = dip_dd[1];
        js.origin = Vec3(0.5 * n, 0.5 * n, 0.5 * n);
        js.spacing = 1.0;
        js.number = n - 1;
        cut_joint_set(m, js, not_base, 1e-6);
    }
    const double t_cut = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    std::printf("jset: %d blocks cut in %.3f s\n", m.blocks.size() - 1, t_cut);

    const double peak_cut = peak_rss_bytes();
    malloc_trim(0);
    const double heap_blocks = heap_bytes(); // the model without contacts
    const double rss_blocks = rss_bytes();
    reset_peak_rss();
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const std::string err = prepare_cycle(m);
    if (!err.empty()) {
        std::printf("cannot cycle: %s\n", err.c_str());
        return;
    }
    const double t_detect = std::chrono::duration<double>(Clock::now() - t0).count();
    double heap_most = heap_bytes();
    const double peak_detect = peak_rss_bytes();
    std::printf("  after first detection: heap %.1f MB, peak resident %.1f MB\n", heap_most / 1e6, peak_detect / 1e6);
    reset_peak_rss();
    m.profile = Profile{};
    const long revision0 = m.contacts.revision;
    const double build0 = m.contacts.build_seconds, write0 = m.contacts.write_seconds;
    CycleLimits lim;
    lim.max_steps = steps;
    const auto t1 = Clock::now();
    lim.max_steps = 1;
    cycle(m, lim); // the first step sizes the cycle's buffers
    heap_most = std::max(heap_most, heap_bytes());
    lim.max_steps = steps - 1;
    cycle(m, lim);
    heap_most = std::max(heap_most, heap_bytes());
    const double t = std::chrono::duration<double>(Clock::now() - t1).count();
    const double peak_cycle = peak_rss_bytes();
    const double rss_end = rss_bytes();
    const double total_stage = [&] {
        double s = 0;
        for (double x : m.profile.seconds) s += x;
        return s;
    }();
    std::printf("blocks %d  contacts %d  sub-contacts %d  first detection %.3f s\n", m.blocks.size(), m.contacts.size(),
                m.contacts.n_subs(), t_detect);
    std::printf("  %ld steps in %.3f s: %.1f steps/s, %.3g s/step, %.3g sub-contact updates/s, detections %ld, "
                "refresh passes %ld\n",
                steps, t, steps / t, t / steps, static_cast<double>(m.contacts.n_subs()) * steps / t, m.contacts.n_detections,
                m.contacts.revision - revision0);
    std::printf("  refresh passes: %.3f s building contacts (on the threads), %.3f s writing them into the set (on one "
                "thread)\n",
                m.contacts.build_seconds - build0, m.contacts.write_seconds - write0);
    std::printf("  stages:");
    for (int s = 0; s < static_cast<int>(Stage::Count); ++s) {
        std::printf(" %s %.1f%%", stage_name(static_cast<Stage>(s)), 100.0 * m.profile.seconds[s] / total_stage);
    }
    const double ns = std::max(1, m.contacts.n_subs());
    std::printf("\n  memory: %.0f bytes per block (model without contacts), %.0f bytes per sub-contact (contacts at "
                "their largest, %.0f per contact record)\n",
                heap_blocks / m.blocks.size(), (heap_most - heap_blocks) / ns,
                (heap_most - heap_blocks) / std::max(1, m.contacts.size()));
    const double peak = std::max({peak_cut, peak_detect, peak_cycle});
    std::printf("  resident: %.1f MB at the start, peaks %.1f MB cutting, %.1f MB detecting, %.1f MB cycling (%.1f MB at "
                "the end); %.1f MB with the blocks cut; peak %.1f MB = %.0f bytes per block; detecting and cycling at their "
                "peak %.0f bytes per sub-contact above the blocks\n",
                rss_start / 1e6, peak_cut / 1e6, peak_detect / 1e6, peak_cycle / 1e6, rss_end / 1e6, rss_blocks / 1e6, peak / 1e6,
                peak / m.blocks.size(), (std::max(peak_detect, peak_cycle) - rss_blocks) / ns);
    {
        // What the contact set's own arrays hold (their capacity), apart from the buffers
        // and the per-block state the figures above include.
        const ContactSet& cs = m.contacts;
        auto bytes = [](const auto& v) { return static_cast<double>(v.capacity() * sizeof(v[0])); };
        const double per_contact = bytes(cs.id) + bytes(cs.block_a) + bytes(cs.block_b) + bytes(cs.normal_code) +
                                   bytes(cs.gap) + bytes(cs.joint) + bytes(cs.sub_offset) + bytes(cs.free_motion) +
                                   bytes(cs.color_order);
        const double per_sub = bytes(cs.sub_code) + bytes(cs.sub_area) + bytes(cs.sub_point) +
                               bytes(cs.sub_tri) + bytes(cs.sub_un) + bytes(cs.sub_udil) +
                               bytes(cs.sub_us) + bytes(cs.sub_ss) + bytes(cs.key_table.keys);
        int carrying = 0;
        for (int c = 0; c < cs.size(); ++c) carrying += cs.sub_offset[c + 1] > cs.sub_offset[c];
        std::printf("  contact set arrays: %.1f MB per-contact (%.0f B a contact), %.1f MB per-sub-contact (%.0f B a "
                    "sub-contact); %d of %d contacts carry sub-contacts (%.2f each); %.0f B per sub-contact in all\n",
                    per_contact / 1e6, per_contact / std::max(1, cs.size()), per_sub / 1e6, per_sub / ns, carrying,
                    cs.size(), static_cast<double>(cs.n_subs()) / std::max(1, carrying), (per_contact + per_sub) / ns);
    }
    std::printf("  unbalanced ratio %.3g, largest unbalanced force %.3g N\n", unbalanced_ratio(m),
                max_unbalanced_force(m));
}

} // namespace

int main(int argc, char** argv) {
    tune_allocator(); // as odec does
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
