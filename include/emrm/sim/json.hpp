#pragma once

// The stable JSON form of a simulated cell (docs/simulate.md, "JSON"; listed in docs/outputs.md).

#include <nlohmann/json.hpp>

#include "emrm/sim/simulate.hpp"

namespace emrm::sim {

struct JsonOptions {
  bool timing = false;  ///< add planner wall-clock times (they vary run to run; off keeps output reproducible)
  /// Each strategy's `trajectory` and `truck_trajectory`; off for a caller that hands them out
  /// otherwise (the Python module, as arrays over the result's own memory).
  bool trajectories = true;
};

/// {"input":…, "feasible":…, "region":…, "evidence":…, "unmitigated":…, "strategies":{name: …}}, each
/// strategy with its trajectory at every integration step, the truck's at the same times and the
/// maneuver that replays it.
[[nodiscard]] nlohmann::json to_json(const CellResult& result, const Scene& scene, std::uint64_t seed,
                                     const JsonOptions& options = {});

/// {"impact_speed_kph", "delta_v_kph", "p_mais3", "p_fatal", "loss_level"}: an impact as each
/// strategy's outcome shows it.
[[nodiscard]] nlohmann::json to_json(const ImpactAssessment& impact);

/// An actuation as JSON: its six keys, every number to full precision.
[[nodiscard]] nlohmann::json to_json(const ActuationConfig& actuation);
/// The actuation back from that JSON. Throws InputError naming `where` and the key when a member is
/// missing, of the wrong type or not finite.
[[nodiscard]] ActuationConfig actuation_from_json(const nlohmann::json& j, const std::string& where);

/// A cell as JSON: {key: value} for each of the scenario's factors.
[[nodiscard]] nlohmann::json to_json(const CellInput& cell, const FactorTable& factors);
/// A factor table as JSON: [{key, unit, what, role, default, low, low_inclusive, high}] in cell
/// order (`high` null when unbounded): `emrm families --json`.
[[nodiscard]] nlohmann::json to_json(const FactorTable& factors);
/// A certificate as JSON, every number to full precision (check_certificate re-derives it); its cell
/// named by the scenario's factors.
[[nodiscard]] nlohmann::json to_json(const Certificate& certificate, const FactorTable& factors);
/// The certificate back from that JSON. Throws InputError naming `where` and the key when a member
/// is missing, of the wrong type or not finite.
[[nodiscard]] Certificate certificate_from_json(const nlohmann::json& j, const FactorTable& factors,
                                                const std::string& where);

/// A maneuver as JSON: {"plan": [segment…], "tail": {…} or null}, every number to full precision so
/// that a replay reproduces the run bit for bit.
[[nodiscard]] nlohmann::json to_json(const Maneuver& maneuver);
/// The maneuver back from that JSON. Throws InputError naming `where` and the key when a member is
/// missing, of the wrong type or not finite.
[[nodiscard]] Maneuver maneuver_from_json(const nlohmann::json& j, const std::string& where);

}  // namespace emrm::sim
