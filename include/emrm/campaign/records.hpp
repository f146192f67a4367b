#pragma once

// What a campaign stores per cell and per strategy: plain rows, the common currency of the
// results store, the exports and the aggregation (tables, KPIs, diagnostics).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/enum_names.hpp"
#include "emrm/sim/factors.hpp"
#include "emrm/sim/region.hpp"

namespace emrm::campaign {

/// What backs a cell's region: a simulated cell's sim::Evidence (witness, certificate, undecided),
/// an adaptive sweep's inference (inferred), or nothing (an infeasible cell, named "").
enum class CellEvidence : std::uint8_t { kNone, kWitness, kCertificate, kUndecided, kInferred };
/// The CellEvidence of a simulated feasible cell.
[[nodiscard]] CellEvidence cell_evidence(sim::Evidence e) noexcept;

/// How a cell's region was found: by simulating it, or inferred by an adaptive sweep.
enum class CellMethod : std::uint8_t { kSimulated, kInferred };

/// A field of a record whose +infinity is kept as NULL (a store's column, a JSON null).
struct InfinityIsNull {};
inline constexpr InfinityIsNull kInfinityIsNull{};

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
  sim::Evidence evidence = sim::Evidence::kWitness;
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

  /// The record's field list (docs/architecture.md, "The record field list"): `visit(name, field)`
  /// for each field a row of the store's outcomes table holds, in its column order, with
  /// kInfinityIsNull where +infinity is kept as NULL. The store's columns, its writer and reader
  /// and the MPI wire are made from it; the trajectories (path and trees) are kept apart, in their
  /// own table. `self` is an OutcomeRecord, const or not.
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& visit) {
    visit("strategy", self.strategy);
    visit("avoided", self.avoided);
    visit("contact", self.contact);
    visit("road_departure", self.road_departure);
    visit("impact_speed_kph", self.impact_speed_kph);
    visit("delta_v_kph", self.delta_v_kph);
    visit("p_mais3", self.p_mais3);
    visit("p_fatal", self.p_fatal);
    visit("loss_level", self.loss_level);
    visit("delta_loss", self.delta_loss);
    visit("min_ttc_s", self.min_ttc_s, kInfinityIsNull);
    visit("planner_nodes", self.planner_nodes);
    visit("planner_rollouts", self.planner_rollouts);
    visit("fsm_trace", self.fsm_trace);
    visit("loss_evaluation_trace", self.loss_evaluation_trace);
    visit("chosen_strategy", self.chosen_strategy);
    visit("adopted_from", self.adopted_from);
    visit("evidence", self.evidence);
    visit("maneuver", self.maneuver);
  }
};

/// One cell of a grid with its unmitigated reference, region and outcomes.
struct CellRecord {
  std::string grid;
  std::int64_t index = 0;  ///< position of the cell in its grid's expansion order
  sim::CellInput factors;  ///< the cell's factor values, in the order of the scene's factor table
  std::uint64_t seed = 0;
  bool feasible = false;
  sim::Region region = sim::Region::kInfeasible;
  double unmitigated_impact_speed_kph = 0.0;
  double unmitigated_delta_v_kph = 0.0;
  double unmitigated_p_mais3 = 0.0;
  double unmitigated_p_fatal = 0.0;
  int unmitigated_loss_level = 0;
  CellEvidence evidence = CellEvidence::kNone;                                   ///< of the region
  sim::MitigationEvidence mitigation_evidence = sim::MitigationEvidence::kNone;  ///< O and R
  bool strengthened = false;                                                     ///< the searches were strengthened
  std::string certificate;              ///< the unavoidability certificate as JSON text, when there is one
  double p_mais3_reduction = 0.0;       ///< unmitigated P(MAIS3+) minus the best strategy's
  double p_fatal_reduction = 0.0;       ///< the same for P(fatal)
  std::vector<OutcomeRecord> outcomes;  ///< in the campaign's strategy order; none for an inferred cell
  /// Simulated, or inferred by an adaptive sweep (docs/adaptive.md): then only the region is known
  /// (evidence kInferred, no outcomes, the unmitigated reference not computed).
  CellMethod method = CellMethod::kSimulated;
  /// An inferred cell's grounds: the indices (in its grid) of the simulated cells that bound it;
  /// empty when the analytic stop boundary alone makes it G.
  std::vector<std::int64_t> inferred_from;

  /// The record's field list, as OutcomeRecord's: `visit(name, field)` for each field a row of the
  /// store's cells table holds, in its column order. The factors are one field, a column per
  /// factor of the scene (named by the factor table's keys); the outcomes are OutcomeRecord's rows.
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& visit) {
    visit("grid", self.grid);
    visit("cell_index", self.index);
    visit("factors", self.factors);
    visit("seed", self.seed);
    visit("feasible", self.feasible);
    visit("region", self.region);
    visit("unmitigated_impact_speed_kph", self.unmitigated_impact_speed_kph);
    visit("unmitigated_delta_v_kph", self.unmitigated_delta_v_kph);
    visit("unmitigated_p_mais3", self.unmitigated_p_mais3);
    visit("unmitigated_p_fatal", self.unmitigated_p_fatal);
    visit("unmitigated_loss_level", self.unmitigated_loss_level);
    visit("evidence", self.evidence);
    visit("mitigation_evidence", self.mitigation_evidence);
    visit("strengthened", self.strengthened);
    visit("certificate", self.certificate);
    visit("p_mais3_reduction", self.p_mais3_reduction);
    visit("p_fatal_reduction", self.p_fatal_reduction);
    visit("method", self.method);
    visit("inferred_from", self.inferred_from);
  }

  /// Feasible and simulated, not inferred: the unmitigated reference and the harm reduction are known.
  [[nodiscard]] bool simulated() const noexcept { return feasible && method == CellMethod::kSimulated; }
  /// Feasible and inferred by an adaptive sweep: a region, no outcomes.
  [[nodiscard]] bool inferred() const noexcept { return feasible && method == CellMethod::kInferred; }
  /// The outcome of `strategy`, or null when the cell has none (an inferred cell, a strategy not run).
  [[nodiscard]] const OutcomeRecord* outcome(std::string_view strategy) const noexcept {
    for (const auto& o : outcomes)
      if (o.strategy == strategy) return &o;
    return nullptr;
  }
};

}  // namespace emrm::campaign

template <>
struct emrm::core::EnumNames<emrm::campaign::CellEvidence> {
  static constexpr std::array kNames{std::pair{campaign::CellEvidence::kNone, std::string_view("")},
                                     std::pair{campaign::CellEvidence::kWitness, std::string_view("witness")},
                                     std::pair{campaign::CellEvidence::kCertificate, std::string_view("certificate")},
                                     std::pair{campaign::CellEvidence::kUndecided, std::string_view("undecided")},
                                     std::pair{campaign::CellEvidence::kInferred, std::string_view("inferred")}};
};
template <>
struct emrm::core::EnumNames<emrm::campaign::CellMethod> {
  static constexpr std::array kNames{std::pair{campaign::CellMethod::kSimulated, std::string_view("simulated")},
                                     std::pair{campaign::CellMethod::kInferred, std::string_view("inferred")}};
};
