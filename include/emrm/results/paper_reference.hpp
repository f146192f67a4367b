#pragma once

// The paper's numbers that our tables show beside ours (tables.hpp), loaded from one YAML file
// (examples/tjunction/paper_reference.yaml) into typed structs: they are data, never code.

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::results {

struct PaperRegions {
  double g = 0.0, y = 0.0, o = 0.0, r = 0.0;  ///< percent of the feasible cells
  template <class A>
  void serialize(A& a) {
    a.required("G", g);
    a.required("Y", y);
    a.required("O", o);
    a.required("R", r);
  }
};

struct PaperFineGrid {
  std::string grid;  ///< the campaign grid the regions are of; empty: none
  int feasible_cells = 0;
  PaperRegions regions_pct;
  template <class A>
  void serialize(A& a) {
    a.required("grid", grid);
    a.required("feasible_cells", feasible_cells);
    a.required("regions_pct", regions_pct);
  }
};

/// One column of the paper's EMRM-vs-baseline table and the strategy of ours it is compared with.
struct PaperBaselineColumn {
  std::string label;
  std::string strategy;
  double collision_avoidance_rate_pct = 0.0;
  double mean_residual_impact_speed_kph = 0.0;
  double mitigability_success_pct = 0.0;
  double delta_loss = 0.0;
  SourceLocation where;
  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("label", label);
    a.required("strategy", strategy);
    a.required("collision_avoidance_rate_pct", collision_avoidance_rate_pct);
    a.required("mean_residual_impact_speed_kph", mean_residual_impact_speed_kph);
    a.required("mitigability_success_pct", mitigability_success_pct);
    a.required("delta_loss", delta_loss);
  }
};

struct PaperBaseline {
  std::string grid;
  int cells = 0;
  std::vector<PaperBaselineColumn> columns;
  template <class A>
  void serialize(A& a) {
    a.required("grid", grid);
    a.required("cells", cells);
    a.required("columns", columns);
  }
};

/// Per-level values of one row of the by-parameter table, one list per strategy column, keyed by
/// the strategy's registered name (validated when the reference is loaded).
struct PaperLevelValues {
  std::map<std::string, std::vector<double>> by_strategy;
  /// The list of a strategy column, or nullptr when the row has none for it.
  [[nodiscard]] const std::vector<double>* of(std::string_view strategy) const;
};

struct PaperByParameterRow {
  std::string factor;  ///< speed, ttc, friction or passage
  std::string label;
  std::vector<std::string> levels;  ///< level names of that factor (aggregate.hpp level_names)
  PaperLevelValues values;
  std::vector<int> tests;  ///< one per level, or one total
  SourceLocation where;
  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("factor", factor);
    a.required("label", label);
    a.required("levels", levels);
    a.required("values", values.by_strategy);
    a.required("tests", tests);
  }
};

struct PaperByParameter {
  std::vector<std::string> strategies;
  std::vector<PaperByParameterRow> rows;
  template <class A>
  void serialize(A& a) {
    a.required("strategies", strategies);
    a.required("rows", rows);
  }
};

struct PaperCoverage {
  double framework = 0.0, hara_only = 0.0, stpa_only = 0.0, manual = 0.0;
  template <class A>
  void serialize(A& a) {
    a.required("framework", framework);
    a.required("hara_only", hara_only);
    a.required("stpa_only", stpa_only);
    a.required("manual", manual);
  }
};

struct PaperClaims {
  double emergency_stop_never_avoids_above_kph = 0.0;
  double no_avoidance_below_mu = 0.0;
  double no_avoidance_below_mu_at_ttc_s = 0.0;
  PaperCoverage coverage_pct;
  template <class A>
  void serialize(A& a) {
    a.required("emergency_stop_never_avoids_above_kph", emergency_stop_never_avoids_above_kph);
    a.required("no_avoidance_below_mu", no_avoidance_below_mu);
    a.required("no_avoidance_below_mu_at_ttc_s", no_avoidance_below_mu_at_ttc_s);
    a.required("coverage_pct", coverage_pct);
  }
};

/// Every number of the paper's evaluation that we show beside ours. Default-constructed, it holds
/// none (empty()): an example without a paper_reference.yaml, whose tables show ours alone.
struct PaperReference {
  std::string file;
  int version = 1;
  std::string source;
  PaperFineGrid fine_grid;
  PaperBaseline emrm_vs_baseline;
  PaperByParameter by_parameter;
  PaperClaims claims;
  template <class A>
  void serialize(A& a) {
    a.required("version", version);
    a.optional("source", source);
    a.required("fine_grid", fine_grid);
    a.required("emrm_vs_baseline", emrm_vs_baseline);
    a.required("by_parameter", by_parameter);
    a.required("claims", claims);
  }
  /// True when there is no published number to show (no regions, no columns, no rows).
  [[nodiscard]] bool empty() const noexcept {
    return fine_grid.grid.empty() && emrm_vs_baseline.columns.empty() && by_parameter.rows.empty();
  }
  /// The by-parameter row of a factor, if the paper has one.
  [[nodiscard]] const PaperByParameterRow* by_parameter_row(std::string_view factor) const;
};

/// Loads the paper's reference numbers. Throws InputError (file:line:column) for an unreadable or
/// malformed file, a version other than 1, a missing or unknown field, a percentage outside
/// [0, 100], a negative count, an unknown factor or level, or a value list whose length is not
/// the number of levels (`tests` may also be a single total).
[[nodiscard]] PaperReference load_paper_reference(const std::filesystem::path& path);
[[nodiscard]] PaperReference parse_paper_reference(const std::string& text, const std::string& file_name);

}  // namespace emrm::results
