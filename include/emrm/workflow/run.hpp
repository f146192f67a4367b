#pragma once

// Running a planned scenario set (`emrm run`, docs/plan.md): every scenario of a scenarios.csv
// simulated once through the campaign engine (same store, resume, threads, determinism), then
// the statistics of the paper's §V-B — per-cell Wilson intervals, Hoeffding bounds and the
// weighted estimator Ŝ(A) — the FSM transitions the runs actually exercised, and the
// traceability matrix with its scenarios column filled.

#include <cstddef>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "emrm/campaign/plan_settings.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/results/run_estimates.hpp"
#include "emrm/results/run_outcomes.hpp"
#include "emrm/scenario/statistics.hpp"

namespace emrm::workflow {

struct RunOptions {
  std::filesystem::path scenarios_csv;
  std::filesystem::path output_dir;
  std::optional<std::filesystem::path> safety_file;  ///< default: the plan's (scenarios.json)
  int threads = 0;
  bool progress = true;
  /// An actuation profile overlaying the plan's scene (sim::apply_profile; a NAME is looked up in
  /// the scene's profiles/ folder). Empty: the scene as it is.
  std::string profile;
  /// Other processes that simulate scenarios beside this one's threads (SweepOptions::distributor);
  /// borrowed. Null: this process alone.
  campaign::Distributor* distributor = nullptr;
};

/// One scenario and what the acceptance strategy made of it: a row of outcomes.csv.
using ScenarioOutcome = results::ScenarioOutcome;

struct CellEstimate {
  std::string cell;
  std::size_t n = 0;
  std::size_t successes = 0;
  scenario::Interval wilson;
  double hoeffding_epsilon = 1.0;  ///< at the plan's δ
  bool tracked = false;
  std::vector<std::pair<std::string, std::string>> levels;  ///< (factor, bin label); empty when unknown
};

struct SubsetEstimate {
  std::string subset;  ///< "all", a malfunction id
  scenario::WeightedEstimate estimate;
  std::string shortfall;  ///< the plan's shortfall for this mode, if any
};

struct RunResult {
  campaign::SweepSummary sweep;
  std::vector<std::string> factors;                      ///< the scenario file's factor columns
  std::vector<std::string> unsimulated_factors;          ///< factor columns the simulator has no use for
  std::vector<ScenarioOutcome> outcomes;                 ///< in file order
  std::vector<CellEstimate> cells;                       ///< by cell key
  double widest_tracked_half_width = 0.0;                ///< largest Wilson half-width over tracked cells
  double epsilon = 0.25;                                 ///< the plan's target for it
  std::vector<SubsetEstimate> subsets;                   ///< Ŝ(A): all, then each malfunction (every mode of the plan)
  std::vector<campaign::PlanShortfall> plan_shortfalls;  ///< the plan's, repeated as warnings
  std::size_t transitions_exercised = 0;                 ///< EMRM FSM transitions the traces took
  std::size_t transitions_total = 0;
  std::vector<std::string> transitions_missed;
  std::size_t traceability_rows = 0;  ///< 0 when no safety case is known
  double confidence = 0.95;
};

/// Runs the scenarios into OPTIONS.output_dir (results.sqlite and the sweep's exports, then
/// outcomes.csv, estimates.csv, estimates.json and — with a safety case — traceability.csv/.md).
/// estimates.json records where the plan lives ("plan": its scenarios.csv and coverage.json,
/// relative to the output folder) and the plan's shortfalls.
/// Every input (the scenarios, scenarios.json, the scene, the profile, the safety case) is read
/// before the store is opened, so bad input writes nothing; the files after the sweep are written
/// all or none (core::write_files).
/// Throws InputError for a bad scenarios file (line:column) or one whose values the simulator
/// rejects; UsageError when the store holds another plan.
RunResult run_scenarios(const RunOptions& options);

/// What estimates.json holds of the run (results/run_estimates.hpp), without what run_scenarios adds
/// from the plan: the acceptance criterion, the ODD's factors and where the plan lives.
[[nodiscard]] results::RunEstimates estimates_of(const RunResult& result);

/// The summary `emrm run` prints: the plan's shortfalls as warnings, scenarios and what was simulated, the
/// widest tracked Wilson half-width, Ŝ(A) per subset with tests, the EMRM FSM transitions exercised and the
/// files written into `output_dir`. `scenarios_file` is shown as given.
[[nodiscard]] std::string to_text(const RunResult& result, const std::string& scenarios_file,
                                  const std::filesystem::path& output_dir);

}  // namespace emrm::workflow
