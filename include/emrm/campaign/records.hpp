#pragma once

// What a campaign stores per cell and per strategy: plain rows, the common currency of the
// results store, the exports and the aggregation (tables, KPIs, diagnostics).

#include <cstdint>
#include <string>
#include <vector>

namespace emrm::campaign {

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
};

/// One cell of a grid with its unmitigated reference, region and outcomes.
struct CellRecord {
  std::string grid;
  std::int64_t index = 0;  ///< position of the cell in its grid's expansion order
  double speed_kph = 0.0;
  double ttc_s = 0.0;
  double mu = 0.0;
  double passage_m = 0.0;
  double truck_speed_kph = 0.0;
  std::uint64_t seed = 0;
  bool feasible = false;
  std::string region;  ///< G, Y, O, R or infeasible
  double unmitigated_impact_speed_kph = 0.0;
  double unmitigated_delta_v_kph = 0.0;
  double unmitigated_p_mais3 = 0.0;
  double unmitigated_p_fatal = 0.0;
  int unmitigated_loss_level = 0;
  std::vector<OutcomeRecord> outcomes;  ///< in the campaign's strategy order
};

}  // namespace emrm::campaign
