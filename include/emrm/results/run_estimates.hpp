#pragma once

// estimates.json, what `emrm run` estimated of a planned scenario set (docs/plan.md): its fields
// listed once (serialize), for its writer (workflow::run_scenarios, through core::write_json) and
// its typed reader (read_run_estimates, through which the report reads it). In `results` because
// the report, below `workflow`, reads it.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "emrm/campaign/plan_settings.hpp"
#include "emrm/core/json_archive.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/scenario/statistics.hpp"

namespace emrm::results {

/// Ŝ(A) over one subset A (all, or a malfunction's region) as estimates.json lists it.
struct SubsetSuccess {
  std::size_t n = 0;                     ///< tests in A
  double weight = 0.0;                   ///< Σ w
  double n_eff = 0.0;                    ///< Kish's effective sample size
  std::optional<double> estimate;        ///< none when A holds no test
  scenario::Interval wilson;             ///< at n_eff
  std::optional<std::string> shortfall;  ///< the plan's shortfall for the mode

  template <class A>
  void serialize(A& a) {
    a.required("n", n);
    a.required("weight", weight);
    a.required("n_eff", n_eff);
    a.required("estimate", estimate);
    a.required("wilson", wilson);
    a.optional("shortfall", shortfall);
  }
};

/// One cell of the ODD: the acceptance criterion's successes among its tests.
struct CellSuccess {
  std::string cell;
  std::vector<std::pair<std::string, std::string>> levels;  ///< (factor, bin label); empty when unknown
  std::size_t n = 0;
  std::size_t successes = 0;
  scenario::Interval wilson;
  double hoeffding_epsilon = 1.0;  ///< at the plan's δ
  bool tracked = false;            ///< has a precision target

  template <class A>
  void serialize(A& a) {
    a.required("cell", cell);
    a.required("levels", levels);
    a.required("n", n);
    a.required("successes", successes);
    a.required("wilson", wilson);
    a.required("hoeffding_epsilon", hoeffding_epsilon);
    a.required("tracked", tracked);
  }
};

/// The EMRM FSM's transitions that the runs' traces took.
struct FsmTransitions {
  std::size_t exercised = 0;
  std::size_t total = 0;
  std::vector<std::string> missed;

  template <class A>
  void serialize(A& a) {
    a.required("exercised", exercised);
    a.required("total", total);
    a.required("missed", missed);
  }
};

/// The acceptance criterion: `strategy` avoids the collision, or (outcome "mitigated") lowers the loss.
struct Acceptance {
  std::string strategy;
  std::string outcome;

  template <class A>
  void serialize(A& a) {
    a.required("strategy", strategy);
    a.required("outcome", outcome);
  }
};

/// Where the plan lives, relative to the run's folder.
struct PlanLocation {
  std::string scenarios;                ///< its scenarios.csv
  std::optional<std::string> coverage;  ///< its coverage.json, when it has one

  template <class A>
  void serialize(A& a) {
    a.required("scenarios", scenarios);
    a.required("coverage", coverage);
  }
};

struct RunEstimates {
  std::size_t scenarios = 0;
  std::size_t feasible = 0;
  double confidence = 0.95;
  std::vector<std::string> unsimulated_factors;  ///< factor columns the simulator has no use for
  /// Ŝ(A) by subset: all, then each malfunction of the plan.
  std::vector<std::pair<std::string, SubsetSuccess>> weighted_success;
  double widest_wilson_half_width = 0.0;
  std::size_t tracked_cells = 0;
  double widest_tracked_wilson_half_width = 0.0;
  double epsilon = 0.25;  ///< the plan's target for a tracked cell's Wilson half-width
  std::vector<CellSuccess> cells;
  FsmTransitions fsm_transitions;
  std::size_t traceability_rows = 0;  ///< 0 when no safety case is known
  std::vector<campaign::PlanShortfall> shortfalls;
  std::optional<Acceptance> acceptance;                      ///< from the plan
  std::optional<std::vector<scenario::PlanFactor>> factors;  ///< the plan's ODD factors
  std::optional<PlanLocation> plan;

  template <class A>
  void serialize(A& a) {
    a.required("scenarios", scenarios);
    a.required("feasible", feasible);
    a.required("confidence", confidence);
    a.required("unsimulated_factors", unsimulated_factors);
    a.required("weighted_success", weighted_success);
    a.required("widest_wilson_half_width", widest_wilson_half_width);
    a.required("tracked_cells", tracked_cells);
    a.required("widest_tracked_wilson_half_width", widest_tracked_wilson_half_width);
    a.required("epsilon", epsilon);
    a.required("cells", cells);
    a.required("fsm_transitions", fsm_transitions);
    a.required("traceability_rows", traceability_rows);
    a.required("shortfalls", shortfalls);
    a.optional("acceptance", acceptance);
    a.optional("factors", factors);
    a.optional("plan", plan);
  }
};

/// The text of estimates.json (two-space indents, a final newline).
[[nodiscard]] std::string run_estimates_text(const RunEstimates& estimates);
/// Reads an estimates.json; throws InputError (file:line:column) for what is missing, misspelt or
/// of the wrong type.
[[nodiscard]] RunEstimates read_run_estimates(const std::filesystem::path& path);

/// The estimates.json of the planned run in a results folder, read once for every part of the
/// report that shows it.
struct FoundRunEstimates {
  std::filesystem::path file;             ///< DIR/plan_results/estimates.json or DIR/estimates.json; empty: none
  std::optional<RunEstimates> estimates;  ///< none when there is no file or it could not be read
  std::string error;                      ///< why `file` could not be read (the InputError's message)
};

/// DIR/plan_results/estimates.json (emrm reproduce) or DIR/estimates.json (emrm run), the first of
/// the two that exists and is not empty, read by read_run_estimates. Never throws InputError: a
/// file not in the form `emrm run` writes is returned with its error.
[[nodiscard]] FoundRunEstimates find_run_estimates(const std::filesystem::path& dir);

}  // namespace emrm::results

/// A Wilson interval as [low, high].
template <>
struct emrm::core::YamlCodec<emrm::scenario::Interval> {
  static void read(const YamlNode& n, scenario::Interval& v) {
    const auto bounds = n.elements();
    if (bounds.size() != 2) n.fail("expected an interval [low, high], got " + n.describe());
    v = {bounds[0].as_double(), bounds[1].as_double()};
  }
  static YAML::Node write(const scenario::Interval& v) {
    YAML::Node out(YAML::NodeType::Sequence);
    out.push_back(v.low);
    out.push_back(v.high);
    return out;
  }
};
template <>
struct emrm::core::JsonCodec<emrm::scenario::Interval> {
  static nlohmann::ordered_json write(const scenario::Interval& v) { return {v.low, v.high}; }
};
