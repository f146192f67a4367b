#pragma once

// The figures of a planned run (`emrm run`, docs/report.md): a map per pair of the ODD's factors
// and the sweep curves by the ODD's bins, from the run's outcomes.csv, estimates.json and store.
// They group scenarios by the cells the plan put them in, never by their exact values.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/results/run_estimates.hpp"

namespace emrm::report {

/// One planned scenario as run.
struct PlannedScenario {
  std::string id;
  std::vector<int> levels;  ///< its cell: one level per factor of PlannedRun::factors
  bool feasible = false;
  int success = 0;              ///< Y of the plan's acceptance rule (outcomes.csv)
  campaign::CellRecord record;  ///< its cell of the results store
};

/// A planned run as its figures read it.
struct PlannedRun {
  std::filesystem::path folder;            ///< where outcomes.csv, estimates.json and results.sqlite are
  std::vector<PlanFactor> factors;         ///< the ODD's, in the order of the cell keys; empty when unknown
  std::vector<PlannedScenario> scenarios;  ///< in file order
  double confidence = 0.95;                ///< of the Wilson intervals (estimates.json)
  std::string acceptance;                  ///< "emrm avoided": strategy and outcome that count as success
};

/// The planned run of the estimates.json that results::find_run_estimates found (in
/// `dir/plan_results`, emrm reproduce, or `dir`, emrm run), with the outcomes.csv and store beside
/// it; nullopt when there is none, it could not be read (the report's statistics section says what
/// is wrong with it) or no outcomes.csv is beside it. Factors are empty when estimates.json lists none (a run of a
/// scenarios.csv without the plan's scenarios.json beside it). Throws InputError
/// (file:line:column) when outcomes.csv is malformed or a cell key does not match the factors,
/// UsageError when the store and outcomes.csv disagree on the number of scenarios.
[[nodiscard]] std::optional<PlannedRun> read_planned_run(const results::FoundRunEstimates& estimates);

/// (1e) One map per pair of the run's factors that have two levels or more, in the ODD's order
/// (at most `max_maps`; then one more Figure, plan_map_more, has no files and a note naming the
/// pairs left out). Each map is a grid of the two factors' levels, pooled over the other factors:
/// a rectangle coloured by the share of its feasible scenarios that succeed (red 0 to green 1),
/// labelled successes/feasible and the Wilson interval at the run's confidence; grey when all its
/// scenarios are infeasible, blank when the plan put none there; a cross when one of them is
/// undecided. Stems plan_map_A_B. CSV columns: factor_x, level_x, bin_x, factor_y, level_y, bin_y,
/// scenarios, feasible, successes, rate, wilson_low, wilson_high, undecided.
std::vector<Figure> draw_plan_maps(const PlannedRun& run, const std::filesystem::path& dir, std::size_t max_maps = 15);

/// (4b) The run's sweep curves by the ODD's bins (draw_binned_sweep_curves) of the ego speed (the
/// factor `factors` has in that role), or of the first factor with two levels or more when the ODD
/// does not vary it. A note instead when the factors are unknown or none has two levels. `name` is
/// the figure's stem.
Figure draw_plan_sweep_curves(const PlannedRun& run, const sim::FactorTable& factors, const std::filesystem::path& dir,
                              const std::string& name = "sweep_curves");

}  // namespace emrm::report
