// `emrm boundary DIR [-o OUT]`: the boundary curves of a results store (docs/boundary.md) — for each
// speed and combination of the other factors, the TTC from which the car stops, avoids or
// mitigates, and from which each strategy avoids — beside the analytic stop boundary, as CSV and as
// figures over the region maps.

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "commands.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/boundary_figures.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/boundary.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/stop_physics.hpp"

namespace emrm::cli {
namespace {

namespace fs = std::filesystem;

struct BoundaryOptions {
  std::string dir;
  std::string output;  ///< empty: DIR/boundary
  std::size_t max_figures = 24;
  bool no_figures = false;
};

// gnuplot is looked for before anything is written: without it the command would stop halfway.
void require_gnuplot() {
  if (!core::find_program("gnuplot"))
    throw UsageError(
        "emrm boundary: cannot draw figures: gnuplot was not found on PATH; install it (apt-get install "
        "gnuplot-nox), or pass --no-figures for the CSV files alone");
}

std::string figures_line(const std::vector<report::Figure>& figures, std::size_t slices, const fs::path& out) {
  std::size_t drawn = 0;
  for (const auto& f : figures) drawn += f.png.empty() ? 0 : 1;
  std::string line =
      fmt::format("{} (.png, .svg, .csv) in {}", core::counted(drawn, "figure", "figures"), out.string());
  if (drawn == slices) return line;
  return fmt::format("{}: the first {} of {} slices (--max-figures raises the cap); boundary.csv holds them all", line,
                     drawn, slices);
}

int run(const BoundaryOptions& options) {
  const fs::path dir(options.dir);
  const fs::path store = campaign::results_store_in(dir, "emrm boundary");
  const campaign::CampaignMeta meta = campaign::read_meta(store);
  // The analytic stop boundary is the store's own scene's: its actuators, as the sweep drove them.
  const sim::SceneConfig scene = sim::parse_stored_scene_config(meta.scene_yaml, store.string() + " (scene)");
  const auto records = campaign::read_results(store);
  const results::BoundaryReport boundaries =
      results::compute_boundaries(records, sim::scenario_factors(scene),
                                  sim::stop_boundary_applies(scene) ? std::optional(scene.actuation) : std::nullopt);
  const fs::path out = options.output.empty() ? dir / "boundary" : fs::path(options.output);

  std::vector<report::Figure> figures;
  if (!options.no_figures) {
    require_gnuplot();
    report::BoundaryFigureOptions figure_options;
    figure_options.max_figures = options.max_figures;
    figures = report::draw_boundary_figures(boundaries, records, out, figure_options);
  }
  // The CSV files last, together: when they are there, so is every figure of the run.
  const auto written = results::write_boundary_files(out, boundaries);

  fmt::print("Boundaries of {} ({} cells): {}", dir.string(), records.size(), results::summary(boundaries));
  if (!options.no_figures) fmt::print("Drew {}\n", figures_line(figures, boundaries.slices.size(), out));
  fmt::print("Wrote {}, {}\n", written[0].string(), written[1].string());
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_boundary_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BoundaryOptions>();
  CLI::App* cmd = app.add_subcommand(
      "boundary",
      "Boundary curves of a results store: for each speed and combination of mu, passage width and truck speed,\n"
      "the lowest TTC from which every cell is G (stop), G or Y (avoid), G, Y or O (mitigate), or avoided by each\n"
      "strategy, beside the analytic stop boundary of the store's actuators. Writes OUT/boundary.csv,\n"
      "OUT/analytic_stop.csv and one figure per grid and combination (OUT defaults to DIR/boundary)");
  cmd->add_option("DIR", o->dir, "results folder written by emrm sweep, run or reproduce")->required();
  cmd->add_option("-o,--output", o->output, "Output folder (default: DIR/boundary)");
  cmd->add_option("--max-figures", o->max_figures, "Figures drawn at most (default 24); boundary.csv holds every slice")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1000}));
  cmd->add_flag("--no-figures", o->no_figures, "Write the CSV files only (no gnuplot needed)");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
