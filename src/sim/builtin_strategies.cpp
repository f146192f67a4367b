// The registration of the shipped strategies: the one place that names them. Everything else —
// the evaluation loop, the region rule, EMRM's choices, tables, figures, command-line choices —
// reads these records (docs/simulate.md, "Strategies").

#include "builtin_strategies.hpp"

namespace emrm::sim {

std::vector<RegisteredStrategy> builtin_strategies() {
  std::vector<RegisteredStrategy> all;
  all.push_back({{.name = "emergency_stop",
                  .label = "emergency stop",
                  .title = "Emerg. Stop",
                  .colour = "#4d4d4d",
                  .order = 10,
                  .role = StrategyRole::kBaseline,
                  .limits = {},
                  .planner = {},
                  .may_adopt = {},
                  .emrm_may_choose = true,
                  .controllability = 0},
                 emergency_stop_strategy()});
  all.push_back({{.name = "dodge",
                  .label = "dodge",
                  .title = "Dodge",
                  .colour = "#1f77b4",
                  .order = 20,
                  .role = StrategyRole::kEvasive,
                  .limits = {.forbid_rear_sliding = true},
                  .planner = "rrt",
                  .may_adopt = {"emergency_stop"},
                  .emrm_may_choose = true,
                  .controllability = 1},
                 planned_strategy()});
  all.push_back({{.name = "drift_to_avoid",
                  .label = "drift to avoid",
                  .title = "Drift to Avoid",
                  .colour = "#ff7f0e",
                  .order = 30,
                  .role = StrategyRole::kEvasive,
                  .limits = {.allow_rear_lock = true},
                  .planner = "rrt",
                  .may_adopt = {"emergency_stop", "dodge"},
                  .emrm_may_choose = true,
                  .controllability = 2},
                 planned_strategy()});
  all.push_back({{.name = "drift_to_accident",
                  .label = "drift to accident",
                  .title = "Drift to Accident",
                  .colour = "#9467bd",
                  .order = 40,
                  .role = StrategyRole::kEvasive,
                  .limits = {.allow_rear_lock = true, .accept_contact = true},
                  .planner = "rrt",
                  .may_adopt = {"emergency_stop", "dodge", "drift_to_avoid"},
                  .emrm_may_choose = true,
                  .controllability = 2},
                 planned_strategy()});
  all.push_back({{.name = "emrm",
                  .label = "EMRM",
                  .title = "EMRM",
                  .colour = "#2ca02c",
                  .order = 100,
                  .role = StrategyRole::kChooser,
                  .limits = {},
                  .planner = {},
                  .may_adopt = {},
                  .emrm_may_choose = false,
                  .controllability = {}},
                 emrm_chooser_strategy()});
  all.push_back({{.name = "best_strategy",
                  .label = "oracle (best strategy in hindsight)",
                  .title = "Oracle (best strategy in hindsight)",
                  .colour = "#8c564b",
                  .order = 110,
                  .role = StrategyRole::kChooser,
                  .limits = {},
                  .planner = {},
                  .may_adopt = {},
                  .emrm_may_choose = false,
                  .controllability = {},
                  .hindsight = true},
                 oracle_chooser_strategy()});
  return all;
}

}  // namespace emrm::sim
