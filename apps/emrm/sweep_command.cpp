// `emrm sweep CAMPAIGN.yaml -o DIR` and `emrm merge -o OUT DIR...`: campaigns over the ODD
// (docs/campaign.md).

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "emrm/campaign/adaptive.hpp"
#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/cluster/mpi_sweep.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/sim/scene.hpp"
#include "mpi_options.hpp"
#include "options.hpp"

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
  bool adaptive = false;
  /// --initial-levels, --stride and --spread bound to it, their defaults the search's own.
  campaign::adaptive::Options search;
  std::string verify_sample = "auto";  ///< "auto": search.verify_sample's none
  std::string brackets{campaign::adaptive::brackets_name(search.brackets)};
  MpiOptions mpi;
};

struct MergeCommandOptions {
  std::string output_dir;
  std::vector<std::string> dirs;
};

double percent(std::size_t part, std::size_t whole) {
  return whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

// The adaptive search of one grid in three lines: what it cost, what the sample found, what broke
// monotonicity.
void print_adaptive(const campaign::AdaptiveSummary& a) {
  std::cout << fmt::format("grid '{}': simulated {} of {} cells ({:.1f} %); {} inferred ({} by the stop boundary)\n",
                           a.grid, a.simulated, a.feasible, percent(a.simulated, a.feasible), a.inferred,
                           a.inferred_stop);
  if (a.verify_sampled > 0)
    std::cout << fmt::format(
        "  verification: {} of {} sampled inferred cells disagreed ({:.1f} %; 95 % Wilson interval {:.1f} to "
        "{:.1f} %)\n",
        a.verify_disagreements, a.verify_sampled, percent(a.verify_disagreements, a.verify_sampled),
        100.0 * a.disagreement_low, 100.0 * a.disagreement_high);
  else
    std::cout << "  verification: none (--verify-sample 0, or nothing inferred from simulations)\n";
  std::cout << fmt::format("  monotonicity: {} violation{} found, {} line{} resolved in full around them\n",
                           a.violations, a.violations == 1 ? "" : "s", a.lines_fully_resolved,
                           a.lines_fully_resolved == 1 ? "" : "s");
}

// Every option but the shard (an MPI sweep refuses one).
campaign::SweepOptions sweep_options(const SweepCommandOptions& o) {
  campaign::SweepOptions options;
  options.output_dir = o.output_dir;
  options.threads = o.threads;
  options.progress_log = o.progress_log;
  options.adaptive = o.adaptive;
  options.search = o.search;
  if (o.verify_sample != "auto")
    options.search.verify_sample = std::stoul(o.verify_sample);               // checked by its validator
  options.search.brackets = *campaign::adaptive::brackets_named(o.brackets);  // checked by IsMember
  return options;
}

campaign::Campaign load(const SweepCommandOptions& o) {
  campaign::Campaign c = campaign::load_campaign(o.campaign_file, o.force);
  if (!o.profile.empty()) campaign::apply_profile(c, o.profile);
  return c;
}

void print_swept(const campaign::SweepSummary& s, const SweepCommandOptions& o, const std::string& shard) {
  const double rate = s.seconds > 0.0 ? static_cast<double>(s.cells_simulated) / s.seconds : 0.0;
  std::cout << fmt::format(
      "Swept {} cells{} into {}: {} simulated, {} already stored (skipped), {:.1f} s, {:.1f} cells/s\n", s.cells_total,
      shard, o.output_dir, s.cells_simulated, s.cells_done_before, s.seconds, rate);
}

// A grid none of whose cells is feasible is almost always a unit slip (a TTC in ms, a speed in
// m/s): the sweep succeeds, and says so on stderr with the first cell's reason.
void warn_of_infeasible_grids(const SweepCommandOptions& o, const campaign::Campaign& c,
                              const std::vector<campaign::GridCount>& grids) {
  for (const auto& g : grids) {
    if (g.cells == 0 || g.feasible > 0) continue;
    const auto spec = std::find_if(c.grids.begin(), c.grids.end(), [&](const auto& s) { return s.name == g.grid; });
    const std::string reason = spec != c.grids.end() && !spec->cells.empty()
                                   ? sim::Scene(c.scene, spec->cells.front()).infeasible_reason()
                                   : std::string("the factors' units are those 'emrm families' names");
    fmt::print(stderr, "{}: warning: grid '{}' has no feasible cell among its {}; its first: {}\n", o.campaign_file,
               g.grid, core::counted(g.cells, "cell", "cells"), reason);
  }
}

void print_wrote(const SweepCommandOptions& o) {
  std::cout << fmt::format("Wrote {0}/results.sqlite, {0}/regions.csv, {0}/cells.csv, {0}/cells.json\n", o.output_dir);
}

int run_sweep(const SweepCommandOptions& o) {
  campaign::SweepOptions options = sweep_options(o);
  campaign::parse_shard(o.shard, options.shard_index, options.shard_count);
  const campaign::Campaign c = load(o);
  const campaign::SweepSummary s = campaign::sweep(c, options);
  print_swept(s, o,
              options.shard_count > 1 ? fmt::format(" (shard {}/{})", options.shard_index, options.shard_count)
                                      : std::string());
  for (const auto& a : s.adaptive) print_adaptive(a);
  print_wrote(o);
  warn_of_infeasible_grids(o, c, s.grids);
  return static_cast<int>(ExitCode::kSuccess);
}

// Rank 0 of `mpirun -n N emrm sweep ... --mpi` (docs/cluster.md); the other ranks print nothing,
// not even an error rank 0 reports.
int run_sweep_mpi(const SweepCommandOptions& o, cluster::Ranks& ranks) {
  if (o.shard != "1/1")
    throw UsageError("--mpi with --shard: the ranks share the campaign out among themselves; leave out --shard");
  campaign::SweepOptions options = sweep_options(o);
  options.distributor = &ranks.distributor();
  const campaign::Campaign c = load(o);
  const auto s = ranks.summary(campaign::sweep(c, options));
  print_swept(s.sweep, o, fmt::format(" on {} MPI rank{}", ranks.size(), ranks.size() == 1 ? "" : "s"));
  for (const auto& a : s.sweep.adaptive) print_adaptive(a);
  std::string per_rank;
  for (std::size_t r = 0; r < s.ranks.size(); ++r)
    per_rank += fmt::format("{}{:.2f}", r == 0 ? "" : ", ", s.ranks[r].simulation_seconds);
  std::cout << fmt::format("Simulation seconds per rank: {} (threads {}); busiest {:.1f} % above the mean per thread\n",
                           per_rank, s.ranks[0].threads, 100.0 * cluster::busiest_above_mean(s.ranks));
  if (s.cells_sent > 0) {
    const auto per_cell_ms = [&](double seconds) { return 1e3 * seconds / static_cast<double>(s.cells_sent); };
    std::cout << fmt::format(
        "Coordination on rank 0: {:.4f} ms per cell handed out answering messages, {:.4f} ms with the probing "
        "between them ({} cells in {} chunks); its commits {:.4f} ms per cell\n",
        per_cell_ms(s.handling_seconds), per_cell_ms(s.coordination_seconds), s.cells_sent, s.chunks,
        per_cell_ms(s.committing_seconds));
  }
  for (const int rank : s.lost_ranks)
    std::cout << fmt::format("Rank {} said nothing for {:g} s and was given up; the other ranks simulated its cells\n",
                             rank, o.mpi.hung_after_s);
  print_wrote(o);
  warn_of_infeasible_grids(o, c, s.sweep.grids);
  return static_cast<int>(ExitCode::kSuccess);
}

int run_merge(const MergeCommandOptions& o) {
  std::vector<std::filesystem::path> dirs(o.dirs.begin(), o.dirs.end());
  campaign::merge(dirs, o.output_dir);
  const auto store = campaign::ResultStore::open_for_reading(results::ResultsDir(o.output_dir).store());
  std::cout << fmt::format("Merged {} folders into {}: {} cells (config hash {})\n", dirs.size(), o.output_dir,
                           store.cell_count(), store.meta().config_hash);
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_sweep_commands(CLI::App& app, int& exit_code) {
  auto s = std::make_shared<SweepCommandOptions>();
  auto* sweep = app.add_subcommand("sweep",
                                   "Simulate every cell of a campaign's grids in parallel into DIR/results.sqlite\n"
                                   "(resumable: a rerun skips stored cells) and export regions.csv and cells.csv.");
  sweep->add_option("campaign", s->campaign_file, "Campaign file (docs/campaign.md)")->required();
  sweep->add_option("-o,--output", s->output_dir, "Output folder")->required();
  add_threads_option(sweep, s->threads, "Worker threads (0: all cores)")->capture_default_str();
  sweep->add_option("--shard", s->shard, "Take only shard K of N (K/N, 1 <= K <= N); join shards with `emrm merge`")
      ->capture_default_str();
  sweep->add_flag("--force", s->force, "Allow grids of more than max_cells cells");
  sweep->add_option("--profile", s->profile,
                    "Actuation profile overlaying the scene: a NAME in the scene's profiles/ folder or a FILE "
                    "(docs/actuation.md)");
  sweep
      ->add_option("--progress-log", s->progress_log,
                   "Also write the progress to FILE, one JSON line per commit: done, total, elapsed_s, eta_s")
      ->type_name("FILE");
  sweep->add_flag("--adaptive", s->adaptive,
                  "Adaptive boundary search on every product grid: simulate only the cells near region "
                  "boundaries and infer the rest (docs/adaptive.md)");
  sweep
      ->add_option("--verify-sample", s->verify_sample,
                   "Adaptive: inferred cells re-simulated at random to measure the disagreement rate (0 to "
                   "1000000, or auto: 0.5 % of the feasible cells, 20 to 500)")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            if (value == "auto") return {};
            std::size_t n = 0;
            const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
            if (ec != std::errc() || end != value.data() + value.size() || n > 1000000)
              return fmt::format("expected auto or a whole number from 0 to 1000000, got '{}'", shortened(value));
            return {};
          },
          "auto|0..1000000"))
      ->capture_default_str();
  sweep
      ->add_option("--initial-levels", s->search.initial_levels,
                   "Adaptive: lines searched per factor before refining (2 to 1000; 0: automatic)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1000}, "0 to 1000") & !CLI::IsMember({std::size_t{1}}))
      ->capture_default_str();
  sweep
      ->add_option("--stride", s->search.stride,
                   "Adaptive: unavoidable cells along a line sampled every N cells (1 to 1000; 1 simulates all)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000}, "1 to 1000"))
      ->capture_default_str();
  sweep
      ->add_option("--brackets", s->brackets,
                   "Adaptive: a line between corners whose thresholds agree within a level searches its own "
                   "(search), takes the one predicted from them (predict), or auto: predict on grids of three "
                   "factors or more")
      ->check(CLI::IsMember(std::vector<std::string>(campaign::adaptive::kBracketsNames.begin(),
                                                     campaign::adaptive::kBracketsNames.end())))
      ->capture_default_str();
  sweep
      ->add_option("--spread", s->search.spread,
                   "Adaptive, where brackets are predicted: corners whose avoidance thresholds or early runs "
                   "differ by up to N TTC levels still agree, and the lines between take what they predict "
                   "(1 to 1000)")
      ->check(CLI::Range(std::uint32_t{1}, std::uint32_t{1000}, "1 to 1000"))
      ->capture_default_str();
  add_mpi_options(sweep, s->mpi, "mpirun -n N emrm sweep ... --mpi");
  sweep->callback([s, &exit_code] {
    const core::InterruptScope interrupts;  // Ctrl-C keeps what is done (docs/campaign.md)
    exit_code = on_ranks(s->mpi, s->threads, [&](cluster::Ranks* ranks) {
      return ranks != nullptr ? run_sweep_mpi(*s, *ranks) : run_sweep(*s);
    });
  });

  auto m = std::make_shared<MergeCommandOptions>();
  auto* merge = app.add_subcommand("merge",
                                   "Join the results stores of shards of one campaign (same config hash) into\n"
                                   "OUT/results.sqlite and write its exports.");
  merge->add_option("-o,--output", m->output_dir, "Output folder")->required();
  merge->add_option("dirs", m->dirs, "Folders written by `emrm sweep --shard K/N`")
      ->required()
      ->check(CLI::ExistingDirectory);
  merge->callback([m, &exit_code] { exit_code = run_merge(*m); });
}

}  // namespace emrm::cli
