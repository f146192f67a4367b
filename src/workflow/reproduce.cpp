// `emrm reproduce -o DIR`: the paper's whole case study on the shipped T-junction example —
// analysis of the safety case, checks of both FSMs, the campaign sweep, the profiles side by side,
// the tables beside the paper's numbers, diagnostics, the planned set and its run, the report.

#include "emrm/workflow/reproduce.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/core/table.hpp"
#include "emrm/core/text.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/fsm/report.hpp"
#include "emrm/report/report.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/diagnostics.hpp"
#include "emrm/results/paper_reference.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/sensitivity.hpp"
#include "emrm/results/tables.hpp"
#include "emrm/results/verify.hpp"
#include "emrm/safety/analysis.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/workflow/plan_checks.hpp"
#include "emrm/workflow/profiles.hpp"
#include "emrm/workflow/run.hpp"
#include "emrm/workflow/safety_case.hpp"

namespace emrm::workflow {
namespace {

namespace fs = std::filesystem;

// What an example folder holds; paper_reference.yaml (published numbers to show beside ours) is optional.
constexpr const char* kExampleFiles[] = {"safety.yaml", "emrm_fsm.yaml", "loss_evaluation_fsm.yaml", "campaign.yaml",
                                         "odd.yaml"};
constexpr const char* kPaperReferenceFile = "paper_reference.yaml";

bool is_example_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "campaign.yaml", ec) && fs::is_regular_file(dir / "safety.yaml", ec);
}

std::string pct(double v) { return core::format_number(v, 1); }

// Steps 1–4: the safety case, written as `emrm analyze -o DIR/analysis` would.
bool run_analysis(const fs::path& examples, const fs::path& out) {
  const auto safety_file = examples / "safety.yaml";
  const safety::Analysis analysis = analyze_safety_file(safety_file);
  const auto dir = results::ResultsDir(out).analysis_dir();
  safety::write_analysis(dir, analysis);
  const auto& c = analysis.safety_case;
  fmt::print("analysis  {}: {}, {}, {}; {}, {}; {} -> {}\n", safety_file.string(),
             core::counted(c.losses.size(), "loss", "losses"), core::counted(c.hazards.size(), "hazard", "hazards"),
             core::counted(c.ucas.size(), "UCA", "UCAs"), core::counted(analysis.errors(), "error", "errors"),
             core::counted(analysis.warnings(), "warning", "warnings"),
             core::counted(analysis.matrix.size(), "traceability row", "traceability rows"), dir.string());
  return analysis.errors() == 0;
}

// Step 5: the structural checks of one FSM, as `emrm fsm FILE --check --format json`, and its
// plain diagram.
bool run_fsm_check(const fs::path& file, const fs::path& out) {
  const fsm::Report report = fsm::write_check_files(file, results::ResultsDir(out).fsm_dir());
  const fsm::Generator& g = report.machine;
  const fsm::CheckReport& r = *report.check;
  fmt::print(
      "fsm       {}: {} states, {} transitions; accessible {}, co-accessible {}, deterministic {}, "
      "non-blocking {}\n",
      file.string(), g.states().size(), g.transitions().size(), r.accessible.ok() ? "ok" : "FAILED",
      r.coaccessible.ok() ? "ok" : "FAILED", r.deterministic.ok() ? "ok" : "FAILED",
      r.nonblocking.ok() ? "ok" : "FAILED");
  return r.ok();
}

}  // namespace

// ./examples/tjunction, then the same under every parent folder (running from inside a build tree),
// then next to the executable (an installed tree's share/emrm).
fs::path find_examples(const fs::path& examples_dir) {
  if (!examples_dir.empty()) {
    if (!fs::is_directory(examples_dir))
      throw UsageError(fmt::format("--examples: '{}' is not a folder", examples_dir.string()));
    for (const char* name : kExampleFiles)
      if (!fs::is_regular_file(fs::path(examples_dir) / name))
        throw UsageError(fmt::format("--examples: '{}' has no {} (expected {})", examples_dir.string(), name,
                                     core::join({std::begin(kExampleFiles), std::end(kExampleFiles)}, ", ")));
    return examples_dir;
  }
  std::vector<fs::path> tried;
  std::error_code ec;
  for (fs::path dir = fs::current_path(ec); !dir.empty(); dir = dir.parent_path()) {
    tried.push_back(dir / "examples" / "tjunction");
    if (is_example_dir(tried.back())) return tried.back();
    if (dir == dir.root_path()) break;
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    tried.push_back(exe.parent_path() / ".." / "share" / "emrm" / "examples" / "tjunction");
    if (is_example_dir(tried.back())) return fs::weakly_canonical(tried.back());
    for (fs::path dir = exe.parent_path(); !dir.empty() && dir != dir.root_path(); dir = dir.parent_path()) {
      tried.push_back(dir / "examples" / "tjunction");
      if (is_example_dir(tried.back())) return tried.back();
    }
  }
  throw UsageError(fmt::format(
      "cannot find the shipped example folder examples/tjunction (looked in the current folder, its parents "
      "and {}); run from the repository or pass --examples DIR",
      tried.empty() ? std::string("nowhere") : (exe.parent_path() / ".." / "share" / "emrm" / "examples").string()));
}

