#pragma once

// One scenario cell under every strategy (docs/simulate.md): the outcome of each strategy, the
// unmitigated reference, the cell's region, and the traces through the EMRM and loss-evaluation
// FSMs. Pure: the same config, cell and seed give the same result on any thread.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/random.hpp"
#include "emrm/fsm/generator.hpp"
#include "emrm/sim/certificate.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/region.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {

struct StrategyOutcome {
  std::string strategy;
  bool avoided = false;
  bool contact = false;
  bool road_departure = false;
  ImpactAssessment impact;  ///< zeros when avoided
  int delta_loss = 0;       ///< unmitigated level − this outcome's level
  double min_ttc_s = 0.0;
  std::vector<std::string> fsm_trace;              ///< EMRM FSM: s0 e1 s1 e2 s2 …
  std::vector<std::string> loss_evaluation_trace;  ///< emrm only
  std::string chosen_strategy;                     ///< emrm only
  std::string adopted_from;                        ///< set when the outcome is another strategy's (see docs)
  Evidence evidence = Evidence::kWitness;
  PlannerStats planner;
  /// The executed trajectory at every integration step, from t = 0 (the witness's trajectory).
  std::vector<PathPoint> path;
  Maneuver maneuver;           ///< the controls that drove it: replay() reproduces `path`
  std::vector<TreeEdge> tree;  ///< when trees are kept
};

struct CellResult {
  CellInput input;
  bool feasible = false;
  Region region = Region::kInfeasible;
  /// G and Y: a witness; O and R: a certificate of unavoidability, or undecided without one.
  Evidence evidence = Evidence::kWitness;
  /// O and R only: what backs the split (MitigationEvidence); kNone otherwise.
  MitigationEvidence mitigation_evidence = MitigationEvidence::kNone;
  /// The searches were strengthened (restarts with seeds independent of the cell's, the reference
  /// planner) because the first found no avoidance and no certificate settles the cell.
  bool strengthened = false;
  /// The proof that nothing avoids the truck, when the cell has one (O and R cells only).
  std::optional<Certificate> certificate;
  /// An undecided O or R cell whose scene cannot carry a certificate: why (sim::no_certificate_bound:
  /// a vehicle model or time step without the bound); empty otherwise.
  std::string no_certificate;
  ImpactAssessment unmitigated;
  /// Mitigation within a level: the unmitigated reference's P(MAIS3+) and P(fatal) minus the best
  /// (lowest) of the strategies' (0 when there is no risk; the reference's own when one avoids).
  double p_mais3_reduction = 0.0;
  double p_fatal_reduction = 0.0;
  std::vector<StrategyOutcome> strategies;  ///< in the order asked for
};

/// The shipped FSMs (compiled in from examples/tjunction/*.yaml).
[[nodiscard]] const fsm::Generator& default_emrm_fsm();
[[nodiscard]] const fsm::Generator& default_loss_evaluation_fsm();

/// The registered strategies' names in evaluation order (strategy.hpp); shipped: emergency_stop,
/// dodge, drift_to_avoid, drift_to_accident, emrm, best_strategy.
[[nodiscard]] std::vector<std::string> strategy_names();
/// Whether `name` is a registered strategy.
[[nodiscard]] bool known_strategy(std::string_view name);
/// "unknown strategy 'emergency_stpo' (did you mean 'emergency_stop'?); expected one of: …": what
/// every reader of a strategy name says of one that is not registered.
[[nodiscard]] std::string unknown_strategy_message(std::string_view name);
/// Throws UsageError naming the registered strategies when `name` is not one (the CLI's "all" besides).
void validate_strategy(std::string_view name);

struct CellOptions {
  std::vector<std::string> strategies = strategy_names();
  std::uint64_t seed = 1;
  bool keep_trees = false;
  /// When no search avoids and nothing proves the cell unavoidable, search again (docs/planner.md,
  /// "A region that does not depend on the seed") before calling the cell undecided.
  bool strengthen = true;
  /// Try to prove the cell unavoidable first (certificate.hpp); a certified cell skips the
  /// avoidance searches. Off: every search runs (for checking certificates).
  bool certify = true;
  const fsm::Generator* emrm_fsm = nullptr;             ///< default_emrm_fsm() when null
  const fsm::Generator* loss_evaluation_fsm = nullptr;  ///< default_loss_evaluation_fsm() when null
};

/// Simulates one cell: every registered strategy in evaluation order (strategy.hpp; the choosers
/// only when one of them is in `options.strategies`), then the region. Infeasible cells are returned with no strategies
/// simulated. Throws core::ConfigError (an InputError) for a scene validate(config) rejects, UsageError for an unknown
/// strategy in `options` or a cell the scene rejects (validate_cell).
[[nodiscard]] CellResult simulate_cell(const SceneConfig& config, const CellInput& cell, const CellOptions& options);

/// Seeds of strategies and cells (core/random.hpp).
using core::derive_seed;

}  // namespace emrm::sim
