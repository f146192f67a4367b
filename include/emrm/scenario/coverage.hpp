#pragma once

// Coverage of a scenario set against an ODD (paper §V-B constraints C1–C4 and §VI coverage
// analysis), measured from the points alone so that it checks the planner independently:
// hazard, UCA (malfunction), FSM transition, cell, t-wise and boundary coverage. The same code
// measures the baselines of docs/plan.md: HARA only, STPA only and a manual sparse grid.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "emrm/scenario/odd.hpp"

namespace emrm::scenario {

struct CoverageCount {
  std::size_t covered = 0;
  std::size_t total = 0;
  std::vector<std::string> missing;  ///< what is not covered (all of it, in a stable order)
  /// covered / total, 1 when total is 0.
  [[nodiscard]] double fraction() const noexcept {
    return total == 0 ? 1.0 : static_cast<double>(covered) / static_cast<double>(total);
  }
};

struct CoverageReport {
  std::string name;  ///< "emrm plan", "HARA only", "STPA only", "manual grid"
  std::size_t scenarios = 0;
  std::size_t inadmissible = 0;  ///< points outside the domain or R_f, or breaking a constraint (not counted)
  CoverageCount hazards;         ///< hazards some admissible test's malfunction leads to
  CoverageCount malfunctions;    ///< modes with ≥ 1 test in their region (UCA coverage)
  std::vector<std::pair<std::string, std::size_t>> tests_per_malfunction;  ///< admissible tests per region (C4)
  CoverageCount transitions;  ///< FSM transitions some test's malfunctions exercise
  CoverageCount cells;        ///< relevant cells with ≥ 1 test
  CoverageCount boundaries;   ///< feasible boundary targets hit exactly
  CoverageCount twise;        ///< admissible t-tuples of influential levels realised
  bool c1 = false;            ///< every relevant cell has ≥ n_c tests
  bool c2 = false;            ///< every feasible boundary target is hit
  bool c3 = false;            ///< every admissible t-tuple is realised
  bool c4 = false;            ///< every mode has ≥ n_m tests in its region
  [[nodiscard]] bool all() const noexcept { return c1 && c2 && c3 && c4; }
};

/// Measures a set of points (each one value per ODD factor). Recomputes cells, relevance, regions
/// and tuples from the ODD by brute force; shares no bookkeeping with build_plan. Validates the
/// ODD first (validate(const Odd&)): throws core::ConfigError (an InputError) naming the field,
/// std::invalid_argument for a point with the wrong number of values.
[[nodiscard]] CoverageReport measure_coverage(const Odd& odd, const std::vector<std::vector<double>>& points,
                                              std::string name);

/// The nominal point: every factor at its nominal value.
[[nodiscard]] std::vector<double> nominal_point(const Odd& odd);

/// Traditional HARA: one nominal scenario per hazard (all at the nominal point).
[[nodiscard]] std::vector<std::vector<double>> hara_only_baseline(const Odd& odd);
/// Traditional STPA: one scenario per malfunction mode, the admissible point of its region nearest
/// the nominal point (distances in units of each factor's domain width).
[[nodiscard]] std::vector<std::vector<double>> stpa_only_baseline(const Odd& odd);
/// Manual: the ODD's `baselines.manual` grid, other factors nominal (5 speeds × 6 TTCs in the
/// shipped example); empty when the ODD declares none.
[[nodiscard]] std::vector<std::vector<double>> manual_baseline(const Odd& odd);

/// Every field of `report`, with each count's fraction and whether C1–C4 all hold.
[[nodiscard]] nlohmann::ordered_json to_json(const CoverageReport& report);
/// The report that to_json wrote, read back (the fractions and "all" are recomputed, not read).
/// Throws InputError naming `file` and the field's place in the document (`where`, e.g.
/// "baselines[1]") when a field is missing or of the wrong type.
[[nodiscard]] CoverageReport coverage_report_from_json(const nlohmann::ordered_json& j, const std::string& file,
                                                       const std::string& where);

}  // namespace emrm::scenario
