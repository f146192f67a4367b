#pragma once

// The exports of a results store (docs/campaign.md): the stored cells as CSV and JSON for other
// tools, streamed from the store so that nothing holds all results at once.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace emrm::campaign {

/// The exports' files in a results folder (results::ResultsDir names the folder's other files).
inline constexpr std::string_view kRegionsCsv = "regions.csv";
inline constexpr std::string_view kCellsCsv = "cells.csv";
inline constexpr std::string_view kCellsJson = "cells.json";

/// Writes DIR/regions.csv (every cell), DIR/cells.csv (one row per feasible cell and strategy) and
/// DIR/cells.json (every cell with its outcomes), sorted by grid order, index and strategy order,
/// CSV numbers with {:.6g}; the three are streamed into temporaries and renamed into place once all
/// three are complete (core::OutputFile), so a failure leaves the previous exports. Throws
/// as read_meta for a missing or foreign store, and emrm::Error when a file cannot be written.
/// Returns each grid's cells and feasible cells, in the store's order.
struct GridCount {
  std::string grid;
  std::size_t cells = 0, feasible = 0;
};
std::vector<GridCount> write_exports(const std::filesystem::path& results_sqlite, const std::filesystem::path& dir);

}  // namespace emrm::campaign
