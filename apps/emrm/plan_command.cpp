// `emrm plan ODD.yaml [--safety SAFETY.yaml] -o DIR`: the minimum scenario set of an ODD
// (docs/plan.md). Exit 1 when the independent checker finds C1–C4 not all satisfied.

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/scenario/coverage.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/scenario/plan_io.hpp"

namespace emrm::cli {
namespace {

namespace fs = std::filesystem;

struct PlanOptions {
  std::string odd_file;
  std::string safety_file;
  std::string output_dir;
};

std::string pct(const scenario::CoverageCount& c) {
  return fmt::format("{:.1f} % ({}/{})", 100.0 * c.fraction(), c.covered, c.total);
}

int run(const PlanOptions& o) {
  if (!fs::is_regular_file(o.odd_file)) throw UsageError(fmt::format("emrm plan: '{}' does not exist", o.odd_file));
  std::optional<fs::path> safety;
  if (!o.safety_file.empty()) safety = o.safety_file;
  const auto start = std::chrono::steady_clock::now();
  const scenario::Odd odd = scenario::load_odd(o.odd_file, safety);
  const scenario::Plan plan = scenario::build_plan(odd);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto reports = scenario::coverage_comparison(odd, plan);

  const fs::path dir = o.output_dir;
  scenario::write_plan(dir, odd, plan, reports);

  fmt::print("plan      {}: {} factors, {:.0f} cells, {} relevant, {} tracked, {} malfunction modes\n", o.odd_file,
             odd.factors.size(), odd.cell_count(), plan.relevant_cells, plan.tracked_cells, odd.malfunctions.size());
  for (const auto& step : plan.steps) fmt::print("  {:<15} +{:<4} {}\n", step.name, step.added, step.note);
  fmt::print("  {} scenarios in {:.2f} s; {}\n", plan.scenarios.size(), seconds, plan.stop_reason);
  for (const auto& note : plan.infeasible) fmt::print("  no admissible point (exempt from C2): {}\n", note);
  for (const auto& note : plan.shortfalls) fmt::print("  shortfall: {}\n", note);
  const auto& ours = reports.front();
  fmt::print("  coverage: hazards {}, UCAs {}, transitions {}, cells {}, {}-wise {}, boundaries {}\n",
             pct(ours.hazards), pct(ours.malfunctions), pct(ours.transitions), pct(ours.cells), odd.strength,
             pct(ours.twise), pct(ours.boundaries));
  fmt::print("  independent check: C1 {}, C2 {}, C3 {}, C4 {}\n", ours.c1 ? "holds" : "FAILS",
             ours.c2 ? "holds" : "FAILS", ours.c3 ? "holds" : "FAILS", ours.c4 ? "holds" : "FAILS");
  for (std::size_t i = 1; i < reports.size(); ++i)
    fmt::print("  baseline {:<12} {:>3} scenarios: hazards {}, UCAs {}, cells {}\n", reports[i].name,
               reports[i].scenarios, pct(reports[i].hazards), pct(reports[i].malfunctions), pct(reports[i].cells));
  fmt::print("  -> {}\n", (dir / "scenarios.csv").string());
  return ours.all() ? 0 : 1;
}

}  // namespace

void register_plan_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<PlanOptions>();
  CLI::App* cmd = app.add_subcommand("plan", "Build the minimum scenario set of an ODD (C1-C4, statistics)");
  cmd->add_option("ODD", options->odd_file, "ODD file (docs/odd-yaml.md)")->required();
  cmd->add_option("--safety", options->safety_file, "safety case whose UCAs are the malfunction modes "
                                                    "(default: the ODD's 'safety:' entry)");
  cmd->add_option("-o,--output", options->output_dir, "output folder")->required();
  cmd->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace emrm::cli
