#pragma once

// Private to the report: the sections of report.html read from side files of the results folder
// (a planned run's shortfalls and estimates, verify.json, diagnostics.json, analysis/findings.json)
// and where a planned run's files are.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/results/run_estimates.hpp"

namespace emrm::report::detail {

/// Where a plan's coverage.json may be: reproduce's plan/, this folder, and beside the scenarios.csv
/// the run read (estimates.json's "plan", relative to its own folder).
[[nodiscard]] std::vector<std::filesystem::path> coverage_candidates(const std::filesystem::path& dir,
                                                                     const results::FoundRunEstimates& run);

/// The plan's shortfalls that the run repeated, first thing in the report: its estimates lack them.
/// "" when the run has none (or there is no run).
[[nodiscard]] std::string shortfalls_html(const results::FoundRunEstimates& run);

/// A section of report.html: its anchor, its name in the navigation, its heading and its HTML;
/// empty when the folder has nothing for it, and then `absent` says what would fill it and how.
struct Section {
  std::string id, nav, heading, body, absent;
};

/// The sections after the figures that come from side files: the planned run's estimates
/// (statistics_html), the verification, the diagnostics and the findings of the safety analysis.
[[nodiscard]] std::vector<Section> side_sections(const std::filesystem::path& dir,
                                                 const results::FoundRunEstimates& run);

/// The sections that have a body, each under its heading.
[[nodiscard]] std::string sections_html(const std::vector<Section>& sections);

}  // namespace emrm::report::detail
