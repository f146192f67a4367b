#pragma once

// outcomes.csv, one row per scenario of a planned run (docs/outputs.md): its columns listed once
// (ScenarioOutcome::visit_fields), for its writer (workflow::run_scenarios, through
// run_outcomes_csv) and its typed reader (read_run_outcomes, through which the report reads it). In
// `results` because the report, below `workflow`, reads it.

#include <filesystem>
#include <string>
#include <vector>

namespace emrm::results {

/// Marks a column that is blank for an infeasible scenario (and read back as 0 from a blank).
struct FeasibleOnly {};
inline constexpr FeasibleOnly kFeasibleOnly{};

/// One scenario of a planned run and what the acceptance strategy made of it.
struct ScenarioOutcome {
  std::string id;
  std::string cell;
  std::vector<std::string> malfunctions;
  double weight = 1.0;
  bool feasible = false;  ///< the simulator could place the scene (else no outcome)
  std::string region;
  int success = 0;  ///< Y: 1 when the acceptance strategy avoided (or mitigated)
  std::string chosen_strategy;
  double impact_speed_kph = 0.0;
  int loss_level = 0;
  std::vector<double> factor_values;  ///< the scenario's factor columns, in file order

  /// The columns of outcomes.csv in order: `visit(column, field[, kFeasibleOnly])`; the factor
  /// columns, one per factor of the scenario file, where `factor_values` is visited. Numbers are
  /// written to six significant digits, flags as yes/no, lists as words.
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& visit) {
    visit("id", self.id);
    visit("cell", self.cell);
    visit("factors", self.factor_values);
    visit("malfunctions", self.malfunctions);
    visit("weight", self.weight);
    visit("feasible", self.feasible);
    visit("region", self.region);
    visit("success", self.success, kFeasibleOnly);
    visit("chosen_strategy", self.chosen_strategy);
    visit("impact_speed_kph", self.impact_speed_kph, kFeasibleOnly);
    visit("loss_level", self.loss_level, kFeasibleOnly);
  }
};

/// outcomes.csv's scenarios with the names of their factor columns.
struct RunOutcomes {
  std::vector<std::string> factors;
  std::vector<ScenarioOutcome> scenarios;
  std::vector<int> lines;  ///< read_run_outcomes: each scenario's line in the file, for messages
};

/// The text of outcomes.csv.
[[nodiscard]] std::string run_outcomes_csv(const RunOutcomes& outcomes);
/// Reads an outcomes.csv that run_outcomes_csv wrote: the header's fixed columns must be as it
/// writes them (the factor columns are those between `cell` and `malfunctions`). Throws InputError
/// at the file's line and column for another header, a row of another length or a value of the
/// wrong kind.
[[nodiscard]] RunOutcomes read_run_outcomes(const std::filesystem::path& path);

}  // namespace emrm::results
