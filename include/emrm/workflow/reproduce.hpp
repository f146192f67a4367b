#pragma once

// `emrm reproduce`: the paper's whole case study on an example folder (the shipped T-junction by
// default) — the safety case analysed, both FSMs checked, the campaign swept and verified, the
// headline grid under every actuation profile, tables beside the paper's numbers, diagnostics, the
// minimum scenario set planned and run, figures and report.html (docs/results.md).

#include <cstddef>
#include <filesystem>
#include <string>

#include "emrm/campaign/sweep.hpp"

namespace emrm::workflow {

struct ReproduceOptions {
  std::filesystem::path output_dir;
  std::filesystem::path examples_dir;  ///< empty: find_examples() searches
  int threads = 0;                     ///< 0: all cores
  std::size_t sample = 40;             ///< cells checked against the reference planner
  std::string profile;                 ///< an actuation profile (NAME or FILE) over the scene; empty: none
  bool progress = false;               ///< the sweeps' progress line on standard error
};

/// The example folder: `examples_dir` when given (UsageError unless it holds every file reproduce
/// reads), else examples/tjunction in the current folder or a parent, or beside the executable
/// (an installed tree's share/emrm). Throws UsageError when there is none.
[[nodiscard]] std::filesystem::path find_examples(const std::filesystem::path& examples_dir);

/// Runs the whole case study into options.output_dir, printing a line per step on standard output,
/// and returns whether every check held (the analysis without errors, both FSMs sound, every
/// claim of the store verified, the plan covering C1–C4). A rerun resumes the sweeps stored there.
/// `distributor`: other processes that simulate the sweeps' cells (an MPI job's ranks; borrowed);
/// null: this process alone. Throws InputError/UsageError for bad input, before any long work.
bool reproduce(const ReproduceOptions& options, campaign::Distributor* distributor = nullptr);

}  // namespace emrm::workflow
