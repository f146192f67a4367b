#pragma once

// The cross-file checks of `emrm plan` (docs/plan.md, "Checks across files"): the ODD's factors
// against what the scene and the simulator accept, the safety case's factor ranges against the
// ODD's, and the planned scenarios against the scene's limit on the initial distance.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "emrm/safety/model.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::workflow {

/// The scene a plan's scenarios will run in: the ODD's `scene:` file, else the default scene.
/// Throws InputError for a bad scene file.
[[nodiscard]] sim::SceneConfig plan_scene(const scenario::Odd& odd);

/// The levels of the categorical factor `factor` of the scene in `scene_file` (none: the default
/// scene), in index order; empty when it has none of that name. The scenario::LevelLookup every ODD
/// is loaded with, so that a constant factor may name a level (`value: deer`).
[[nodiscard]] std::vector<std::string> family_levels(const std::optional<std::filesystem::path>& scene_file,
                                                     const std::string& factor);

/// Checks every ODD factor the simulator reads (sim::scenario_factors) against the scene: its
/// unit, then each value of its domain (bin edges, class values, the constant). Throws InputError at
/// the offending unit or value in the ODD file, saying what was expected and hinting at a unit slip:
/// "mu 50: expected a friction coefficient in (0, 2]; a percentage?".
void check_odd_against_scene(const scenario::Odd& odd, const sim::SceneConfig& scene);

/// "FILE:LINE:COL: warning: …" for each factor whose ODD domain reaches beyond the safety case's
/// `min`/`max` for it, or whose unit differs; each names both places.
[[nodiscard]] std::vector<std::string> safety_range_warnings(const scenario::Odd& odd, const safety::SafetyCase& sc);

/// A warning (at the ODD's relevance rule) when planned scenarios lie where the scene cannot place
/// the truck (v·TTC beyond its max_initial_distance_m): `emrm run` would find them infeasible.
[[nodiscard]] std::vector<std::string> placement_warnings(const scenario::Odd& odd, const scenario::Plan& plan,
                                                          const sim::SceneConfig& scene);

}  // namespace emrm::workflow
