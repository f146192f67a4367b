#pragma once

// The scene block of the family "openscenario" (docs/import.md): a scenario imported from an
// ASAM OpenSCENARIO file (.xosc) with its OpenDRIVE road. The scenario's storyboard is played open
// loop for each cell (its declared parameters that are factors set to the cell's values), the ego
// follows its storyboard until the threat onset — the first moment its time to collision with
// another road user falls to the cell's TTC — and from then on the strategies drive it.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "emrm/core/config.hpp"
#include "emrm/sim/factors.hpp"
#include "emrm/sim/road.hpp"

namespace emrm::sim {

/// A declared parameter of the scenario that the cells set: a factor under the parameter's name.
struct ImportedFactor {
  std::string parameter;   ///< as the scenario declares it
  std::string unit = "1";  ///< for texts and axes (OpenSCENARIO's values are SI: m, s, m/s, rad)
  /// The values a cell may give it (inclusive); unbounded when not given.
  std::optional<double> min;
  std::optional<double> max;

  template <class A>
  void serialize(A& a) {
    EMRM_REQUIRED_FIELD(a, parameter);
    EMRM_FIELD(a, unit);
    EMRM_FIELD(a, min);
    EMRM_FIELD(a, max);
    a.ensure(!parameter.empty(), "parameter", "expected the name of a declared parameter, got an empty one");
    a.ensure(!(min && max && *min > *max), "max", "expected min <= max, got {} and {}", min.value_or(0.0),
             max.value_or(0.0));
  }
};

/// The most declared parameters a scene may make factors: the others besides speed, TTC and friction.
inline constexpr std::size_t kMaxImportedFactors = kMaxFactors - kMethodFactors;

struct OpenScenarioConfig {
  /// The scenario (.xosc): relative to the scene file's folder as written; absolute once read.
  std::string file;
  /// The entity the EMRM drives.
  std::string ego = "Ego";
  /// A declared parameter (m/s) that the factor speed_kph sets; empty: the factor replaces the ego's
  /// speed in the storyboard's Init.
  std::string speed_parameter;
  /// Declared parameters that are factors, in cell order after speed, TTC and friction.
  std::vector<ImportedFactor> factors;
  /// How long the storyboard is played looking for the threat onset.
  double onset_search_s = 60.0;
  /// A storyboard element (event, action, maneuver, act, ...) at whose start the strategies take
  /// over, whatever the TTC then (the cell's ttc_s does not move it). Empty: the onset is where the
  /// ego's TTC first falls to the cell's.
  std::string handover;
  /// What lies beyond each edge of the drivable area (OpenDRIVE draws no guardrail into the lanes).
  Roadside right_roadside = Roadside::kBarrier;
  Roadside left_roadside = Roadside::kBarrier;

  template <class A>
  void serialize(A& a) {
    EMRM_REQUIRED_FIELD(a, file);
    EMRM_FIELD(a, ego);
    EMRM_FIELD(a, speed_parameter);
    EMRM_FIELD(a, factors);
    EMRM_FIELD(a, onset_search_s, core::positive);
    EMRM_FIELD(a, handover);
    EMRM_FIELD(a, right_roadside);
    EMRM_FIELD(a, left_roadside);
    a.ensure(!ego.empty(), "ego", "expected the name of the entity the EMRM drives, got an empty one");
    a.ensure(factors.size() <= kMaxImportedFactors, "factors",
             "expected at most {} declared parameters as factors, got {}", kMaxImportedFactors, factors.size());
  }
};

}  // namespace emrm::sim
