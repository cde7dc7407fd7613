// Histories as CSV: one header row, then one row per sample.
#pragma once

#include <string>
#include <vector>

#include "engine/history.h"

namespace odec {

// Write histories `numbers` (1-based) to `path`, a row for each sample, in step order. With
// vs > 0 the first column is history vs instead of the step number, and the samples taken
// before that history was made have no row. A history made during a run has an empty cell
// in the rows before its first sample. Returns false and fills `error` when the file cannot
// be written; `rows` is the number of rows written. The file is written to a temporary name
// and renamed, so a failed write never leaves a half file behind.
bool write_histories_csv(const HistorySet& h, const std::vector<int>& numbers, int vs,
                         const std::string& path, std::string& error, size_t* rows = nullptr);

} // namespace odec
