#pragma once

// Diagnostics of a campaign's results (docs/results.md): checks that the regions and outcomes are
// what physics and our own reference planner say they must be, and which FSM transitions the
// campaign exercised. Everything reads stored records; only the RRT-vs-reference check simulates
// (the reference planner on a seeded sample of cells).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/fsm/generator.hpp"
#include "emrm/fsm/operations.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::results {

/// A cell named in a diagnostic.
struct CellRef {
  std::string grid;
  std::int64_t index = 0;
  sim::CellInput factors;
  sim::Region region = sim::Region::kInfeasible;
};
[[nodiscard]] CellRef cell_ref(const campaign::CellRecord& r);

/// (a) The analytic stop boundary TTC >= L + v/(2 mu g) (through the actuators:
/// v·TTC >= their stopping distance) against the stored regions.
struct StopBoundaryCheck {
  /// Whether the scene's family has the boundary (sim::stop_boundary_applies); when not, nothing
  /// below is checked and only `feasible` is counted.
  bool applies = true;
  double latency_s = 0.0;  ///< perception latency
  sim::ActuationConfig actuation;
  std::size_t feasible = 0;
  std::size_t stoppable = 0;                 ///< feasible cells above the boundary
  std::vector<CellRef> stoppable_red;        ///< must be empty: a car that can stop is never R
  std::vector<CellRef> stoppable_not_green;  ///< above the boundary but not G (R included)
  std::vector<CellRef> green_not_stoppable;  ///< G below the boundary, the hazard in the car's path
  /// G below the boundary where the hazard never stands in the car's straight path for certain
  /// (sim::hazard_in_the_way: it leaves the lane free, or keeps going): braking need not stop short
  /// of it, so these are no contradiction. Only with a scene; without one they count above.
  std::vector<CellRef> green_clear_path;
};
[[nodiscard]] StopBoundaryCheck check_stop_boundary(const std::vector<campaign::CellRecord>& records,
                                                    double latency_s = 0.0);
[[nodiscard]] StopBoundaryCheck check_stop_boundary(const std::vector<campaign::CellRecord>& records,
                                                    const sim::ActuationConfig& actuation);
/// The same through the scene's actuators, a G cell below the boundary told apart by whether the
/// scene's hazard stands in the car's path (green_not_stoppable) or not (green_clear_path).
[[nodiscard]] StopBoundaryCheck check_stop_boundary(const std::vector<campaign::CellRecord>& records,
                                                    const sim::SceneConfig& scene);

/// (b) One monotonicity reversal: a strategy avoided at a lower TTC (or μ) but not at the next
/// higher one, all other factors equal.
struct Reversal {
  std::string grid, strategy, factor;  ///< factor: ttc or mu
  CellRef lower, higher;
};
struct ReversalCount {
  std::string grid, strategy, factor;
  std::size_t pairs = 0;  ///< adjacent feasible pairs compared
  std::size_t reversals = 0;
};
struct MonotonicityCheck {
  std::vector<ReversalCount> counts;  ///< per grid × strategy × factor with at least one pair
  std::vector<Reversal> examples;     ///< every reversal, up to `max_examples`
  std::size_t total_reversals = 0;
};
/// Groups each grid's feasible cells by every factor but TTC (then but μ), sorts each group by the
/// varying factor and compares neighbours, per strategy.
[[nodiscard]] MonotonicityCheck check_monotonicity(const std::vector<campaign::CellRecord>& records,
                                                   std::size_t max_examples = 50);

/// (c) The stored RRT outcomes against the reference planner on a sample of cells.
struct ReferenceDisagreement {
  CellRef cell;
  std::string strategy;  ///< a checked strategy (reference_checked_strategies)
  bool reference_avoids = false;
  bool stored_avoided = false;
};
/// One checked strategy's counts over the sample.
struct ReferenceCounts {
  std::string strategy;
  std::size_t reference_avoids = 0;  ///< cells the reference planner avoids with its limits
  std::size_t missed = 0;            ///< the reference avoids, the stored outcome did not
  std::size_t beyond_reference = 0;  ///< the stored outcome avoided, the reference did not
};
struct ReferenceCheck {
  std::size_t sampled = 0;
  std::uint64_t seed = 0;
  std::vector<ReferenceCounts> strategies;           ///< in evaluation order
  std::vector<ReferenceDisagreement> disagreements;  ///< both directions
  /// The counts of that strategy, or nullptr when it was not checked.
  [[nodiscard]] const ReferenceCounts* of(std::string_view strategy) const noexcept;
};
/// The strategies the check compares: every registered strategy that searches for an avoidance of
/// its own with a planner (a planner set, contact not accepted), in evaluation order; shipped: dodge
/// and drift_to_avoid.
[[nodiscard]] std::vector<sim::StrategyInfo> reference_checked_strategies();
/// Runs sim::plan_reference with each checked strategy's control limits on `sample` feasible
/// cells drawn without replacement (seeded; all of them when there are fewer) from the records that
/// have stored outcomes of every checked strategy. `threads` <= 0: hardware concurrency. Throws
/// core::ConfigError for a scene sim::validate rejects, and what the simulator throws for a cell
/// that does not fit `scene`.
[[nodiscard]] ReferenceCheck check_against_reference(const std::vector<campaign::CellRecord>& records,
                                                     const sim::SceneConfig& scene, std::size_t sample,
                                                     std::uint64_t seed, int threads = 0);

