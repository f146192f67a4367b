// The analysis of one safety case and its printed and written forms (`emrm analyze`, reproduce).

#include "emrm/safety/analysis.hpp"

#include <fmt/format.h>

#include <string_view>
#include <utility>

#include "emrm/core/text.hpp"

namespace emrm::safety {
using core::counted;

Analysis analyze(SafetyCase sc, std::optional<FsmTransitions> fsm) {
  Analysis analysis{std::move(sc), std::move(fsm), {}, {}};
  analysis.findings = check(analysis.safety_case, analysis.fsm);
  analysis.matrix = traceability_matrix(analysis.safety_case);
  return analysis;
}

std::optional<std::filesystem::path> fsm_file(const SafetyCase& sc) {
  if (!sc.fsm) return std::nullopt;
  return std::filesystem::path(sc.file).parent_path() / *sc.fsm;
}

std::string findings_text(const std::vector<Finding>& findings) {
  std::string out;
  for (const auto& f : findings)
    out +=
        fmt::format("  {}: {} {} [{}]: {}\n", f.where.str(), core::enum_name(f.severity), f.code, f.subject, f.message);
  return out;
}

std::string to_text(const Analysis& analysis) {
  const SafetyCase& sc = analysis.safety_case;
  std::string out = fmt::format("Safety case '{}' ({})\n", sc.name, sc.file);
  out += fmt::format("  {}, {}, {}, {}, {}\n", counted(sc.losses.size(), "loss", "losses"),
                     counted(sc.hazards.size(), "hazard", "hazards"),
                     counted(sc.control_actions.size(), "control action", "control actions"),
                     counted(sc.ucas.size(), "UCA", "UCAs"), counted(sc.factors.size(), "factor", "factors"));
  if (analysis.fsm)
    out += fmt::format("  FSM transitions checked against {} ({} transitions)\n", analysis.fsm->file,
                       analysis.fsm->transitions.size());

  out += fmt::format("\nFindings: {}, {}\n", counted(analysis.errors(), "error", "errors"),
                     counted(analysis.warnings(), "warning", "warnings"));
  out += findings_text(analysis.findings);

  out += "\nHARA ratings (ASIL by ISO 26262-3 Table 4; SMIL by the case's table)\n";
  out += core::markdown_table(asil_header(), asil_rows(sc));

  out += "\nM_HARA-STPA: UCA -> hazards, losses, risk\n";
  for (const auto& m : map_hara_stpa(sc)) {
    const Uca* u = sc.find_uca(m.uca);
    out += fmt::format("  {} ({}): hazards {}; losses {}; risk ASIL {}, worst loss {}{}\n", m.uca,
                       core::enum_name(u->type), m.hazards.empty() ? "none" : core::join(m.hazards, ", "),
                       m.losses.empty() ? "none" : core::join(m.losses, ", "), core::enum_name(m.risk.asil),
                       m.risk.worst_loss.empty() ? "none" : m.risk.worst_loss,
                       m.risk.irreversible ? " (irreversible)" : "");
  }
  out += fmt::format("\nTraceability matrix: {} rows (UCA x hazard x loss, with FSM transitions)\n",
                     analysis.matrix.size());
  return out;
}

nlohmann::json to_json(const Analysis& analysis) {
  auto j = analysis_json(analysis.safety_case, analysis.findings);
  if (analysis.fsm) j["fsm"] = analysis.fsm->file;
  return j;
}

std::vector<std::filesystem::path> write_analysis(const std::filesystem::path& dir, const Analysis& analysis) {
  std::vector<core::FileContent> files = traceability_files(dir, analysis.safety_case.name, analysis.matrix);
  files.push_back({dir / kFindingsJson, findings_json(analysis.findings).dump(2) + "\n"});
  files.push_back({dir / kAsilCsv, core::csv_table(asil_header(), asil_rows(analysis.safety_case))});
  core::write_files(files);  // the four or none
  std::vector<std::filesystem::path> written;
  for (const auto& f : files) written.push_back(f.path);
  return written;
}

}  // namespace emrm::safety
