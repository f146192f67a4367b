#pragma once

// The minimum scenario set (paper §V-B, docs/plan.md): the paper's five-step greedy
// construction, coverage first — (1) boundary seed (C2), (2) covering array over the
// influential factors (C3), (3) malfunction allocation (C4), (4) cell fill (C1) and risk-weighted
// top-up with proposal q ∝ √π, (5) stop when C1–C4 hold and every tracked cell's worst-case
// Wilson half-width is ≤ ε, or when the budget is spent.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "emrm/scenario/odd.hpp"

namespace emrm::scenario {

/// One planned test: a point of the ODD with its traceability.
struct Scenario {
  std::string id;                         ///< S001, S002, … in plan order
  std::string step;                       ///< boundary, covering_array, malfunction, cell_fill, top_up
  std::vector<double> values;             ///< one per ODD factor, in the ODD's order
  std::vector<int> cell;                  ///< α(values)
  std::vector<std::string> malfunctions;  ///< modes whose hazard region holds at the point
  std::vector<std::string> transitions;   ///< FSM transitions those modes exercise
  double weight = 1.0;                    ///< w = π(cell)/q(cell), q the plan's cell frequencies
  std::uint64_t seed = 0;                 ///< derive_seed(ODD seed, the point's key)
};

/// "c1.0.2.1.0": the levels of a cell.
[[nodiscard]] std::string cell_key(const std::vector<int>& cell);

/// A cell of the abstract domain where R_f and the constraints hold somewhere.
struct RelevantCell {
  std::vector<int> levels;
  std::vector<double> witness;  ///< an admissible point inside it
  double prior = 0.0;           ///< π(cell): product of the factors' priors, renormalised
  bool tracked = false;         ///< the ODD's `tracked` predicate holds somewhere in it
};

/// Every relevant cell, in odometer order (the last factor varies fastest). A cell is relevant
/// when an admissible point is found among its corners (upper corners taken just inside), its
/// centre and 16 seeded interior points. Throws InputError at the ODD when the abstract domain has
/// more than 200 000 cells.
[[nodiscard]] std::vector<RelevantCell> relevant_cells(const Odd& odd);

/// Boundary targets of C2: each numeric factor's bin edges and kinks, each class of a
/// categorical factor, as (factor, value) pairs.
struct BoundaryTarget {
  std::size_t factor = 0;
  double value = 0.0;
};
[[nodiscard]] std::vector<BoundaryTarget> boundary_targets(const Odd& odd);

/// Why a malfunction mode or a relevant cell has fewer tests than its target.
enum class ShortfallKind {
  kEmptyRegion,   ///< no admissible point of the mode's region exists (as far as every cell's probes show)
  kTooFewTests,   ///< the mode's region has admissible points, but fewer than n_m distinct ones were found
  kTooFewPoints,  ///< a relevant cell has fewer than n_c distinct admissible points
};

/// A target of C1 or C4 the plan could not meet, and why.
struct Shortfall {
  ShortfallKind kind = ShortfallKind::kTooFewTests;
  std::string subject;     ///< the mode's id or the cell's key
  std::size_t found = 0;   ///< tests the plan holds there
  std::size_t needed = 0;  ///< n_m or n_c
  std::string message;     ///< "malfunction UCA5: …", "cell c1.0.2: …", as printed
};

struct PlanStep {
  std::string name;
  std::size_t added = 0;
  std::string note;
};

struct Plan {
  std::vector<Scenario> scenarios;
  std::vector<PlanStep> steps;
  std::vector<RelevantCell> cells;  ///< 𝒞_f with priors and tracked flags
  std::size_t relevant_cells = 0;
  std::size_t tracked_cells = 0;
  std::size_t tests_per_tracked_cell = 0;  ///< from ε and δ (worst-case Wilson)
  std::vector<std::string> infeasible;     ///< boundary targets no admissible point reaches (C2 exempts them)
  std::vector<Shortfall> shortfalls;       ///< modes or cells that could not get enough distinct tests
  bool targets_met = false;                ///< C1–C4 and the precision target
  std::string stop_reason;
};

/// Builds the plan. Deterministic for equal ODD and seed. Validates the ODD first (validate(const
/// Odd&), sharing its relevant cells): throws core::ConfigError (an InputError) naming the field.
[[nodiscard]] Plan build_plan(const Odd& odd);

/// The malfunction modes whose region holds at `values`, and the transitions they exercise
/// (in first-seen order, without repeats).
void classify(const Odd& odd, const std::vector<double>& values, std::vector<std::string>& malfunctions,
              std::vector<std::string>& transitions);

}  // namespace emrm::scenario

template <>
struct emrm::core::EnumNames<emrm::scenario::ShortfallKind> {
  static constexpr std::array<std::pair<emrm::scenario::ShortfallKind, std::string_view>, 3> kNames{
      {{emrm::scenario::ShortfallKind::kEmptyRegion, "empty_region"},
       {emrm::scenario::ShortfallKind::kTooFewTests, "too_few_tests"},
       {emrm::scenario::ShortfallKind::kTooFewPoints, "too_few_points"}}};
};
