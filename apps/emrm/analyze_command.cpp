// `emrm analyze SAFETY.yaml`: paper Algorithm 1, steps 1–4.

#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "emrm/core/text.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/safety/asil.hpp"
#include "emrm/safety/checks.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/safety/traceability.hpp"

namespace emrm::cli {
namespace {

struct AnalyzeOptions {
  std::string safety_file;
  std::string fsm_file;  // overrides the safety case's own `fsm:` entry
  bool no_fsm = false;
  std::string format = "text";
  std::string output_dir;
  bool strict = false;  // warnings count as errors
};

// The FSM the UCAs refer to: --fsm, else the safety case's `fsm:` (relative to its file).
std::optional<safety::FsmTransitions> load_fsm_transitions(const AnalyzeOptions& options,
                                                           const safety::SafetyCase& sc) {
  if (options.no_fsm) return std::nullopt;
  std::filesystem::path path;
  if (!options.fsm_file.empty()) {
    path = options.fsm_file;
  } else if (sc.fsm) {
    path = std::filesystem::path(options.safety_file).parent_path() / *sc.fsm;
  } else {
    return std::nullopt;
  }
  const fsm::Generator generator = fsm::load_generator(path);
  safety::FsmTransitions known{path.string(), {}};
  for (const auto& t : generator.transitions()) known.transitions.insert({t.from, t.event, t.to});
  return known;
}

std::string counted(std::size_t n, std::string_view one, std::string_view many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

void print_text(const safety::SafetyCase& sc, const std::optional<safety::FsmTransitions>& fsm,
                const std::vector<safety::Finding>& findings) {
  auto& out = std::cout;
  out << fmt::format("Safety case '{}' ({})\n", sc.name, sc.file);
  out << fmt::format("  {}, {}, {}, {}, {}\n", counted(sc.losses.size(), "loss", "losses"),
                     counted(sc.hazards.size(), "hazard", "hazards"),
                     counted(sc.control_actions.size(), "control action", "control actions"),
                     counted(sc.ucas.size(), "UCA", "UCAs"), counted(sc.factors.size(), "factor", "factors"));
  if (fsm) out << fmt::format("  FSM transitions checked against {} ({} transitions)\n", fsm->file, fsm->transitions.size());

  const auto errors = safety::count(findings, safety::FindingSeverity::kError);
  const auto warnings = safety::count(findings, safety::FindingSeverity::kWarning);
  out << fmt::format("\nFindings: {}, {}\n", counted(errors, "error", "errors"),
                     counted(warnings, "warning", "warnings"));
  for (const auto& f : findings)
    out << fmt::format("  {}: {} {} [{}]: {}\n", f.where.str(), core::enum_name(f.severity), f.code, f.subject,
                       f.message);

  out << "\nHARA ratings (ASIL by ISO 26262-3 Table 4; SMIL by the case's table)\n";
  out << core::markdown_table(safety::asil_header(), safety::asil_rows(sc));

  out << "\nM_HARA-STPA: UCA -> hazards, losses, risk\n";
  for (const auto& m : safety::map_hara_stpa(sc)) {
    const safety::Uca* u = sc.find_uca(m.uca);
    out << fmt::format("  {} ({}): hazards {}; losses {}; risk ASIL {}, worst loss {}{}\n", m.uca,
                       core::enum_name(u->type), m.hazards.empty() ? "none" : core::join(m.hazards, ", "),
                       m.losses.empty() ? "none" : core::join(m.losses, ", "), core::enum_name(m.risk.asil),
                       m.risk.worst_loss.empty() ? "none" : m.risk.worst_loss,
                       m.risk.irreversible ? " (irreversible)" : "");
  }
  out << fmt::format("\nTraceability matrix: {} rows (UCA x hazard x loss, with FSM transitions)\n",
                     safety::traceability_matrix(sc).size());
}

void write_outputs(const std::filesystem::path& dir, const safety::SafetyCase& sc,
                   const std::vector<safety::Finding>& findings) {
  const auto matrix = safety::traceability_matrix(sc);
  core::write_file(dir / "traceability.csv", safety::traceability_csv(matrix));
  core::write_file(dir / "traceability.md", "# Traceability matrix: " + sc.name + "\n\n" +
                                                safety::traceability_markdown(matrix));
  core::write_file(dir / "findings.json", safety::findings_json(findings).dump(2) + "\n");
  core::write_file(dir / "asil.csv", core::csv_table(safety::asil_header(), safety::asil_rows(sc)));
}

int run(const AnalyzeOptions& options) {
  const safety::SafetyCase sc = safety::load_safety_case(options.safety_file);
  const auto fsm = load_fsm_transitions(options, sc);
  const auto findings = safety::check(sc, fsm);

  if (options.format == "json") {
    auto j = safety::analysis_json(sc, findings);
    if (fsm) j["fsm"] = fsm->file;
    std::cout << j.dump(2) << "\n";
  } else {
    print_text(sc, fsm, findings);
  }
  if (!options.output_dir.empty()) {
    write_outputs(options.output_dir, sc, findings);
    if (options.format == "text")
      std::cout << fmt::format("Wrote traceability.csv, traceability.md, findings.json, asil.csv to {}\n",
                               options.output_dir);
  }
  const bool failed = safety::count(findings, safety::FindingSeverity::kError) > 0 ||
                      (options.strict && !findings.empty());
  return static_cast<int>(failed ? ExitCode::kFindings : ExitCode::kSuccess);
}

}  // namespace

void register_analyze_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<AnalyzeOptions>();
  auto* cmd = app.add_subcommand("analyze",
                                 "Check a safety case (HARA, STPA UCAs, mapping) and write its traceability matrix.\n"
                                 "Exit 0: no errors; 1: the analysis found errors; 2: bad input.");
  cmd->add_option("SAFETY.yaml", options->safety_file, "Safety case file (schema: docs/safety-yaml.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--fsm", options->fsm_file,
                  "EMRM FSM whose transitions the UCAs name (default: the case's own 'fsm:' entry)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-fsm", options->no_fsm, "Do not check UCA transitions against an FSM");
  cmd->add_option("--format", options->format, "Output on stdout")->check(CLI::IsMember({"text", "json"}));
  cmd->add_option("-o,--output", options->output_dir,
                  "Write traceability.csv, traceability.md, findings.json and asil.csv to this folder");
  cmd->add_flag("--strict", options->strict, "Warnings count as errors (exit 1)");
  cmd->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace emrm::cli
