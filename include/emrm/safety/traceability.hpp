#pragma once

// The integrated mapping M_HARA-STPA : C × UCA → {H, L, R} (paper eq. 2) and the traceability
// matrix UCA × hazard × loss × FSM transition × scenarios built from it.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/safety/checks.hpp"
#include "emrm/safety/model.hpp"

namespace emrm::safety {

/// The files of traceability_files (results::ResultsDir names the folders they are written to).
inline constexpr std::string_view kTraceabilityCsv = "traceability.csv";
inline constexpr std::string_view kTraceabilityMd = "traceability.md";

/// The risk measure R of one UCA: the highest ASIL among its hazards, and the worst loss they
/// lead to (losses are declared from least to most severe, as the paper's L1…L7).
struct RiskMeasure {
  Asil asil = Asil::kQM;
  std::string worst_loss;     ///< empty when the UCA reaches no loss
  bool irreversible = false;  ///< some reachable loss is irreversible
};

/// One value of M_HARA-STPA: what one UCA leads to. References that do not resolve are left out
/// (they are SAF001 findings).
struct MappingEntry {
  std::string uca;
  std::vector<std::string> hazards;
  std::vector<std::string> losses;  ///< union over the hazards, in declaration order
  RiskMeasure risk;
};

[[nodiscard]] std::vector<MappingEntry> map_hara_stpa(const SafetyCase& sc);

/// One row of the traceability matrix: a (UCA, hazard, loss) triple with the FSM transitions
/// and region of the UCA. `scenarios` is filled by scenario generation (empty until then).
struct TraceRow {
  std::string uca;
  std::string uca_type;
  std::string control_action;
  std::string hazard;
  std::string asil;
  std::string smil;
  std::string loss;
  std::string loss_name;
  bool loss_reversible = true;
  std::vector<std::string> transitions;  ///< "S3 -execute_maneuver-> S4"
  std::string region;
  std::vector<std::string> scenarios;

  /// The row's field list, in traceability.csv's column order: `visit(column, field)`, and for a
  /// list the separator its cell joins it with. The header, the writer (to_row) and the reader
  /// (read_traceability_csv) all go through it.
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& visit) {
    visit("uca", self.uca);
    visit("uca_type", self.uca_type);
    visit("control_action", self.control_action);
    visit("hazard", self.hazard);
    visit("asil", self.asil);
    visit("smil", self.smil);
    visit("loss", self.loss);
    visit("loss_name", self.loss_name);
    visit("reversible", self.loss_reversible);  // yes or no
    visit("fsm_transitions", self.transitions, std::string_view("; "));
    visit("region", self.region);
    visit("scenarios", self.scenarios, std::string_view(" "));
  }
};

/// Rows in the order UCA, then hazard, then loss, as declared.
[[nodiscard]] std::vector<TraceRow> traceability_matrix(const SafetyCase& sc);

[[nodiscard]] core::Row traceability_header();
[[nodiscard]] core::Row to_row(const TraceRow& row);
[[nodiscard]] std::string traceability_csv(const std::vector<TraceRow>& rows);
/// Reads a traceability.csv that traceability_csv wrote: the header must be traceability_header();
/// throws InputError at the file's line and column for another header, a row of another length or
/// a `reversible` that is neither yes nor no.
[[nodiscard]] std::vector<TraceRow> read_traceability_csv(const std::filesystem::path& path);
/// As Markdown; a scenarios cell of more than six ids reads "292: S003 S004 … ".
[[nodiscard]] std::string traceability_markdown(const std::vector<TraceRow>& rows);
/// The one producer of the matrix files (`emrm analyze`, `emrm run`, `emrm reproduce`):
/// DIR/traceability.csv and DIR/traceability.md, the latter titled "Traceability matrix: NAME"
/// after the safety case, for a command to write with its other files (core::write_files).
[[nodiscard]] std::vector<core::FileContent> traceability_files(const std::filesystem::path& dir,
                                                                const std::string& case_name,
                                                                const std::vector<TraceRow>& rows);

/// Per hazard: S, E, C, the ASIL they give, the stated ASIL, the extended ratings, the SMIL the
/// table gives and the stated SMIL.
[[nodiscard]] core::Row asil_header();
[[nodiscard]] std::vector<core::Row> asil_rows(const SafetyCase& sc);

/// The whole analysis as JSON: summary counts, findings, ASIL table, mapping and matrix.
[[nodiscard]] nlohmann::json analysis_json(const SafetyCase& sc, const std::vector<Finding>& findings);
[[nodiscard]] nlohmann::json findings_json(const std::vector<Finding>& findings);
/// Reads a findings.json that findings_json wrote (a list of findings); throws InputError at the
/// file's line and column for what is missing, misspelt or of the wrong type.
[[nodiscard]] std::vector<Finding> read_findings_json(const std::filesystem::path& path);

}  // namespace emrm::safety
