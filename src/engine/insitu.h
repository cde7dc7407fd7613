// The in-situ stress state (`insitu`): a stress field given once, taken by the zones of
// deformable blocks and by the joints between blocks, so that a model whose field is in
// equilibrium with gravity and its boundaries starts at rest.
//
// Zones take the field at their centroid. A joint takes, at each sub-contact, the traction
// the field puts on the joint plane (sigma n, n the contact normal), split into the normal
// stress (compression positive) and the shear stress on block b, and the closure that
// carries the normal stress (sn / kn). With water in the joints ('config flow') the springs
// carry the effective stress: the field's normal stress less the pore pressure of the
// sub-contact's flow node, which pushes on the faces itself (flow.h). Where the
// field's shear exceeds the joint's Coulomb strength, or its tension the joint's tensile
// strength, the sub-contact is capped as the joint law would cap it (and fails, when it had
// cohesion or tension to lose); a joined joint has no limits.
//
// Only the face-to-face part of a joint is loaded: a sub-contact's area must lie on a face
// of its block flat to the contact plane (within 20 degrees) and over a face of the other
// block flat to it too. Blocks that meet only along an edge or at a corner (where two joint
// sets cross) may still touch through an edge-on face: they start unloaded, as the rock
// around them carries the field through its real joints.
//
// Forces at rest. A surface gridpoint of a zoned block carries, from its zones, the traction
// of the field integrated against its shape function over the block surface around it, and
// for a field that varies linearly that integral is the field's traction at the weighted
// centre of the gridpoint's area ((2 x_i + x_j + x_k) / 4 over each surface triangle): each
// gridpoint sub-contact takes the traction there, with the area of its flat surface that
// lies over the other block's flat face. Where the two sides' meshes match (blocks cut from
// each other and zoned with the same edge), each gridpoint's contact force then balances its
// zones exactly. A rigid block's sub-contacts take the traction at their points, with
// weights on them corrected so that each contact's resultant and its moment about the
// contact's centre are those of the field over the contact area (the polygon's own
// vertex shares are exact for neither).
//
// The model keeps the fields given (Model::insitu, saved with it): zones made later by
// `gen` take them too, and so do the contacts of the blocks zoned, at zoning. Contacts
// found later as blocks move, or on faces cut later, start unloaded.
#pragma once

#include <vector>

#include "engine/range.h"
#include "engine/zones.h"

namespace odec {

struct Model;

// s + x gx + y gy + z gz, xx yy zz xy xz yz, Pa, tension positive.
struct StressField {
    Sym6 s = {0, 0, 0, 0, 0, 0};
    Sym6 gx = {0, 0, 0, 0, 0, 0};
    Sym6 gy = {0, 0, 0, 0, 0, 0};
    Sym6 gz = {0, 0, 0, 0, 0, 0};
    Sym6 at(const Vec3& x) const;
};

// One `insitu` command, as the model keeps it for zones made later.
struct InsituRecord {
    Range range;
    StressField field;
};

// What setting an in-situ field did.
struct InsituCount {
    int zones = 0;          // zones set
    int contacts = 0;       // contacts set
    int subs = 0;           // sub-contacts loaded
    int edge_subs = 0;      // sub-contacts left unloaded: an edge or corner contact, not face to face
    int slipping = 0;       // sub-contacts whose field shear exceeds the joint's strength: capped
    int opened = 0;         // sub-contacts the field pulls apart beyond the joint's tensile strength
    int no_stiffness = 0;   // contacts left unloaded: no joint material with a normal stiffness
    InsituCount& operator+=(const InsituCount& o);
};

// `insitu`: zones whose centroid r selects take the field; so do the contacts whose centroid
// (or either block, for region/group/id filters) r selects. Contacts are detected first when
// the model changed. The record is kept in m.insitu for zones made later.
InsituCount apply_insitu(Model& m, const Range& r, const StressField& f);

// After `gen` zoned `blocks`: their zones, and the contacts with one of them, take the kept
// fields (each record over its range, in the order given). Detects contacts when there are
// records to apply. Returns what was set (zeros when there are no records).
InsituCount apply_kept_insitu(Model& m, const std::vector<int>& blocks);

// The contact part alone (r selects contacts as above; `only`, when not empty, flags the
// blocks one of which a contact must have).
// 'insitu pp | wtable' changed the joints' water pressures from old_pp (per flow node): the
// rock's total stress stays, so every loaded sub-contact's springs take the change (sn' - dp,
// capped by the joint's strength as 'insitu' caps it; a joint whose water now carries all of
// the stress opens). Returns how many sub-contacts changed.
int shift_joint_water(Model& m, const std::vector<double>& old_pp);
InsituCount set_insitu_contact_stress(Model& m, const Range& r, const StressField& f,
                                      const std::vector<char>& only = {});

} // namespace odec