bool reproduce(const ReproduceOptions& options, campaign::Distributor* distributor) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path examples = find_examples(options.examples_dir);
  const fs::path out = options.output_dir;
  const results::ResultsDir folder(out);
  // Read every input before any long work, so bad input fails in a second and not after the sweep.
  campaign::Campaign plan = campaign::load_campaign(examples / "campaign.yaml");
  if (!options.profile.empty()) campaign::apply_profile(plan, options.profile);
  const results::PaperReference paper = fs::is_regular_file(examples / kPaperReferenceFile)
                                            ? results::load_paper_reference(examples / kPaperReferenceFile)
                                            : results::PaperReference{};
  const scenario::Odd odd = scenario::load_odd(examples / "odd.yaml", std::nullopt, workflow::family_levels);
  workflow::check_odd_against_scene(odd, workflow::plan_scene(odd));
  fmt::print("emrm reproduce: example {} -> {}\n", examples.string(), out.string());

  bool ok = run_analysis(examples, out);
  ok = run_fsm_check(examples / "emrm_fsm.yaml", out) && ok;
  ok = run_fsm_check(examples / "loss_evaluation_fsm.yaml", out) && ok;

  campaign::SweepOptions sweep_options;
  sweep_options.output_dir = out;
  sweep_options.threads = options.threads;
  sweep_options.progress = options.progress;
  sweep_options.distributor = distributor;
  const auto s = campaign::sweep(plan, sweep_options);
  fmt::print("sweep     {}: {} cells, {} already stored, {} simulated in {:.1f} s -> {}\n",
             (examples / "campaign.yaml").string(), s.cells_total, s.cells_done_before, s.cells_simulated, s.seconds,
             folder.store().string());

  // Every claim of the store re-checked without trusting the sweep (docs/verify.md).
  const auto verified = results::verify_results(folder.store());
  results::write_verify_report(out, verified);
  fmt::print(
      "verify    {} cells, {} maneuvers replayed, {} avoidances re-checked every ms, {} certificates, {} undecided: "
      "{} -> {}\n",
      verified.cells, verified.witnesses, verified.avoidances, verified.certificates, verified.undecided,
      verified.ok() ? "all claims hold" : fmt::format("{} claims FAIL", verified.failures.size()),
      folder.verify_json().string());
  ok = verified.ok() && ok;

  const auto records = campaign::read_results(folder.store());
  results::TableOptions table_options;
  table_options.grid = results::headline_grid(records, paper.fine_grid.grid);
  table_options.cuts = paper.empty() ? results::level_cuts_by_thirds(plan.scene, records, table_options.grid)
                                     : results::level_cuts(plan.scene);
  table_options.actuation = plan.scene.actuation;
  // The tables written, by stem, in the order written (what the summary lists).
  std::vector<std::string> table_stems;
  const auto written = [&](const std::vector<fs::path>& files) {
    for (const auto& f : files)
      if (f.extension() == ".md") table_stems.push_back(f.stem().string());
  };
  written(results::write_tables(out, records, paper, table_options));
  if (sim::stop_boundary_applies(plan.scene))  // the closed form: a family without the stop boundary has none
    written(
        core::write_table(folder.tables_dir(), "brake_sensitivity",
                          results::brake_sensitivity_table(records, paper, table_options.grid, plan.scene.actuation)));

  // The headline grid under every profile of the scene's folder, side by side (docs/actuation.md).
  if (const auto profiles = results::scene_profiles(plan); !profiles.empty()) {
    const auto runs = workflow::sweep_profiles(plan, table_options.grid, profiles, sweep_options);
    std::vector<std::vector<campaign::CellRecord>> per_profile;
    std::vector<std::string> parts;
    for (const auto& run : runs) {
      per_profile.push_back(campaign::read_results(out / run.store));
      const auto c = results::count_regions(per_profile.back(), table_options.grid);
      parts.push_back(fmt::format(
          "{} G {} Y {} O {} R {}{}", run.name, pct(c.pct(c.g)), pct(c.pct(c.y)), pct(c.pct(c.o)), pct(c.pct(c.r)),
          run.reused ? " (this scene)" : fmt::format(" ({} simulated in {:.1f} s)", run.simulated, run.seconds)));
    }
    written(core::write_table(folder.tables_dir(), "regions_by_profile",
                              results::profiles_table(runs, per_profile, paper, table_options.grid)));
    fmt::print("profiles  grid '{}' per profile (%): {} -> {}\n", table_options.grid, core::join(parts, "; "),
               folder.profiles_dir().string());
  }

  results::DiagnosticsOptions diagnostics_options;
  diagnostics_options.reference_sample = options.sample;
  diagnostics_options.seed = plan.seed;
  diagnostics_options.threads = options.threads;
  const auto diagnostics = results::run_diagnostics(records, plan.scene, diagnostics_options);
  results::write_diagnostics(out, diagnostics);

  // Steps 6–7 (paper §V-B): the minimum scenario set, checked, compared with the baselines, run.
  const auto plan_start = std::chrono::steady_clock::now();
  const scenario::Plan scenario_plan = scenario::build_plan(odd);
  const auto coverage = scenario::coverage_comparison(odd, scenario_plan);
  scenario::write_plan(folder.plan().root(), odd, scenario_plan, coverage);
  const core::Table coverage_table = results::coverage_comparison_table(coverage, paper);
  written(core::write_table(folder.tables_dir(), "coverage", coverage_table));
  const double plan_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - plan_start).count();
  const auto& ours = coverage.front();
  ok = ours.all() && ok;
  fmt::print(
      "plan      {}: {} scenarios for {} relevant cells ({} tracked) in {:.2f} s; C1 {}, C2 {}, C3 {}, C4 {}; {} -> "
      "{}\n",
      (examples / "odd.yaml").string(), scenario_plan.scenarios.size(), scenario_plan.relevant_cells,
      scenario_plan.tracked_cells, plan_seconds, ours.c1 ? "holds" : "FAILS", ours.c2 ? "holds" : "FAILS",
      ours.c3 ? "holds" : "FAILS", ours.c4 ? "holds" : "FAILS", scenario_plan.stop_reason,
      folder.plan().root().string());
  workflow::RunOptions run_options;
  run_options.scenarios_csv = folder.plan().scenarios_csv();
  run_options.output_dir = folder.plan_results().root();
  run_options.threads = options.threads;
  run_options.progress = sweep_options.progress;
  run_options.profile = options.profile;
  run_options.distributor = distributor;
  const workflow::RunResult run = workflow::run_scenarios(run_options);
  const auto& all = run.subsets.front().estimate;
  fmt::print(
      "run       {} scenarios in {:.1f} s: S(all) = {:.3f} (Wilson [{:.3f}, {:.3f}] at n_eff {:.1f}); widest "
      "half-width {:.3f} in a tracked cell (target {:g}); EMRM FSM transitions exercised {}/{} -> {}\n",
      run.outcomes.size(), run.sweep.seconds, all.estimate, all.wilson.low, all.wilson.high, all.n_eff,
      run.widest_tracked_half_width, run.epsilon, run.transitions_exercised, run.transitions_total,
      run_options.output_dir.string());
  fmt::print("\n{}\n{}", coverage_table.title, core::markdown_table(coverage_table.header, coverage_table.rows));

  // The summary: the headline numbers, ours beside the paper's.
  const auto regions = results::count_regions(records, table_options.grid);
  const auto& pr = paper.fine_grid.regions_pct;
  if (paper.empty()) {
    fmt::print("\nRegions of grid '{}' (% of feasible cells; no published numbers beside them):\n", table_options.grid);
    fmt::print("  feasible {}; G {}; Y {}; O {}; R {}\n", regions.feasible, pct(regions.pct(regions.g)),
               pct(regions.pct(regions.y)), pct(regions.pct(regions.o)), pct(regions.pct(regions.r)));
  } else {
    fmt::print("\nRegions of grid '{}' (% of feasible cells), ours vs paper:\n", table_options.grid);
    fmt::print("  feasible {} vs {}; G {} vs {:g}; Y {} vs {:g}; O {} vs {:g}; R {} vs {:g}\n", regions.feasible,
               paper.fine_grid.feasible_cells, pct(regions.pct(regions.g)), pr.g, pct(regions.pct(regions.y)), pr.y,
               pct(regions.pct(regions.o)), pr.o, pct(regions.pct(regions.r)), pr.r);
  }
  const auto table = results::emrm_vs_baseline_table(records, paper, table_options.grid);
  fmt::print("\n{}\n{}", table.title, core::markdown_table(table.header, table.rows));
  fmt::print("\nDiagnostics: {}\n", results::summary(diagnostics));
  const auto report = report::write_report(out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print(
      "\nTables: {}/tables/{{{}}}.{{md,csv,tex}}, kpis.csv; diagnostics: {}/diagnostics.json; FSM diagrams: {}/fsm; "
      "analysis: {}/analysis ({:.1f} s)\n",
      out.string(), core::join(table_stems, ","), out.string(), out.string(), out.string(), seconds);
  fmt::print("Report: {} (figures in {}/figures, drawn in {:.1f} s)\n", report.html.string(), out.string(),
             report.figure_seconds);
  if (!ok)
    fmt::print(
        "reproduce: the analysis found errors, an FSM check failed, the plan misses C1-C4 or a claim of the store "
        "did not verify (exit 1)\n");
  return ok;
}

}  // namespace emrm::workflow
