#pragma once

// The headline grid under every actuation profile side by side (docs/actuation.md, "Profiles side
// by side"): `emrm reproduce` sweeps the grid once per profile of the scene's profiles/ folder into
// DIR/profiles/NAME/ (a profile whose actuation is the scene's reuses the main store), and lists
// them in DIR/profiles/index.json for the report.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/records.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/core/table.hpp"
#include "emrm/results/paper_reference.hpp"
#include "emrm/sim/actuation.hpp"

namespace emrm::results {

/// One profile's sweep of the grid.
struct ProfileRun {
  std::string name;                ///< the profile file's stem
  std::string description;         ///< its `description:`
  sim::ActuationConfig actuation;  ///< the scene's actuation with the profile over it
  std::filesystem::path store;     ///< its results.sqlite, relative to the output folder
  bool reused = false;             ///< the campaign's own store (the profile changes nothing)
  std::size_t simulated = 0;
  double seconds = 0.0;
};

/// The profile files of the campaign's scene folder (profiles/*.yaml), by name; none when there is
/// no such folder.
[[nodiscard]] std::vector<std::filesystem::path> scene_profiles(const campaign::Campaign& campaign);

/// Writes DIR/profiles/index.json, the list read_profile_index reads.
void write_profile_index(const std::filesystem::path& dir, const std::vector<ProfileRun>& runs);

/// DIR/profiles/index.json, or nothing when there is none. Throws InputError for a malformed index.
[[nodiscard]] std::vector<ProfileRun> read_profile_index(const std::filesystem::path& dir);

/// The region fractions of `grid` per profile (records[i] are runs[i]'s), with certified and
/// undecided O/R cells, the paper's row beside and notes on what each profile changes.
[[nodiscard]] core::Table profiles_table(const std::vector<ProfileRun>& runs,
                                         const std::vector<std::vector<campaign::CellRecord>>& records,
                                         const PaperReference& paper, const std::string& grid);

}  // namespace emrm::results
