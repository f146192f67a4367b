// `emrm sweep CAMPAIGN.yaml -o DIR` and `emrm merge -o OUT DIR...`: campaigns over the ODD
// (docs/campaign.md).

#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "options.hpp"
#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/core/interrupt.hpp"

namespace emrm::cli {
namespace {

struct SweepCommandOptions {
  std::string campaign_file;
  std::string output_dir;
  int threads = 0;
  std::string shard = "1/1";
  bool force = false;
  std::string profile;
  std::string progress_log;
};

struct MergeCommandOptions {
  std::string output_dir;
  std::vector<std::string> dirs;
};

int run_sweep(const SweepCommandOptions& o) {
  campaign::SweepOptions options;
  campaign::parse_shard(o.shard, options.shard_index, options.shard_count);
  options.output_dir = o.output_dir;
  options.threads = o.threads;
  options.progress_log = o.progress_log;
  campaign::Campaign c = campaign::load_campaign(o.campaign_file, o.force);
  if (!o.profile.empty()) campaign::apply_profile(c, o.profile);
  const campaign::SweepSummary s = campaign::sweep(c, options);
  const double rate = s.seconds > 0.0 ? static_cast<double>(s.cells_simulated) / s.seconds : 0.0;
  std::cout << fmt::format(
      "Swept {} cells{} into {}: {} simulated, {} already stored (skipped), {:.1f} s, {:.1f} cells/s\n",
      s.cells_total,
      options.shard_count > 1 ? fmt::format(" (shard {}/{})", options.shard_index, options.shard_count)
                              : std::string(),
      o.output_dir, s.cells_simulated, s.cells_done_before, s.seconds, rate);
  std::cout << fmt::format("Wrote {0}/results.sqlite, {0}/regions.csv, {0}/cells.csv, {0}/cells.json\n",
                           o.output_dir);
  return static_cast<int>(ExitCode::kSuccess);
}

int run_merge(const MergeCommandOptions& o) {
  std::vector<std::filesystem::path> dirs(o.dirs.begin(), o.dirs.end());
  campaign::merge(dirs, o.output_dir);
  const auto store =
      campaign::ResultStore::open_for_reading(std::filesystem::path(o.output_dir) / "results.sqlite");
  std::cout << fmt::format("Merged {} folders into {}: {} cells (config hash {})\n", dirs.size(),
                           o.output_dir, store.cell_count(), store.meta().config_hash);
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_sweep_commands(CLI::App& app, int& exit_code) {
  auto s = std::make_shared<SweepCommandOptions>();
  auto* sweep =
      app.add_subcommand("sweep",
                         "Simulate every cell of a campaign's grids in parallel into DIR/results.sqlite\n"
                         "(resumable: a rerun skips stored cells) and export regions.csv and cells.csv.");
  sweep->add_option("campaign", s->campaign_file, "Campaign file (docs/campaign.md)")
      ->required();
  sweep->add_option("-o,--output", s->output_dir, "Output folder")->required();
  add_threads_option(sweep, s->threads, "Worker threads (0: all cores)")->capture_default_str();
  sweep
      ->add_option("--shard", s->shard,
                   "Take only shard K of N (K/N, 1 <= K <= N); join shards with `emrm merge`")
      ->capture_default_str();
  sweep->add_flag("--force", s->force, "Allow grids of more than max_cells cells");
  sweep->add_option("--profile", s->profile,
                    "Actuation profile overlaying the scene: a NAME in the scene's profiles/ folder or a FILE "
                    "(docs/actuation.md)");
  sweep->add_option("--progress-log", s->progress_log,
                    "Also write the progress to FILE, one JSON line per commit: done, total, elapsed_s, eta_s")
      ->type_name("FILE");
  sweep->callback([s, &exit_code] {
    const core::InterruptScope interrupts;  // Ctrl-C keeps what is done (docs/campaign.md)
    exit_code = run_sweep(*s);
  });

  auto m = std::make_shared<MergeCommandOptions>();
  auto* merge =
      app.add_subcommand("merge",
                         "Join the results stores of shards of one campaign (same config hash) into\n"
                         "OUT/results.sqlite and write its exports.");
  merge->add_option("-o,--output", m->output_dir, "Output folder")->required();
  merge->add_option("dirs", m->dirs, "Folders written by `emrm sweep --shard K/N`")
      ->required()
      ->check(CLI::ExistingDirectory);
  merge->callback([m, &exit_code] { exit_code = run_merge(*m); });
}

}  // namespace emrm::cli
