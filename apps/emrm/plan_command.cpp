// `emrm plan ODD.yaml [--safety SAFETY.yaml] -o DIR`: the minimum scenario set of an ODD
// (docs/plan.md). Before planning, the inputs are checked across files: the safety case as `emrm
// analyze` checks it (error findings refuse the plan, exit 1, unless --allow-findings), the ODD's
// factors against the scene and the simulator (exit 2 at the ODD's value). Exit 1 also when the
// independent checker finds C1–C4 not all satisfied; warnings alone leave the exit code at 0.

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/scenario/coverage.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/workflow/plan_checks.hpp"
#include "emrm/workflow/safety_case.hpp"

namespace emrm::cli {
namespace {

namespace fs = std::filesystem;

struct PlanOptions {
  std::string odd_file;
  std::string safety_file;
  std::string output_dir;
  bool allow_findings = false;
};

// The safety case's analysis, as `emrm analyze` reports it: its counts, and its findings when it has
// errors. False when the errors refuse the plan.
bool safety_case_acceptable(const safety::Analysis& analysis, const PlanOptions& o,
                            std::vector<std::string>& warnings) {
  if (analysis.findings.empty()) return true;
  const std::string& file = analysis.safety_case.file;
  const bool refused = analysis.errors() > 0 && !o.allow_findings;
  fmt::print("safety    {}: {}, {}{}\n", file, core::counted(analysis.errors(), "error", "errors"),
             core::counted(analysis.warnings(), "warning", "warnings"),
             refused                  ? "; no plan (fix them, or plan anyway with --allow-findings)"
             : analysis.errors() == 0 ? fmt::format(" (emrm analyze {} lists them)", file)
                                      : std::string());
  if (analysis.errors() > 0) fmt::print("{}", safety::findings_text(analysis.findings));
  if (!refused && analysis.errors() > 0)
    warnings.push_back(fmt::format("{}: warning: planned despite {} (--allow-findings)", file,
                                   core::counted(analysis.errors(), "error finding", "error findings")));
  return !refused;
}

int run(const PlanOptions& o) {
  if (!fs::is_regular_file(o.odd_file)) throw UsageError(fmt::format("emrm plan: '{}' does not exist", o.odd_file));
  std::optional<fs::path> safety;
  if (!o.safety_file.empty()) safety = o.safety_file;
  const auto start = std::chrono::steady_clock::now();
  const scenario::Odd odd = scenario::load_odd(o.odd_file, safety, workflow::family_levels);
  const sim::SceneConfig scene = workflow::plan_scene(odd);
  workflow::check_odd_against_scene(odd, scene);
  std::vector<std::string> warnings;
  if (odd.safety_file) {
    const safety::Analysis analysis = workflow::analyze_safety_file(*odd.safety_file);
    if (!safety_case_acceptable(analysis, o, warnings)) return static_cast<int>(ExitCode::kFindings);
    for (auto& w : workflow::safety_range_warnings(odd, analysis.safety_case)) warnings.push_back(std::move(w));
  }
  const scenario::Plan plan = scenario::build_plan(odd);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto reports = scenario::coverage_comparison(odd, plan);
  for (auto& w : workflow::placement_warnings(odd, plan, scene)) warnings.push_back(std::move(w));

  const fs::path dir = o.output_dir;
  scenario::write_plan(dir, odd, plan, reports);

  fmt::print("{}", scenario::summary_text(o.odd_file, odd, plan, reports, seconds, dir));
  for (const auto& w : warnings) fmt::print("{}\n", w);
  if (!warnings.empty()) fmt::print("plan      {}\n", core::counted(warnings.size(), "warning", "warnings"));
  return reports.front().all() ? 0 : 1;
}

}  // namespace

void register_plan_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<PlanOptions>();
  CLI::App* cmd = app.add_subcommand("plan",
                                     "Build the minimum scenario set of an ODD (C1-C4, statistics).\n"
                                     "Exit 0: planned; 1: the safety case has error findings (no plan) or "
                                     "C1-C4 fail; 2: bad input.");
  cmd->add_option("ODD", options->odd_file, "ODD file (docs/odd-yaml.md)")->required();
  cmd->add_option("--safety", options->safety_file,
                  "safety case whose UCAs are the malfunction modes "
                  "(default: the ODD's 'safety:' entry)");
  cmd->add_option("-o,--output", options->output_dir, "output folder")->required();
  cmd->add_flag("--allow-findings", options->allow_findings,
                "Plan even when the safety case has error findings (as `emrm analyze` reports them)");
  cmd->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace emrm::cli
