#include "emrm/workflow/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/diagnostics.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/run_estimates.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/safety/traceability.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::workflow {
namespace {

namespace fs = std::filesystem;

int outcome_success(const campaign::CellRecord& record, const campaign::PlanSettings& settings) {
  for (const auto& o : record.outcomes) {
    if (o.strategy != settings.acceptance_strategy) continue;
    if (settings.acceptance_outcome == "mitigated") return o.avoided || o.delta_loss > 0 ? 1 : 0;
    return o.avoided ? 1 : 0;
  }
  return 0;
}

std::string number(double v) { return fmt::format("{:.6g}", v); }

// Ŝ(A) over the whole set and over each mode's region: every mode of the plan, with or without tests,
// marked with the plan's shortfall for it.
std::vector<SubsetEstimate> subset_estimates(const std::vector<ScenarioOutcome>& outcomes,
                                             const campaign::PlanSettings& settings, double confidence) {
  std::vector<std::string> subsets{"all"};
  const auto add = [&](const std::string& m) {
    if (std::find(subsets.begin(), subsets.end(), m) == subsets.end()) subsets.push_back(m);
  };
  for (const auto& m : settings.malfunctions) add(m);
  for (const auto& o : outcomes)
    for (const auto& m : o.malfunctions) add(m);
  std::sort(subsets.begin() + 1, subsets.end());
  std::vector<SubsetEstimate> out;
  for (const auto& subset : subsets) {
    std::vector<double> w;
    std::vector<int> y;
    for (const auto& o : outcomes) {
      if (!o.feasible) continue;
      if (subset != "all" && std::find(o.malfunctions.begin(), o.malfunctions.end(), subset) == o.malfunctions.end())
        continue;
      w.push_back(o.weight);
      y.push_back(o.success);
    }
    SubsetEstimate e{subset, scenario::weighted_success(w, y, confidence), ""};
    for (const auto& s : settings.shortfalls)
      if (s.subject == subset) e.shortfall = s.message;
    out.push_back(std::move(e));
  }
  return out;
}

// The factor columns of estimates.csv: every factor some cell names, in the order first met.
std::vector<std::string> level_factors(const std::vector<CellEstimate>& cells) {
  std::vector<std::string> out;
  for (const auto& c : cells)
    for (const auto& [factor, label] : c.levels)
      if (std::find(out.begin(), out.end(), factor) == out.end()) out.push_back(factor);
  return out;
}

std::string level_of(const CellEstimate& c, const std::string& factor) {
  for (const auto& [f, label] : c.levels)
    if (f == factor) return label;
  return "";
}

// Where the plan lives, relative to the run's folder, so that `emrm report` finds its coverage.
results::PlanLocation plan_location(const fs::path& scenarios_csv, const fs::path& output_dir) {
  const auto relative = [&](const fs::path& p) {
    std::error_code ec;
    const auto r = fs::relative(fs::absolute(p), fs::absolute(output_dir), ec);
    return (ec || r.empty() ? p : r).generic_string();
  };
  const fs::path coverage = scenario::PlanDir::of(scenarios_csv).coverage_json();
  return {relative(scenarios_csv), fs::is_regular_file(coverage) ? std::optional(relative(coverage)) : std::nullopt};
}

}  // namespace

namespace {

// outcomes.csv (a row per scenario with its factor values) and estimates.csv (a row per cell with
// its bins), docs/plan.md.
std::vector<core::FileContent> run_tables(const fs::path& dir, const RunResult& result) {
  std::vector<core::FileContent> files{
      {results::ResultsDir(dir).outcomes_csv(), results::run_outcomes_csv({result.factors, result.outcomes, {}})}};

  const std::vector<std::string> factors = level_factors(result.cells);
  std::vector<core::Row> rows;
  for (const auto& c : result.cells) {
    core::Row row{c.cell};
    for (const auto& f : factors) row.push_back(level_of(c, f));
    for (const auto& field : {std::to_string(c.n), std::to_string(c.successes),
                              number(static_cast<double>(c.successes) / static_cast<double>(c.n)), number(c.wilson.low),
                              number(c.wilson.high), number(c.wilson.half_width()), number(c.hoeffding_epsilon),
                              std::string(c.tracked ? "yes" : "no")})
      row.push_back(field);
    rows.push_back(std::move(row));
  }
  core::Row header{"cell"};
  header.insert(header.end(), factors.begin(), factors.end());
  for (const char* name :
       {"n", "successes", "rate", "wilson_low", "wilson_high", "wilson_half_width", "hoeffding_epsilon", "tracked"})
    header.emplace_back(name);
  files.push_back({results::ResultsDir(dir).estimates_csv(), core::csv_table(header, rows)});
  return files;
}

}  // namespace

