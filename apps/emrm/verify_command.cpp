// `emrm verify DIR`: an independent re-check of a results store (docs/verify.md). Exit 1 when any
// claim does not hold, with the list.

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/verify.hpp"

namespace emrm::cli {
namespace {

struct VerifyCommandOptions {
  std::string dir;
  bool json = false;
};

int run(const VerifyCommandOptions& options) {
  const std::filesystem::path dir(options.dir);
  const auto store = std::filesystem::is_directory(dir) ? results::ResultsDir(dir).store() : dir;
  const results::VerifyReport report = results::verify_results(store);
  if (options.json)
    fmt::print("{}\n", results::to_json(report).dump(2));
  else
    fmt::print("{}", results::to_text(report));
  return static_cast<int>(report.ok() ? ExitCode::kSuccess : ExitCode::kFindings);
}

}  // namespace

void register_verify_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<VerifyCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "verify",
      "Re-check a results store without trusting it: replay every stored maneuver, re-check every avoidance\n"
      "every millisecond (no contact, inside the road, a safe state at the end), re-derive every certificate\n"
      "and every region; exit 1 with a list when a claim does not hold");
  cmd->add_option("DIR", o->dir, "results folder (holds results.sqlite), or the results.sqlite file")->required();
  cmd->add_flag("--json", o->json, "Print the report as JSON");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