/// (d) Transition coverage of one FSM by the stored traces.
struct FsmCoverage {
  std::string fsm;  ///< the generator's name
  std::size_t traces = 0;
  fsm::TransitionCoverage coverage;
  std::vector<fsm::Transition> transitions;   ///< g.transitions(), for the report
  const fsm::Generator* generator = nullptr;  ///< borrowed: the machine measured, for diagrams
};
/// The events of a stored trace "s0 e1 s1 e2 s2 …": the elements at odd positions.
[[nodiscard]] std::vector<std::string> trace_events(const std::vector<std::string>& trace);
/// Coverage of `g` by every outcome's fsm_trace (all strategies) of the feasible records.
[[nodiscard]] FsmCoverage emrm_fsm_coverage(const std::vector<campaign::CellRecord>& records, const fsm::Generator& g);
/// Coverage of `g` by the emrm outcomes' loss_evaluation_trace of the feasible records.
[[nodiscard]] FsmCoverage loss_evaluation_fsm_coverage(const std::vector<campaign::CellRecord>& records,
                                                       const fsm::Generator& g);

struct DiagnosticsOptions {
  std::size_t reference_sample = 40;
  std::uint64_t seed = 1;
  int threads = 0;
};

struct Diagnostics {
  sim::FactorTable factors;  ///< the scene's: how the cells named are written
  StopBoundaryCheck stop_boundary;
  MonotonicityCheck monotonicity;
  ReferenceCheck reference;
  FsmCoverage emrm_fsm, loss_evaluation_fsm;
};

/// All four diagnostics, with the shipped FSMs (sim::default_emrm_fsm(),
/// sim::default_loss_evaluation_fsm()) and the scene's latency.
[[nodiscard]] Diagnostics run_diagnostics(const std::vector<campaign::CellRecord>& records,
                                          const sim::SceneConfig& scene, const DiagnosticsOptions& options = {});

[[nodiscard]] nlohmann::ordered_json to_json(const Diagnostics& d);

/// One paragraph for a terminal: the stop boundary's contradictions, the monotonicity reversals,
/// the reference planner's sample with what the RRT missed per strategy, the FSM coverage.
[[nodiscard]] std::string summary(const Diagnostics& d);

/// True when the stored regions contradict the analytic stop boundary: a cell that can stop
/// classified R, or a G cell below the boundary. Reversals and RRT misses are reported, not errors.
[[nodiscard]] bool contradicts_physics(const Diagnostics& d) noexcept;

/// Writes DIR/diagnostics.json and DIR/fsm/{emrm_fsm,loss_evaluation_fsm}.dot, plus the .svg files
/// when Graphviz is installed, the transitions coloured by their coverage counts; every file is
/// rendered first, then all are written or none (core::write_files). Returns the files written.
/// Throws emrm::Error when a file cannot be written or Graphviz fails.
std::vector<std::filesystem::path> write_diagnostics(const std::filesystem::path& dir, const Diagnostics& d);

/// What a diagnostics.json says, as the report shows it: the counts of each check (the cells named
/// and the definitions left in the file).
struct DiagnosticsSummary {
  bool stop_boundary = true;  ///< whether the family has the boundary (StopBoundaryCheck::applies)
  std::size_t feasible = 0, stoppable = 0, stoppable_red = 0, green_not_stoppable = 0;
  std::size_t total_reversals = 0;
  std::vector<ReversalCount> reversal_counts;
  std::size_t sampled = 0;
  std::uint64_t seed = 0;
  std::vector<ReferenceCounts> reference;  ///< per checked strategy, in the file's order
  struct Coverage {
    std::string name;  ///< emrm_fsm, loss_evaluation_fsm
    std::size_t covered = 0, total = 0, traces = 0;
  };
  std::vector<Coverage> fsm_coverage;
};
/// Reads a diagnostics.json that write_diagnostics wrote; throws InputError at the file's line and
/// column for a member missing or of the wrong type.
[[nodiscard]] DiagnosticsSummary read_diagnostics_summary(const std::filesystem::path& path);

}  // namespace emrm::results
