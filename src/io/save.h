// Saving and restoring the whole model state to a binary file (`save` / `restore`).
//
// A restored model cycles on to the same bits as one that was never saved: every array
// of the model and of its contacts is written with its doubles' exact bytes, including the
// contact-detection caches and the adaptive damping coefficient. save.cpp describes the
// layout.
#pragma once

#include <cstdint>
#include <string>

#include "engine/model.h"

namespace odec {

// Version of the file layout. A file with a larger number is refused; a reader of a newer
// layout may read older ones.
// 2: histories follow a material point; 3: deformable blocks (zones, gridpoints, `bound stress`
// faces, zone and reaction histories) and the zone stage of the profile.
constexpr std::uint32_t kSaveFormatVersion = 5;

// Write the model to `path`. The bytes go to a temporary file in the same directory, which
// is flushed to disk and then renamed over `path`, so a failed or interrupted save leaves
// any existing file as it was. Returns false and fills `error` (naming the file) on failure.
bool save_model(const Model& m, const std::string& path, std::string& error);

// Read `path` into `out`. The file is read into a fresh model, which replaces `out` only
// when the whole file was read and checked; on any failure (cannot open, truncated, not a
// save file, newer format, checksum mismatch, inconsistent arrays) `out` is untouched and
// `error` says which file and what is wrong.
bool restore_model(const std::string& path, Model& out, std::string& error);

// The program version written into save files ("0.1.0").
const char* save_program_version();

// Extension added to a save file name that has none.
constexpr const char* kSaveExtension = ".sav";
// `name` with ".sav" added when its last path component has no extension.
std::string save_file_name(const std::string& name);

} // namespace odec
