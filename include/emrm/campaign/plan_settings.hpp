#pragma once

// What a planned scenario set says beyond its scenarios.csv (scenarios.json beside it, written by
// scenario::write_plan): the campaign engine reads it to run the plan as a one-grid campaign
// (`emrm run`), and `emrm export --plan` to export it.

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "emrm/scenario/plan_io.hpp"

namespace emrm::campaign {

/// The grid a run stores its scenarios in: cell i is the scenario on row i of scenarios.csv.
inline constexpr const char* kPlanGrid = "plan";

/// A target the plan fell short of (scenarios.json's `stop.shortfalls`), repeated by `emrm run`.
struct PlanShortfall {
  std::string kind;     ///< empty_region, too_few_tests, too_few_points (empty in older plans)
  std::string subject;  ///< the mode's id or the cell's key (empty in older plans)
  std::string message;

  template <class A>
  void serialize(A& a) {
    a.required("kind", kind);
    a.required("subject", subject);
    a.required("message", message);
  }
};

/// What a plan says beyond its CSV (read from scenarios.json beside it, when present).
struct PlanSettings {
  std::optional<std::filesystem::path> safety_file;
  std::optional<std::filesystem::path> scene_file;
  std::vector<std::string> strategies;         ///< empty: all
  std::string acceptance_strategy;             ///< empty: the registered chooser (EMRM)
  std::string acceptance_outcome = "avoided";  ///< avoided or mitigated
  double delta = 0.05;
  double epsilon = 0.25;
  std::uint64_t seed = 1;
  std::set<std::string> tracked_cells;  ///< cell keys with a precision target
  /// Each cell's bins as (factor, bin label) in the plan's factor order (scenarios.json "cells").
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> cell_levels;
  /// The ODD's factors with their levels, as scenarios.json lists them (none without them): copied
  /// into estimates.json, so that the report groups the run by the ODD's bins.
  std::optional<std::vector<scenario::PlanFactor>> factors;
  std::vector<std::string> malfunctions;  ///< every mode of the plan, in plan order
  std::vector<PlanShortfall> shortfalls;
};

/// Reads scenarios.json; throws InputError when it is malformed or names an unknown strategy.
[[nodiscard]] PlanSettings read_plan_settings(const std::filesystem::path& scenarios_json);

/// The acceptance strategy of a plan that names none: the registered chooser (EMRM), or empty.
[[nodiscard]] std::string default_acceptance_strategy();

}  // namespace emrm::campaign
