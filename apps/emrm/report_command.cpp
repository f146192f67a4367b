// `emrm report DIR`: the paper's figures and one self-contained HTML report from a results folder
// (docs/report.md).

#include <fmt/format.h>

#include <memory>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/report/report.hpp"

namespace emrm::cli {
namespace {

int run(const std::string& dir) {
  const auto summary = report::write_report(dir);
  std::size_t drawn = 0;
  for (const auto& f : summary.figures) {
    if (f.png.empty()) {
      fmt::print("  {:<22} not drawn: {}\n", f.name, f.note);
      continue;
    }
    ++drawn;
    fmt::print("  {:<22} {} (.svg, .csv){}\n", f.name, f.png.string(), f.note.empty() ? "" : "; " + f.note);
  }
  fmt::print("report    {} figures in {:.1f} s -> {}\n", drawn, summary.figure_seconds, summary.html.string());
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_report_command(CLI::App& app, int& exit_code) {
  auto dir = std::make_shared<std::string>();
  CLI::App* cmd =
      app.add_subcommand("report",
                         "Draw the paper's figures (PNG, SVG and CSV in DIR/figures) and write DIR/report.html from a "
                         "results folder written by emrm sweep, run or reproduce");
  cmd->add_option("DIR", *dir, "results folder (holds results.sqlite)")->required();
  cmd->callback([dir, &exit_code] { exit_code = run(*dir); });
}

}  // namespace emrm::cli
