#pragma once

// Private to the report: the statistics of a planned run (docs/report.md, "Statistics").

#include <filesystem>
#include <string>

#include "emrm/results/run_estimates.hpp"

namespace emrm::report::detail {

/// The section for the run's acceptance criterion, from its estimates.json (results::find_run_estimates
/// in DIR): per cell the estimate, Wilson interval, n and whether the precision target
/// is met; the Hoeffding bound in a sentence with the n that would meet the target; the weighted
/// Ŝ(A) with its intervals; for every cell that misses its target, how many more scenarios it
/// needs. A note when the file is not in emrm's form; "" when no run is found.
[[nodiscard]] std::string statistics_html(const results::FoundRunEstimates& found, const std::filesystem::path& dir);

}  // namespace emrm::report::detail
