// `emrm analyze SAFETY.yaml`: paper Algorithm 1, steps 1–4 (safety::analyze), printed and written by
// the safety library's producers (safety/analysis.hpp).

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "emrm/safety/analysis.hpp"
#include "emrm/workflow/safety_case.hpp"

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

int run(const AnalyzeOptions& options) {
  std::optional<std::filesystem::path> fsm;
  if (!options.fsm_file.empty()) fsm = options.fsm_file;
  const safety::Analysis analysis = workflow::analyze_safety_file(options.safety_file, fsm, options.no_fsm);

  if (options.format == "json")
    std::cout << safety::to_json(analysis).dump(2) << "\n";
  else
    std::cout << safety::to_text(analysis);
  if (!options.output_dir.empty()) {
    safety::write_analysis(options.output_dir, analysis);
    if (options.format == "text")
      std::cout << fmt::format("Wrote traceability.csv, traceability.md, findings.json, asil.csv to {}\n",
                               options.output_dir);
  }
  const bool failed = analysis.errors() > 0 || (options.strict && !analysis.findings.empty());
  return static_cast<int>(failed ? ExitCode::kFindings : ExitCode::kSuccess);
}

}  // namespace

void register_analyze_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<AnalyzeOptions>();
  auto* cmd = app.add_subcommand("analyze",
                                 "Check a safety case (HARA, STPA UCAs, mapping) and write its traceability matrix.\n"
                                 "Exit 0: no errors; 1: the analysis found errors; 2: bad input.");
  cmd->add_option("SAFETY.yaml", options->safety_file, "Safety case file (schema: docs/safety-yaml.md)")->required();
  cmd->add_option("--fsm", options->fsm_file,
                  "EMRM FSM whose transitions the UCAs name (default: the case's own 'fsm:' entry)");
  cmd->add_flag("--no-fsm", options->no_fsm, "Do not check UCA transitions against an FSM");
  cmd->add_option("--format", options->format, "Output on stdout")->check(CLI::IsMember({"text", "json"}));
  cmd->add_option("-o,--output", options->output_dir,
                  "Write traceability.csv, traceability.md, findings.json and asil.csv to this folder");
  cmd->add_flag("--strict", options->strict, "Warnings count as errors (exit 1)");
  cmd->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace emrm::cli
