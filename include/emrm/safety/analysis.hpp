#pragma once

// The analysis of one safety case (paper Algorithm 1, steps 1–4) and the producers of everything
// `emrm analyze` prints and writes; `emrm reproduce` writes the same files into DIR/analysis.
// Schemas: docs/outputs.md.

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/safety/checks.hpp"
#include "emrm/safety/model.hpp"
#include "emrm/safety/traceability.hpp"

namespace emrm::safety {

/// The files of write_analysis besides traceability_files' (results::ResultsDir names the folder,
/// reproduce's analysis/).
inline constexpr std::string_view kFindingsJson = "findings.json";
inline constexpr std::string_view kAsilCsv = "asil.csv";

/// A checked safety case: its findings and its traceability matrix.
struct Analysis {
  SafetyCase safety_case;
  std::optional<FsmTransitions> fsm;  ///< the FSM the UCAs' transitions were checked against
  std::vector<Finding> findings;      ///< check(safety_case, fsm)
  std::vector<TraceRow> matrix;       ///< traceability_matrix(safety_case)

  [[nodiscard]] std::size_t errors() const { return count(findings, FindingSeverity::kError); }
  [[nodiscard]] std::size_t warnings() const { return count(findings, FindingSeverity::kWarning); }
};

/// Checks `sc` (against `fsm` when given) and builds its traceability matrix.
[[nodiscard]] Analysis analyze(SafetyCase sc, std::optional<FsmTransitions> fsm = {});

/// The FSM file the case's `fsm:` entry names, relative to the folder of the case's own file;
/// nothing when the case has no such entry.
[[nodiscard]] std::optional<std::filesystem::path> fsm_file(const SafetyCase& sc);

/// The transitions a UCA may name, from any range of transitions with `from`, `event` and `to`
/// strings (such as fsm::Generator::transitions(); safety does not depend on fsm).
template <class Transitions>
[[nodiscard]] FsmTransitions fsm_transitions(std::string file, const Transitions& transitions) {
  FsmTransitions known{std::move(file), {}};
  for (const auto& t : transitions) known.transitions.insert({t.from, t.event, t.to});
  return known;
}

/// One line per finding, as `emrm analyze` lists them: "  FILE:LINE:COL: error SAF001 [UCA5]: …".
[[nodiscard]] std::string findings_text(const std::vector<Finding>& findings);

/// The analysis as `emrm analyze` prints it: counts, findings, the HARA ratings table, M_HARA-STPA
/// and the size of the traceability matrix.
[[nodiscard]] std::string to_text(const Analysis& analysis);

/// The analysis as `emrm analyze --format json` prints it: analysis_json, plus "fsm" (the FSM file)
/// when the transitions were checked against one.
[[nodiscard]] nlohmann::json to_json(const Analysis& analysis);

/// The files of an analysis in `dir`: traceability.csv and traceability.md (traceability_files),
/// findings.json and asil.csv, all four or none (core::write_files). Returns their paths in that
/// order. Throws emrm::Error when a file cannot be written.
std::vector<std::filesystem::path> write_analysis(const std::filesystem::path& dir, const Analysis& analysis);

}  // namespace emrm::safety
