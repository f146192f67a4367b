#include "emrm/results/run_estimates.hpp"

#include <system_error>

#include "emrm/core/error.hpp"
#include "emrm/results/results_dir.hpp"

namespace emrm::results {

std::string run_estimates_text(const RunEstimates& estimates) { return core::write_json(estimates).dump(2) + "\n"; }

RunEstimates read_run_estimates(const std::filesystem::path& path) { return core::read_json_file<RunEstimates>(path); }

FoundRunEstimates find_run_estimates(const std::filesystem::path& dir) {
  const ResultsDir folder(dir);
  for (const std::filesystem::path& file : {folder.plan_results().estimates_json(), folder.estimates_json()}) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec) || std::filesystem::file_size(file, ec) == 0 || ec) continue;
    FoundRunEstimates found{file, std::nullopt, {}};
    try {
      found.estimates = read_run_estimates(file);
    } catch (const InputError& e) {
      found.error = e.what();
    }
    return found;
  }
  return {};
}

}  // namespace emrm::results
