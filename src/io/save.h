// Saving and restoring the whole model state to a binary file (`save` / `restore`).
//
// A restored model cycles on to the same bits as one that was never saved: every array
// of the model and of its contacts is written with its doubles' exact bytes, including the
// contact-detection caches and the adaptive damping coefficient. save.cpp describes the
// layout.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/model.h"

namespace odec {

// Version of the file layout. A file with a larger number is refused; a reader of a newer
// layout may read older ones.
// 2: histories follow a material point; 3: deformable blocks (zones, gridpoints, `bound stress`
// faces, zone and reaction histories) and the zone stage of the profile; 4: contacts of
// deformable blocks; 5: FISH histories; 6: static and dynamic analysis (the mode, the inertial
// masses, the checks stage of the profile) and the `insitu` fields the model keeps for zones
// made later (older files have none: their zones and joints keep the stresses they hold);
// 7: loads on rigid blocks at a point, with a couple and a table (older files' applied force
// becomes a load at the centroid), tables on gridpoint loads and on `bound stress` faces;
// 8: the energy account and energy histories (older files restore with the account off);
// 9: each block's orientation at the last `reset disp` (in place of the accumulated small
// rotation), and the first sample of each history (histories made during a run no longer
// hold a NaN for each sample before them); 10: the overlap tolerance ('set ovtol'; older files
// take the automatic one); 11: cables and rock bolts, their histories and the cables stage of
// the profile (older files have none); 12: clumps, the pieces of a rigid solid that is not
// convex moving as one rigid body (older files have none: their pieces stay glued by their
// joined joint set, as they were saved); 13: fluid flow in the joints (its settings, fluid and
// nodes), the hydraulic apertures of joint materials and the flow stage of the profile (older
// files have no flow); 14: liners and the liners stage of the profile (older files have none);
// 15: adaptive damping's memory of the last step (older files start without it); 16: the
// timestep of that step (older files take the next step's), and gridpoints' sub-contact keys
// marked apart from vertices' (older files' are marked as they are read); 17: the sub-contacts'
// shear displacements and stresses as two components on their contact's shear axes (older
// files' vectors are put on the axes as they are read), and no reference point of a contact's
// plane (derived from its blocks: older files' points are checked and left); 18: a contact's
// normal as its octahedral code, its gap in single precision and its joint model in a byte, the
// sub-contacts' points as codes of fourteen bytes, and no normal stresses (derived from the
// closures) (older files' are coded and narrowed as they are read, their stresses checked and
// left); 19: whether the closures of open sub-contacts between rigid blocks are kept by their
// blocks' geometry references (contact.h; as dynamic mode keeps them: older files' are not),
// and how far
// each contact's blocks may move before a corner could press in unseen (older files have
// none: looked at every step until each contact is rebuilt).
constexpr std::uint32_t kSaveFormatVersion = 19;

// Write the model to `path`. A model that restore would refuse (a velocity that is not a finite
// number after a run-away, an index out of range) is not written: save and restore run the
// same checks, so every file odec writes can be read back. An existing `path` is replaced only
// when it is a regular file with a write permission bit. The bytes go through a small buffer
// (the file is never copied whole in memory) to a temporary file in the same directory,
// `path.tmp-PID-N`, which is flushed to disk and then renamed over `path`, so a failed or
// interrupted save leaves any existing file as it was. Returns false and fills `error` (naming
// the file and what is wrong, ending "nothing was written" when nothing was) on failure.
bool save_model(const Model& m, const std::string& path, std::string& error);

// What restore would refuse in `m` (e.g. "block 3: the velocity is not a finite number"), or "".
std::string save_problem(const Model& m);

// save_model without the checks: writes whatever `m` holds. For making files that restore must
// refuse (the tests of restore's checks); never used by a command.
bool save_model_unchecked(const Model& m, const std::string& path, std::string& error);

// Read `path` into `out`. The file is read into a fresh model, which replaces `out` only
// when the whole file was read and checked; on any failure (cannot open, not a regular file,
// truncated, not a save file, newer format, checksum mismatch, inconsistent arrays, numbers
// that are not finite or out of range) `out` is untouched and `error` says which file and what
// is wrong. A named pipe or a device is refused without waiting on it or reading it, and the
// size of the file is compared with the one its header gives before the rest is read; the
// file is read through a small buffer, never held whole in memory.
bool restore_model(const std::string& path, Model& out, std::string& error);

// A save's temporary file whose process is gone and which has not been written for this
// long is stale (one not written for a day is stale whatever its process).
constexpr int kStaleTemporarySeconds = 10;

// Remove the temporary files that saves killed part way left in `dir`: files named
// `NAME.tmp-PID-N` that are stale, owned by this user, and empty or beginning as a save file
// does. Returns their paths.
std::vector<std::string> remove_stale_save_temporaries(const std::string& dir);
// One line saying what remove_stale_save_temporaries removed ("" when nothing).
std::string stale_temporaries_note(const std::vector<std::string>& removed);

// Save `m` into `dir`, restore that file into a fresh model, save the restored model and
// compare the two files byte for byte (then remove them): true when they are the same, else
// false with `error` saying which step failed. For checking that every model round-trips.
bool check_save_round_trip(const Model& m, const std::string& dir, std::string& error);

// The program version written into save files ("0.1.0").
const char* save_program_version();

// Extension added to a save file name that has none.
constexpr const char* kSaveExtension = ".sav";
// `name` with ".sav" added when its last path component has no extension.
std::string save_file_name(const std::string& name);

} // namespace odec
