#pragma once

// What `emrm import` makes of a scenario (docs/import.md, "emrm import"): the scene of the family
// openscenario, and the ranges a campaign sweeps its factors over — from a ParameterValueDistribution
// file that names the scenario, and from --factor-range KEY=FROM:TO:STEP — written as a campaign.

#include <filesystem>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "emrm/openscenario/distribution.hpp"
#include "emrm/openscenario/family.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::openscenario {

/// The values a campaign sweeps one factor over, in the factor's unit (km/h for speed_kph).
struct FactorSweep {
  std::string factor;                                    ///< a key of the scene's factor table
  std::variant<ValueRange, std::vector<double>> values;  ///< from, to, step; or the levels
  std::string source;                                    ///< for messages: "--factor-range" or file:line:column
};

struct ImportedScenario {
  sim::SceneConfig scene;
  /// In the order of the scene's factor table; a factor at most once.
  std::vector<FactorSweep> sweeps;
  /// A DeterministicMultiParameterDistribution's concrete scenarios, as factor → value (the product
  /// of several such distributions): each one a grid of its own with the sweeps.
  std::vector<std::map<std::string, double>> value_sets;
};

/// The most grids the value sets of a distribution may make.
inline constexpr std::size_t kMaxValueSets = 1000;

/// `KEY=FROM:TO:STEP` (from <= to, step > 0, finite numbers). Throws UsageError otherwise.
[[nodiscard]] FactorSweep parse_factor_range(const std::string& text);

/// Reads a scenario (.xosc), or a ParameterValueDistribution file and the scenario it names, as
/// `emrm import` does: the scene (scene_of; with a distribution and no `choices.factors`, the
/// factors are the parameters the distribution varies), and the sweeps of the distribution (the
/// ego's speed parameter's in km/h as speed_kph's) and of `ranges` (which replace a distribution's
/// for the same factor). Throws InputError at the distribution's element for a parameter the
/// scenario does not declare or that is no number, and UsageError for a range of a factor the scene
/// does not have or beyond what the factor accepts.
[[nodiscard]] ImportedScenario import_scenario(const std::filesystem::path& file, const ImportChoices& choices = {},
                                               const std::vector<FactorSweep>& ranges = {});

/// The TTC range a campaign sweeps when nothing gives one (s).
inline constexpr ValueRange kDefaultTtcSweep{0.1, 2.0, 0.1};

/// A campaign (docs/campaign.md) over the imported scene, `scene_ref` as its `scene:`: one product
/// grid of the sweeps (ttc_s over kDefaultTtcSweep when not swept; other factors at their
/// defaults), or one per value set.
[[nodiscard]] std::string campaign_yaml(const ImportedScenario& imported, const std::string& scene_ref);

}  // namespace emrm::openscenario
