// `emrm verify DIR`: an independent re-check of a results store (docs/verify.md). Exit 1 when any
// claim does not hold, with the list.

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/verify.hpp"
#include "options.hpp"

namespace emrm::cli {
namespace {

struct VerifyCommandOptions {
  std::string dir;
  bool json = false;
  int threads = 0;
};

int run(const VerifyCommandOptions& options) {
  const std::filesystem::path dir(options.dir);
  const auto store = std::filesystem::is_directory(dir) ? results::ResultsDir(dir).store() : dir;
  results::VerifyOptions verify_options;
  verify_options.threads = options.threads;
  const results::VerifyReport report = results::verify_results(store, verify_options);
  // Kept beside the store, where `emrm report` shows it (as `emrm reproduce` keeps it).
  const std::filesystem::path folder = store.parent_path().empty() ? std::filesystem::path(".") : store.parent_path();
  results::write_verify_report(folder, report);
  if (options.json)
    fmt::print("{}\n", results::to_json(report).dump(2));
  else
    fmt::print("{}Wrote {}\n", results::to_text(report), results::ResultsDir(folder).verify_json().string());
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
  cmd->add_flag("--json", o->json, "Print the report as JSON (DIR/verify.json is written either way)");
  add_threads_option(cmd, o->threads, "Worker threads (0: all cores)");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
