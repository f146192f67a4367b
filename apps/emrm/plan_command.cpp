// `emrm plan ODD.yaml [--safety SAFETY.yaml] -o DIR`: the minimum scenario set of an ODD
// (docs/plan.md). Exit 1 when the independent checker finds C1–C4 not all satisfied.

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "commands.hpp"
#include "emrm/core/error.hpp"
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

  fmt::print("{}", scenario::summary_text(o.odd_file, odd, plan, reports, seconds, dir));
  return reports.front().all() ? 0 : 1;
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
