#pragma once

// The headline grid swept under every actuation profile of the scene's folder (docs/actuation.md,
// "Profiles side by side"); results/profiles.hpp reads what this writes.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/results/profiles.hpp"

namespace emrm::workflow {

/// Sweeps `grid` of `campaign` under each of `profiles` into options.output_dir/profiles/NAME/
/// (resumable like any sweep); a profile that leaves the campaign's actuation as it is reuses
/// options.output_dir/results.sqlite, which must hold the grid. Writes profiles/index.json.
/// Throws as sweep() and sim::apply_profile (a malformed profile: InputError at its line).
std::vector<results::ProfileRun> sweep_profiles(const campaign::Campaign& campaign, const std::string& grid,
                                                const std::vector<std::filesystem::path>& profiles,
                                                const campaign::SweepOptions& options);

}  // namespace emrm::workflow
