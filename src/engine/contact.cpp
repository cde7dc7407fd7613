#include "engine/contact.h"

#include "engine/model.h"

namespace odec {

void detect_contacts(Model&) {}
void update_contacts(Model&, double) {}
double contact_critical_timestep(const Model&) { return 0; }

} // namespace odec
