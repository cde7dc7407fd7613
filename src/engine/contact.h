// Contacts between blocks: the common-plane method with sub-contacts.
//
// (Placeholder for the first slice: blocks do not touch yet. The full design,
// broad phase, common plane, sub-contacts and joint laws, replaces this file.)
#pragma once

#include <vector>

namespace odec {

struct Model;

struct ContactSet {
    int size() const { return 0; }
    void clear() {}
};

// Find new contacts and drop lost ones when blocks have moved far enough.
void detect_contacts(Model& m);
// Relative motion -> joint stresses -> forces and moments on both blocks.
void update_contacts(Model& m, double dt);
// Largest stable timestep the contacts allow (0 when there are none).
double contact_critical_timestep(const Model& m);

} // namespace odec
