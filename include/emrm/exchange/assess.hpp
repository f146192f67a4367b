#pragma once

// `emrm assess`: a trajectory recorded by another simulator, judged by emrm's own models
// (docs/openscenario.md, "Judging a recorded trajectory"): contact with the truck and leaving the
// drivable area, between samples too, assessed by the same functions a rollout's checks call
// (sim::actor_impact, sim::roadside_impact: the impact model, Δv, injury risks, loss level), and
// the safe state at the end (stopped, or past the truck and sim::stable_with_room_to_stop). No
// vehicle dynamics run: the recorded motion is what is judged.

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "emrm/core/geometry.hpp"
#include "emrm/exchange/recorded_trajectory.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::exchange {

enum class SafeState { kNone, kStopped, kStabilised };
[[nodiscard]] std::string_view safe_state_name(SafeState s) noexcept;

/// A recorded trajectory's outcome, in the terms of sim::StrategyOutcome.
struct Assessment {
  bool avoided = false;
  bool contact = false;
  std::string contact_with;  ///< the actor met (its name in the scene: "truck", "following car")
  std::string hazard;        ///< the scene's hazard, by its name
  bool road_departure = false;
  std::optional<double> event_time_s;  ///< when the contact or the departure began
  core::Vec2 event_point_m;            ///< where: the contact's point, or the corner across the edge
  sim::ImpactAssessment impact;        ///< zeros when avoided
  sim::ImpactAssessment unmitigated;   ///< the cell's no-action reference (simulated)
  int delta_loss = 0;                  ///< unmitigated level − this level
  std::optional<double> min_ttc_s;     ///< with the scene's truck only (sim::min_ttc_along)
  SafeState safe_state = SafeState::kNone;
  double end_time_s = 0.0;         ///< the event's time, or the last sample's
  std::size_t samples_judged = 0;  ///< samples up to the event (all without one)
};

/// Judges `trajectory` in the cell. Throws UsageError for a cell the scene rejects or that is
/// infeasible (v·TTC beyond max_initial_distance_m).
[[nodiscard]] Assessment assess(const sim::SceneConfig& config, const sim::CellInput& cell,
                                const RecordedTrajectory& trajectory);

/// {"file", "format", "input", "truck", "samples", "strategy"?, "unmitigated", "outcome"}; "outcome" has the
/// keys of a strategy in `emrm simulate --json` (impact, avoided, contact, road_departure,
/// departure_speed_kph, delta_loss, min_ttc_s) plus event_time_s, event_point, safe_state, end_time_s.
[[nodiscard]] nlohmann::ordered_json to_json(const Assessment& a, const RecordedTrajectory& trajectory,
                                             TrajectoryFormat format, const sim::FactorTable& factors,
                                             const sim::CellInput& cell, const std::string& strategy);
/// The same as a few lines of text.
[[nodiscard]] std::string to_text(const Assessment& a, const RecordedTrajectory& trajectory,
                                  const std::string& strategy);

}  // namespace emrm::exchange
