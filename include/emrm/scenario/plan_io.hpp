#pragma once

// The files of a plan (docs/plan.md): scenarios.csv (one row per scenario, the input of
// `emrm run`), scenarios.json (the same with the plan's settings and steps) and coverage.json,
// and the summary `emrm plan` prints.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/scenario/coverage.hpp"
#include "emrm/scenario/plan.hpp"

namespace emrm::scenario {

/// A plan folder, as write_plan writes it (`emrm plan -o DIR`, reproduce's plan/): the paths of
/// its files. A results folder names its plan folder (results::ResultsDir::plan()).
class PlanDir {
 public:
  explicit PlanDir(std::filesystem::path root = {}) : root_(std::move(root)) {}
  /// The plan folder of a scenarios.csv: the folder it is in.
  [[nodiscard]] static PlanDir of(const std::filesystem::path& scenarios_csv) {
    return PlanDir(scenarios_csv.parent_path());
  }
  [[nodiscard]] const std::filesystem::path& root() const noexcept { return root_; }
  [[nodiscard]] std::filesystem::path scenarios_csv() const { return root_ / "scenarios.csv"; }
  /// The ODD, the settings and the scenarios, which `emrm run` reads beside scenarios.csv.
  [[nodiscard]] std::filesystem::path scenarios_json() const { return root_ / "scenarios.json"; }
  [[nodiscard]] std::filesystem::path coverage_json() const { return root_ / "coverage.json"; }
  [[nodiscard]] std::filesystem::path coverage_csv() const { return root_ / "coverage.csv"; }
  [[nodiscard]] std::filesystem::path coverage_md() const { return root_ / "coverage.md"; }

 private:
  std::filesystem::path root_;
};

/// A factor of the ODD as scenarios.json lists it and estimates.json repeats it (docs/plan.md): its
/// bins with their labels and exposure priors. One field list (serialize) for the JSON writer and
/// the typed readers (core/json_archive.hpp).
struct PlanFactor {
  struct Level {
    int level = 0;
    std::string label;
    double prior = 0.0;

    template <class A>
    void serialize(A& a) {
      a.required("level", level);
      a.required("label", label);
      a.required("prior", prior);
    }
  };
  std::string name;
  std::string unit;
  FactorType type = FactorType::kContinuous;
  std::vector<Level> levels;
  bool influential = true;
  double nominal = 0.0;

  template <class A>
  void serialize(A& a) {
    a.required("name", name);
    a.required("unit", unit);
    a.required("type", type);
    a.required("levels", levels);
    a.required("influential", influential);
    a.required("nominal", nominal);
  }
};

/// The factor as a plan lists it.
[[nodiscard]] PlanFactor plan_factor(const OddFactor& factor);

/// Columns: id, step, one per factor, cell, malfunctions (space-separated), transitions
/// ("; "-separated), weight, seed.
[[nodiscard]] std::string scenarios_csv(const Odd& odd, const Plan& plan);
/// {"odd", "settings", "factors", "steps", "stop", "malfunctions", "cells", "scenarios": [...]}, the
/// stop's shortfalls as shortfalls_json writes them. File paths (ODD, safety case, scene)
/// are written relative to `folder`, where the file will be written.
[[nodiscard]] nlohmann::ordered_json scenarios_json(const Odd& odd, const Plan& plan,
                                                    const std::filesystem::path& folder = ".");

/// The plan's coverage (measured by the independent checker), then the baselines' by the same code:
/// "emrm plan", "HARA only", "STPA only", "manual grid" (the last only when the ODD declares one).
[[nodiscard]] std::vector<CoverageReport> coverage_comparison(const Odd& odd, const Plan& plan);
/// [{"kind", "subject", "found", "needed", "message"}]: the plan's shortfalls, in plan order.
[[nodiscard]] nlohmann::ordered_json shortfalls_json(const std::vector<Shortfall>& shortfalls);
/// {"plan": report, "baselines": [reports], "shortfalls": shortfalls_json(shortfalls)}.
[[nodiscard]] nlohmann::ordered_json coverage_json(const std::vector<CoverageReport>& reports,
                                                   const std::vector<Shortfall>& shortfalls = {});
/// The reports of a coverage.json's text (coverage_json's document) in its order: the plan's, then
/// the baselines'. Throws InputError at `file_name` when the text is not JSON or not that layout
/// (the message names the field).
[[nodiscard]] std::vector<CoverageReport> parse_coverage_json(const std::string& text, const std::string& file_name);
/// Reads a coverage.json as write_plan wrote it. Throws InputError naming the file when it cannot
/// be read or is not such a file.
[[nodiscard]] std::vector<CoverageReport> read_coverage_json(const std::filesystem::path& path);
/// One row per metric (hazard, UCA, transition, cell, t-wise, boundary coverage, C1–C4), one
/// column per report.
[[nodiscard]] std::pair<core::Row, std::vector<core::Row>> coverage_table(const std::vector<CoverageReport>& reports);

/// Writes DIR/scenarios.csv, scenarios.json, coverage.json, coverage.csv and coverage.md, all five or
/// none (core::write_files).
void write_plan(const std::filesystem::path& dir, const Odd& odd, const Plan& plan,
                const std::vector<CoverageReport>& reports);

/// The summary `emrm plan` prints: the ODD's size, each construction step, the scenarios and the
/// `seconds` building took, the notes, the plan's coverage and the independent check of C1–C4,
/// the baselines (reports as coverage_comparison returns them) and DIR/scenarios.csv. `odd_file` is
/// shown as given.
[[nodiscard]] std::string summary_text(const std::string& odd_file, const Odd& odd, const Plan& plan,
                                       const std::vector<CoverageReport>& reports, double seconds,
                                       const std::filesystem::path& dir);

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
