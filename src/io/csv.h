// Histories as CSV: one header row, then one row per sample.
#pragma once

#include <string>
#include <vector>

#include "engine/history.h"

namespace odec {

// Write histories `numbers` (1-based) to `path`. With vs > 0 the first column is history
// vs instead of the step number. Returns false and fills `error` when the file cannot be
// written. The file is written to a temporary name and renamed, so a failed write never
// leaves a half file behind.
bool write_histories_csv(const HistorySet& h, const std::vector<int>& numbers, int vs,
                         const std::string& path, std::string& error);

} // namespace odec
