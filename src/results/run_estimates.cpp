#include "emrm/results/run_estimates.hpp"

namespace emrm::results {

std::string run_estimates_text(const RunEstimates& estimates) { return core::write_json(estimates).dump(2) + "\n"; }

RunEstimates read_run_estimates(const std::filesystem::path& path) { return core::read_json_file<RunEstimates>(path); }

}  // namespace emrm::results
