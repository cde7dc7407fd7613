// From the contact engine's arrays to a ContactView: what `plot contact`, `plot principal`
// and `export vtk` read (contact_view.h). No VTK here.
//
// The engine keeps sub-contacts in body frames with closure positive and shear stress as
// felt by block b; a view speaks in world coordinates, block ids, closure positive and the
// force on block2 from block1. This file is the one place that translates, through the
// engine's public arrays and contact_info(), so the pictures and files agree with
// `print contact`.
#pragma once

#include <string>
#include <vector>

#include "engine/model.h"
#include "render/contact_view.h"

namespace odec {

// State numbers of a view, in the order of the engine's ContactState: "elastic",
// "slipping", "open", "failed".
std::vector<std::string> contact_state_names();

// Every contact of the model (one row each) and every sub-contact (one row each, `parent`
// the row of its contact), as they stand after the last step. `contact_indices` (may be
// null: all) keeps only those contacts and their sub-contacts, in the given order.
ContactView make_contact_view(const Model& m, const std::vector<int>* contact_indices = nullptr);

} // namespace odec