RunResult run_scenarios(const RunOptions& options) {
  const scenario::ScenarioFile file = scenario::read_scenarios_csv(options.scenarios_csv);
  const fs::path settings_file = scenario::PlanDir::of(options.scenarios_csv).scenarios_json();
  campaign::PlanSettings settings =
      fs::is_regular_file(settings_file) ? campaign::read_plan_settings(settings_file) : campaign::PlanSettings{};
  if (settings.acceptance_strategy.empty()) settings.acceptance_strategy = campaign::default_acceptance_strategy();
  if (options.safety_file) settings.safety_file = options.safety_file;
  // The acceptance strategy is simulated even when the plan lists strategies without it.
  if (!settings.strategies.empty() && std::find(settings.strategies.begin(), settings.strategies.end(),
                                                settings.acceptance_strategy) == settings.strategies.end())
    settings.strategies.push_back(settings.acceptance_strategy);

  RunResult result;
  result.confidence = 1.0 - settings.delta;
  result.epsilon = settings.epsilon;

  // The plan as a campaign of one grid whose cells carry the scenarios' own seeds.
  campaign::Campaign campaign;
  campaign.file = file.file;
  campaign.text = core::read_input_file(options.scenarios_csv);
  campaign.seed = settings.seed;
  if (settings.scene_file) {
    if (!fs::is_regular_file(*settings.scene_file))
      throw UsageError(fmt::format("scene file '{}' named by {} does not exist", settings.scene_file->string(),
                                   settings_file.string()));
    campaign.scene_file = settings.scene_file->string();
    campaign.scene = sim::load_scene_config(*settings.scene_file);
  }
  if (!options.profile.empty()) {
    sim::apply_profile(campaign.scene, options.profile, settings.scene_file.value_or("").parent_path());
  }
  if (!settings.strategies.empty()) campaign.strategies = settings.strategies;
  // Every input is read before the sweep writes anything: a broken safety case fails here, not
  // after the store and half the files are written.
  std::optional<safety::SafetyCase> safety_case;
  if (settings.safety_file) safety_case = safety::load_safety_case(*settings.safety_file);
  result.factors = file.factors;
  campaign::GridSpec grid;
  grid.name = campaign::kPlanGrid;
  grid.where = {file.file, 1, 1};
  const sim::FactorTable factors = sim::scenario_factors(campaign.scene);
  for (const auto& name : file.factors)
    if (!factors.find(name)) result.unsimulated_factors.push_back(name);
  for (const auto& row : file.rows) {
    sim::CellInput cell = factors.defaults();
    for (std::size_t i = 0; i < file.factors.size(); ++i) (void)factors.set(cell, file.factors[i], row.values[i]);
    try {
      factors.validate(cell);
    } catch (const UsageError& e) {
      throw InputError(row.where, fmt::format("scenario {}: {}", row.id, e.what()));
    }
    grid.cells.push_back(cell);
    grid.seeds.push_back(row.seed);
  }
  campaign.grids.push_back(std::move(grid));

  campaign::SweepOptions sweep_options;
  sweep_options.output_dir = options.output_dir;
  sweep_options.threads = options.threads;
  sweep_options.progress = options.progress;
  sweep_options.unit = "scenarios";
  sweep_options.distributor = options.distributor;
  result.sweep = campaign::sweep(campaign, sweep_options);

  // Outcomes, in file order.
  const std::vector<campaign::CellRecord> records =
      campaign::read_results(results::ResultsDir(options.output_dir).store());
  std::vector<const campaign::CellRecord*> by_index(file.rows.size(), nullptr);
  for (const auto& r : records)
    if (r.grid == campaign::kPlanGrid && r.index >= 0 && static_cast<std::size_t>(r.index) < by_index.size())
      by_index[static_cast<std::size_t>(r.index)] = &r;
  std::map<std::string, CellEstimate> cells;
  for (std::size_t i = 0; i < file.rows.size(); ++i) {
    const scenario::ScenarioRow& row = file.rows[i];
    const campaign::CellRecord* record = by_index[i];
    if (!record) throw Error(fmt::format("results store lacks scenario {} after the run", row.id));
    ScenarioOutcome o;
    o.id = row.id;
    o.cell = row.cell;
    o.malfunctions = row.malfunctions;
    o.weight = row.weight;
    o.factor_values = row.values;
    o.feasible = record->feasible;
    o.region = core::enum_text(record->region);
    if (record->feasible) {
      o.success = outcome_success(*record, settings);
      for (const auto& out : record->outcomes)
        if (out.strategy == settings.acceptance_strategy) {
          o.chosen_strategy = out.chosen_strategy.empty() ? out.strategy : out.chosen_strategy;
          o.impact_speed_kph = out.impact_speed_kph;
          o.loss_level = out.loss_level;
        }
      CellEstimate& c = cells[row.cell];
      c.cell = row.cell;
      ++c.n;
      c.successes += static_cast<std::size_t>(o.success);
    }
    result.outcomes.push_back(std::move(o));
  }
  for (auto& [key, c] : cells) {
    c.wilson = scenario::wilson_interval(static_cast<double>(c.successes), static_cast<double>(c.n), result.confidence);
    c.hoeffding_epsilon = scenario::hoeffding_epsilon(static_cast<double>(c.n), settings.delta);
    c.tracked = settings.tracked_cells.count(key) > 0;
    if (const auto it = settings.cell_levels.find(key); it != settings.cell_levels.end()) {
      c.levels = it->second;  // in the scenario file's column order
      const auto rank = [&](const auto& level) {
        return std::find(file.factors.begin(), file.factors.end(), level.first) - file.factors.begin();
      };
      std::stable_sort(c.levels.begin(), c.levels.end(),
                       [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
    }
    if (c.tracked) result.widest_tracked_half_width = std::max(result.widest_tracked_half_width, c.wilson.half_width());
    result.cells.push_back(c);
  }

  result.subsets = subset_estimates(result.outcomes, settings, result.confidence);
  result.plan_shortfalls = settings.shortfalls;

  // The EMRM FSM transitions the runs took.
  const results::FsmCoverage fc = results::emrm_fsm_coverage(records, sim::default_emrm_fsm());
  result.transitions_total = fc.transitions.size();
  result.transitions_exercised = fc.coverage.covered;
  for (std::size_t t = 0; t < fc.transitions.size(); ++t)
    if (fc.coverage.counts[t] == 0) result.transitions_missed.push_back(fc.transitions[t].str());

  // Files, all composed first and then written together (the sweep wrote the store and its exports).
  const fs::path& dir = options.output_dir;
  std::vector<core::FileContent> files = run_tables(dir, result);
  if (safety_case) {
    auto matrix = safety::traceability_matrix(*safety_case);
    for (auto& row : matrix)
      for (const auto& o : result.outcomes)
        if (std::find(o.malfunctions.begin(), o.malfunctions.end(), row.uca) != o.malfunctions.end())
          row.scenarios.push_back(o.id);
    result.traceability_rows = matrix.size();
    for (auto& f : safety::traceability_files(dir, safety_case->name, matrix)) files.push_back(std::move(f));
  }
  results::RunEstimates estimates = estimates_of(result);
  estimates.acceptance = {settings.acceptance_strategy, settings.acceptance_outcome};
  estimates.factors = settings.factors;  // the report groups by the ODD's levels
  estimates.plan = plan_location(options.scenarios_csv, dir);
  files.push_back({results::ResultsDir(dir).estimates_json(), results::run_estimates_text(estimates)});
  core::write_files(files);
  return result;
}

std::string to_text(const RunResult& result, const std::string& scenarios_file, const fs::path& output_dir) {
  std::string out;
  const auto feasible =
      std::count_if(result.outcomes.begin(), result.outcomes.end(), [](const auto& s) { return s.feasible; });
  out += fmt::format("run       {}: {} scenarios ({} feasible), {} simulated, {} already stored, {:.1f} s\n",
                     scenarios_file, result.outcomes.size(), feasible, result.sweep.cells_simulated,
                     result.sweep.cells_done_before, result.sweep.seconds);
  for (const auto& s : result.plan_shortfalls) out += fmt::format("warning: the plan fell short: {}\n", s.message);
  if (!result.unsimulated_factors.empty())
    out += fmt::format("  not simulated (carried through only): {}\n", core::join(result.unsimulated_factors, ", "));
  const auto tracked = std::count_if(result.cells.begin(), result.cells.end(), [](const auto& c) { return c.tracked; });
  out += fmt::format(
      "  {} cells, {} tracked; widest Wilson {:.0f} % half-width in a tracked cell {:.3f} (target {:g})\n",
      result.cells.size(), tracked, 100.0 * result.confidence, result.widest_tracked_half_width, result.epsilon);
  for (const auto& s : result.subsets) {
    const auto& e = s.estimate;
    if (e.n == 0) {
      out += fmt::format("  S({}): no tests{}\n", s.subset, s.shortfall.empty() ? "" : " (a plan shortfall, above)");
      continue;
    }
    out += fmt::format("  S({}) = {:.3f}  ({} tests, n_eff {:.1f}, Wilson [{:.3f}, {:.3f}])\n", s.subset, e.estimate,
                       e.n, e.n_eff, e.wilson.low, e.wilson.high);
  }
  out +=
      fmt::format("  EMRM FSM transitions exercised: {}/{}{}\n", result.transitions_exercised, result.transitions_total,
                  result.transitions_missed.empty() ? std::string()
                                                    : " (never: " + core::join(result.transitions_missed, ", ") + ")");
  if (result.traceability_rows > 0)
    out += fmt::format("  traceability: {} rows with their scenarios -> {}\n", result.traceability_rows,
                       results::ResultsDir(output_dir).traceability_csv().string());
  out += fmt::format("  -> {}/estimates.json, estimates.csv, outcomes.csv, results.sqlite\n", output_dir.string());
  if (!result.plan_shortfalls.empty())
    out += fmt::format("run       {} of the plan (scenarios.json): the estimates above lack them\n",
                       core::counted(result.plan_shortfalls.size(), "shortfall", "shortfalls"));
  return out;
}

results::RunEstimates estimates_of(const RunResult& r) {
  results::RunEstimates e;
  e.scenarios = r.outcomes.size();
  e.feasible = static_cast<std::size_t>(
      std::count_if(r.outcomes.begin(), r.outcomes.end(), [](const auto& o) { return o.feasible; }));
  e.confidence = r.confidence;
  e.unsimulated_factors = r.unsimulated_factors;
  for (const auto& s : r.subsets) {
    const auto& w = s.estimate;
    e.weighted_success.emplace_back(
        s.subset, results::SubsetSuccess{.n = w.n,
                                         .weight = w.weight,
                                         .n_eff = w.n_eff,
                                         .estimate = std::isnan(w.estimate) ? std::nullopt : std::optional(w.estimate),
                                         .wilson = w.wilson,
                                         .shortfall = s.shortfall.empty() ? std::nullopt : std::optional(s.shortfall)});
  }
  for (const auto& c : r.cells) {
    e.widest_wilson_half_width = std::max(e.widest_wilson_half_width, c.wilson.half_width());
    e.cells.push_back({.cell = c.cell,
                       .levels = c.levels,
                       .n = c.n,
                       .successes = c.successes,
                       .wilson = c.wilson,
                       .hoeffding_epsilon = c.hoeffding_epsilon,
                       .tracked = c.tracked});
    if (c.tracked) ++e.tracked_cells;
  }
  e.widest_tracked_wilson_half_width = r.widest_tracked_half_width;
  e.epsilon = r.epsilon;
  e.fsm_transitions = {r.transitions_exercised, r.transitions_total, r.transitions_missed};
  e.traceability_rows = r.traceability_rows;
  e.shortfalls = r.plan_shortfalls;
  return e;
}

}  // namespace emrm::workflow
