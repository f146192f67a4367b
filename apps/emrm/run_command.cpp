// `emrm run SCENARIOS.csv -o DIR`: a planned scenario set through the campaign engine, with the
// statistics of the paper's §V-B (docs/plan.md).

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "emrm/campaign/run.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::cli {
namespace {

struct RunCommandOptions {
  std::string scenarios;
  std::string output_dir;
  std::string safety;
  int threads = 0;
};

int run(const RunCommandOptions& o) {
  if (!std::filesystem::is_regular_file(o.scenarios))
    throw UsageError(fmt::format("emrm run: '{}' does not exist", o.scenarios));
  campaign::RunOptions options;
  options.scenarios_csv = o.scenarios;
  options.output_dir = o.output_dir;
  options.threads = o.threads;
  if (!o.safety.empty()) {
    if (!std::filesystem::is_regular_file(o.safety))
      throw UsageError(fmt::format("emrm run: --safety '{}' does not exist", o.safety));
    options.safety_file = o.safety;
  }
  const campaign::RunResult r = campaign::run_scenarios(options);
  const auto feasible =
      std::count_if(r.outcomes.begin(), r.outcomes.end(), [](const auto& s) { return s.feasible; });
  fmt::print("run       {}: {} scenarios ({} feasible), {} simulated, {} already stored, {:.1f} s\n", o.scenarios,
             r.outcomes.size(), feasible, r.sweep.cells_simulated, r.sweep.cells_done_before, r.sweep.seconds);
  if (!r.unsimulated_factors.empty())
    fmt::print("  not simulated (carried through only): {}\n", core::join(r.unsimulated_factors, ", "));
  const auto tracked = std::count_if(r.cells.begin(), r.cells.end(), [](const auto& c) { return c.tracked; });
  fmt::print("  {} cells, {} tracked; widest Wilson {:.0f} % half-width in a tracked cell {:.3f} (target {:g})\n",
             r.cells.size(), tracked, 100.0 * r.confidence, r.widest_tracked_half_width, r.epsilon);
  for (const auto& s : r.subsets) {
    const auto& e = s.estimate;
    if (e.n == 0) continue;
    fmt::print("  S({}) = {:.3f}  ({} tests, n_eff {:.1f}, Wilson [{:.3f}, {:.3f}])\n", s.subset, e.estimate, e.n,
               e.n_eff, e.wilson.low, e.wilson.high);
  }
  fmt::print("  EMRM FSM transitions exercised: {}/{}{}\n", r.transitions_exercised, r.transitions_total,
             r.transitions_missed.empty() ? std::string()
                                          : " (never: " + core::join(r.transitions_missed, ", ") + ")");
  if (r.traceability_rows > 0)
    fmt::print("  traceability: {} rows with their scenarios -> {}\n", r.traceability_rows,
               (std::filesystem::path(o.output_dir) / "traceability.csv").string());
  fmt::print("  -> {}/estimates.json, estimates.csv, outcomes.csv, results.sqlite\n", o.output_dir);
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_run_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<RunCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Simulate a planned scenario set (scenarios.csv from `emrm plan`) and estimate per cell and per "
             "malfunction (Wilson, Hoeffding, weighted S(A)); resumable like `emrm sweep`");
  cmd->add_option("SCENARIOS", options->scenarios, "scenarios.csv written by `emrm plan`")->required();
  cmd->add_option("-o,--output", options->output_dir, "output folder")->required();
  cmd->add_option("--safety", options->safety,
                  "safety case for the traceability matrix (default: the plan's, from scenarios.json)");
  cmd->add_option("--threads", options->threads, "worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
  cmd->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace emrm::cli
