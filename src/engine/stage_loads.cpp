#include "engine/stages.h"

namespace odec {

void block_applied_load(const Model& m, int b, double t, Vec3& force, Vec3& moment) {
    force.setZero();
    moment.setZero();
    const std::vector<BlockLoad>& loads = m.blocks.loads[b];
    if (loads.empty()) return;
    const Mat3 r = m.blocks.orientation[b].toRotationMatrix();
    for (const BlockLoad& l : loads) {
        const double k = m.table_factor(l.table, t);
        const Vec3 f = k * l.force;
        force += f;
        moment += k * l.couple;
        if (!l.lever.isZero(0)) moment += (r * l.lever).cross(f);
    }
}

double block_applied_force_bound(const Model& m, int b) {
    double sum = 0;
    for (const BlockLoad& l : m.blocks.loads[b]) {
        double k = 1;
        if (l.table > 0) {
            const Table* t = m.tables.find(l.table);
            k = t ? t->max_abs() : 0.0;
        }
        sum += k * l.force.stableNorm();
    }
    return sum;
}

void apply_loads(Model& m) {
    BlockSet& s = m.blocks;
    // Each block on its own: on the threads when they are many.
    parallel_for(s.size(), thread_count(), s.size() >= kParallelMinBlocks, [&](int b) {
        const Vec3 w = s.mass[b] * m.gravity;
        if (s.loads[b].empty()) {
            s.force[b] = w;
            s.moment[b].setZero();
            s.force_scale[b] = w.norm();
            return;
        }
        Vec3 f, mom;
        block_applied_load(m, b, m.time, f, mom);
        s.force[b] = w + f;
        s.moment[b] = mom;
        s.force_scale[b] = w.norm() + f.norm();
    });
}

} // namespace odec
