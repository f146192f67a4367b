#pragma once

// The files of a plan (docs/plan.md): scenarios.csv (one row per scenario, the input of
// `emrm run`), scenarios.json (the same with the plan's settings and steps) and coverage.json.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "emrm/core/error.hpp"
#include "emrm/scenario/plan.hpp"

namespace emrm::scenario {

/// Columns: id, step, one per factor, cell, malfunctions (space-separated), transitions
/// ("; "-separated), weight, seed.
[[nodiscard]] std::string scenarios_csv(const Odd& odd, const Plan& plan);
/// {"odd", "settings", "steps", "stop", "scenarios": [...]}.
[[nodiscard]] nlohmann::ordered_json scenarios_json(const Odd& odd, const Plan& plan);

/// One row of a scenarios.csv as read back.
struct ScenarioRow {
  std::string id;
  std::string step;
  std::vector<double> values;  ///< in the file's factor order
  std::string cell;
  std::vector<std::string> malfunctions;
  std::vector<std::string> transitions;
  double weight = 1.0;
  std::uint64_t seed = 0;
  SourceLocation where;
};

struct ScenarioFile {
  std::string file;
  std::vector<std::string> factors;  ///< factor columns, in file order
  std::vector<ScenarioRow> rows;
};

/// Reads a scenarios.csv. Throws InputError (file:line:column) for a missing column, a row of the
/// wrong length, a value that is not a finite number, a negative weight, a bad seed or a
/// duplicate id; UsageError when the file cannot be read.
[[nodiscard]] ScenarioFile read_scenarios_csv(const std::filesystem::path& path);

}  // namespace emrm::scenario
