#pragma once

// What a campaign stores per cell and per strategy: plain rows, the common currency of the
// results store, the exports and the aggregation (tables, KPIs, diagnostics).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/sim/factors.hpp"

namespace emrm::campaign {

/// A trajectory as a figure needs it: points (t s, x m, y m, speed m/s).
using Polyline = std::vector<std::array<double, 4>>;

/// One strategy's outcome in one cell (the fields of sim::StrategyOutcome a report needs).
struct OutcomeRecord {
  std::string strategy;
  bool avoided = false;
  bool contact = false;
  bool road_departure = false;
  double impact_speed_kph = 0.0;
  double delta_v_kph = 0.0;
  double p_mais3 = 0.0;
  double p_fatal = 0.0;
  int loss_level = 0;
  int delta_loss = 0;
  double min_ttc_s = 0.0;  ///< may be +infinity (stored as NULL)
  int planner_nodes = 0;
  int planner_rollouts = 0;
  std::vector<std::string> fsm_trace;
  std::vector<std::string> loss_evaluation_trace;  ///< emrm only
  std::string chosen_strategy;                     ///< emrm only
  std::string adopted_from;
  std::string evidence;  ///< witness, certificate or undecided (sim::Evidence)
  /// The controls that drove it, as sim::to_json(Maneuver) text: replayed by `emrm verify`.
  std::string maneuver;
  /// Kept only for grids with `keep_trees: true` (the trajectory figure): the executed path and
  /// the planner's goal and fail-safe trees (at most 400 edges of each, 4 points per edge; stored
  /// to 0.01).
  Polyline path;
  std::vector<Polyline> goal_tree;
  std::vector<Polyline> failsafe_tree;

  /// The speed at which a road departure crossed the edge (its impact speed); 0 without one.
  [[nodiscard]] double departure_speed_kph() const noexcept { return road_departure ? impact_speed_kph : 0.0; }
};

/// One cell of a grid with its unmitigated reference, region and outcomes.
struct CellRecord {
  std::string grid;
  std::int64_t index = 0;  ///< position of the cell in its grid's expansion order
  sim::CellInput factors;  ///< the cell's factor values, in the order of the scene's factor table
  std::uint64_t seed = 0;
  bool feasible = false;
  std::string region;  ///< G, Y, O, R or infeasible
  double unmitigated_impact_speed_kph = 0.0;
  double unmitigated_delta_v_kph = 0.0;
  double unmitigated_p_mais3 = 0.0;
  double unmitigated_p_fatal = 0.0;
  int unmitigated_loss_level = 0;
  std::string evidence;                 ///< of the region: witness, certificate or undecided
  std::string mitigation_evidence;      ///< O and R: witness, proof or search (sim::CellResult)
  bool strengthened = false;            ///< the searches were strengthened
  std::string certificate;              ///< the unavoidability certificate as JSON text, when there is one
  double p_mais3_reduction = 0.0;       ///< unmitigated P(MAIS3+) minus the best strategy's
  double p_fatal_reduction = 0.0;       ///< the same for P(fatal)
  std::vector<OutcomeRecord> outcomes;  ///< in the campaign's strategy order; none for an inferred cell
  /// "simulated", or "inferred" by an adaptive sweep (docs/adaptive.md): then only the region is
  /// known (evidence "inferred", no outcomes, the unmitigated reference not computed).
  std::string method = "simulated";
  /// An inferred cell's grounds: the indices (in its grid) of the simulated cells that bound it;
  /// empty when the analytic stop boundary alone makes it G.
  std::vector<std::int64_t> inferred_from;

  /// Feasible and simulated, not inferred: the unmitigated reference and the harm reduction are known.
  [[nodiscard]] bool simulated() const noexcept { return feasible && method == "simulated"; }
  /// The outcome of `strategy`, or null when the cell has none (an inferred cell, a strategy not run).
  [[nodiscard]] const OutcomeRecord* outcome(std::string_view strategy) const noexcept {
    for (const auto& o : outcomes)
      if (o.strategy == strategy) return &o;
    return nullptr;
  }
};

}  // namespace emrm::campaign
