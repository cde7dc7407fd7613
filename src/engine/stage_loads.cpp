#include "engine/stages.h"

namespace odec {

void apply_loads(Model& m) {
    BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        const Vec3 w = s.mass[b] * m.gravity;
        s.force[b] = w + s.applied_force[b];
        s.moment[b].setZero();
        s.force_scale[b] = w.norm() + s.applied_force[b].norm();
    }
}

} // namespace odec
