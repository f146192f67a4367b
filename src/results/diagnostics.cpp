#include "emrm/results/diagnostics.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <thread>
#include <tuple>

#include "emrm/core/json_archive.hpp"
#include "emrm/core/text.hpp"
#include "emrm/fsm/dot.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::results {
namespace {

using Json = nlohmann::ordered_json;

// Cells compared along one factor share every other factor exactly: they come from one grid's
// expansion of the same list values, so exact equality is the right test.
using GroupKey = std::vector<double>;  // every factor but the one compared along

void count_along(const std::vector<const campaign::CellRecord*>& cells, const std::string& grid, std::size_t along,
                 const std::string& factor, const std::vector<std::string>& strategies, std::size_t max_examples,
                 MonotonicityCheck& out) {
  std::map<GroupKey, std::vector<const campaign::CellRecord*>> groups;
  for (const auto* c : cells) {
    GroupKey key(c->factors.begin(), c->factors.end());
    key.erase(key.begin() + static_cast<std::ptrdiff_t>(along));
    groups[key].push_back(c);
  }
  const auto value = [&](const campaign::CellRecord* c) { return c->factors[along]; };
  for (const auto& strategy : strategies) {
    ReversalCount count{grid, strategy, factor, 0, 0};
    for (auto& [key, group] : groups) {
      std::sort(group.begin(), group.end(), [&](auto* a, auto* b) { return value(a) < value(b); });
      for (std::size_t i = 0; i + 1 < group.size(); ++i) {
        const auto* lo = group[i]->outcome(strategy);
        const auto* hi = group[i + 1]->outcome(strategy);
        if (lo == nullptr || hi == nullptr || value(group[i]) == value(group[i + 1])) continue;
        ++count.pairs;
        if (lo->avoided && !hi->avoided) {
          ++count.reversals;
          ++out.total_reversals;
          if (out.examples.size() < max_examples)
            out.examples.push_back({grid, strategy, factor, cell_ref(*group[i]), cell_ref(*group[i + 1])});
        }
      }
    }
    if (count.pairs > 0) out.counts.push_back(count);
  }
}

FsmCoverage coverage_of(const fsm::Generator& g, const std::vector<std::vector<std::string>>& words) {
  FsmCoverage c;
  c.fsm = g.name();
  c.traces = words.size();
  c.coverage = fsm::transition_coverage(g, words);
  c.transitions = g.transitions();
  c.generator = &g;
  return c;
}

Json cell_json(const CellRef& c, const sim::FactorTable& factors) {
  Json j{{"grid", c.grid}, {"index", c.index}};
  for (std::size_t f = 0; f < factors.size() && f < c.factors.size(); ++f) j[factors[f].key] = c.factors[f];
  j["region"] = core::enum_text(c.region);
  return j;
}

Json cells_json(const std::vector<CellRef>& cells, const sim::FactorTable& factors) {
  Json out = Json::array();
  for (const auto& c : cells) out.push_back(cell_json(c, factors));
  return out;
}

Json coverage_json(const FsmCoverage& c) {
  Json transitions = Json::array();
  for (std::size_t i = 0; i < c.transitions.size(); ++i) {
    const auto& t = c.transitions[i];
    transitions.push_back({{"from", t.from}, {"event", t.event}, {"to", t.to}, {"count", c.coverage.counts[i]}});
  }
  return {{"fsm", c.fsm},
          {"traces", c.coverage.traces},
          {"accepted", c.coverage.accepted},
          {"rejected", c.coverage.rejected.size()},
          {"covered", c.coverage.covered},
          {"total", c.coverage.counts.size()},
          {"fraction", c.coverage.fraction()},
          {"transitions", transitions}};
}

}  // namespace

CellRef cell_ref(const campaign::CellRecord& r) { return {r.grid, r.index, r.factors, r.region}; }

StopBoundaryCheck check_stop_boundary(const std::vector<campaign::CellRecord>& records, double latency_s) {
  sim::ActuationConfig actuation;
  actuation.perception_latency_s = latency_s;
  return check_stop_boundary(records, actuation);
}

namespace {

StopBoundaryCheck stop_boundary_check(const std::vector<campaign::CellRecord>& records,
                                      const sim::ActuationConfig& actuation, const sim::SceneConfig* scene) {
  StopBoundaryCheck c;
  c.latency_s = actuation.perception_latency_s;
  c.actuation = actuation;
  c.applies = scene == nullptr || sim::stop_boundary_applies(*scene);
  for (const auto& r : records) {
    if (!r.feasible) continue;
    ++c.feasible;
    if (!c.applies) continue;
    const bool stoppable = sim::analytically_stoppable(r.factors, actuation);
    if (stoppable) {
      ++c.stoppable;
      if (r.region == sim::Region::kR) c.stoppable_red.push_back(cell_ref(r));
      if (r.region != sim::Region::kG) c.stoppable_not_green.push_back(cell_ref(r));
    } else if (r.region == sim::Region::kG) {
      const bool in_the_way = scene == nullptr || sim::hazard_in_the_way(*scene, r.factors);
      (in_the_way ? c.green_not_stoppable : c.green_clear_path).push_back(cell_ref(r));
    }
  }
  return c;
}

}  // namespace

StopBoundaryCheck check_stop_boundary(const std::vector<campaign::CellRecord>& records,
                                      const sim::ActuationConfig& actuation) {
  return stop_boundary_check(records, actuation, nullptr);
}

StopBoundaryCheck check_stop_boundary(const std::vector<campaign::CellRecord>& records, const sim::SceneConfig& scene) {
  return stop_boundary_check(records, scene.actuation, &scene);
}

MonotonicityCheck check_monotonicity(const std::vector<campaign::CellRecord>& records, std::size_t max_examples) {
  MonotonicityCheck out;
  const auto strategies = strategy_names_of(records);
  for (const auto& grid : grid_names(records)) {
    std::vector<const campaign::CellRecord*> cells;
    for (const auto& r : records)
      if (r.grid == grid && r.feasible) cells.push_back(&r);
    count_along(cells, grid, sim::kTtcFactor, "ttc", strategies, max_examples, out);
    count_along(cells, grid, sim::kFrictionFactor, "mu", strategies, max_examples, out);
  }
  return out;
}

const ReferenceCounts* ReferenceCheck::of(std::string_view strategy) const noexcept {
  for (const auto& c : strategies)
    if (c.strategy == strategy) return &c;
  return nullptr;
}

std::vector<sim::StrategyInfo> reference_checked_strategies() {
  std::vector<sim::StrategyInfo> out;
  for (const auto& e : sim::registered_strategies().entries())
    if (!e.info.planner.empty() && !e.info.limits.accept_contact) out.push_back(e.info);
  return out;
}

ReferenceCheck check_against_reference(const std::vector<campaign::CellRecord>& records, const sim::SceneConfig& scene,
                                       std::size_t sample, std::uint64_t seed, int threads) {
  sim::validate(scene);
  ReferenceCheck check;
  check.seed = seed;
  const auto checked = reference_checked_strategies();
  for (const auto& s : checked) check.strategies.push_back({s.name});
  std::vector<const campaign::CellRecord*> candidates;
  for (const auto& r : records)
    if (r.feasible && std::all_of(checked.begin(), checked.end(),
                                  [&](const sim::StrategyInfo& s) { return r.outcome(s.name) != nullptr; }))
      candidates.push_back(&r);
  // A partial Fisher–Yates shuffle with our own generator: std::shuffle's algorithm is not
  // specified, and the sample must be the same on every standard library.
  std::mt19937_64 rng(seed);
  const std::size_t n = std::min(sample, candidates.size());
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t span = candidates.size() - i;
    const std::size_t j = i + static_cast<std::size_t>(rng() % span);
    std::swap(candidates[i], candidates[j]);
  }
  candidates.resize(n);
  check.sampled = n;

  // reference_avoids[i * checked + k]: the reference planner avoids cell i with strategy k's limits.
  std::vector<char> reference_avoids(n * checked.size(), 0);
  const auto model = sim::make_vehicle_model(scene.simulation.vehicle_model, scene.ego);
  const auto run_one = [&](std::size_t i) {
    const campaign::CellRecord& r = *candidates[i];
    const sim::CellInput& input = r.factors;
    sim::validate_cell(scene, input);
    const sim::Scene cell_scene(scene, input);
    for (std::size_t k = 0; k < checked.size(); ++k)
      reference_avoids[i * checked.size() + k] =
          static_cast<char>(sim::plan_reference(cell_scene, *model, checked[k].limits).avoidance.has_value());
  };
  {
    const int workers = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    // An arena of our own, so the thread limit does not leak into the rest of the process.
    tbb::task_arena arena(workers);
    arena.execute([&] { tbb::parallel_for(std::size_t{0}, n, run_one); });
  }
  for (std::size_t i = 0; i < n; ++i) {
    const campaign::CellRecord& r = *candidates[i];
    for (std::size_t k = 0; k < checked.size(); ++k) {
      ReferenceCounts& counts = check.strategies[k];
      const bool reference = reference_avoids[i * checked.size() + k] != 0;
      const bool stored = r.outcome(counts.strategy)->avoided;
      if (reference) ++counts.reference_avoids;
      if (reference && !stored) ++counts.missed;
      if (!reference && stored) ++counts.beyond_reference;
      if (reference != stored) check.disagreements.push_back({cell_ref(r), counts.strategy, reference, stored});
    }
  }
  return check;
}

std::vector<std::string> trace_events(const std::vector<std::string>& trace) {
  std::vector<std::string> events;
  for (std::size_t i = 1; i < trace.size(); i += 2) events.push_back(trace[i]);
  return events;
}

FsmCoverage emrm_fsm_coverage(const std::vector<campaign::CellRecord>& records, const fsm::Generator& g) {
  std::vector<std::vector<std::string>> words;
  for (const auto& r : records) {
    if (!r.feasible) continue;
    for (const auto& o : r.outcomes)
      if (!o.fsm_trace.empty()) words.push_back(trace_events(o.fsm_trace));
  }
  return coverage_of(g, words);
}

FsmCoverage loss_evaluation_fsm_coverage(const std::vector<campaign::CellRecord>& records, const fsm::Generator& g) {
  std::vector<std::vector<std::string>> words;
  for (const auto& r : records) {
    if (!r.feasible) continue;
    for (const auto& o : r.outcomes)
      if (!o.loss_evaluation_trace.empty()) words.push_back(trace_events(o.loss_evaluation_trace));
  }
  return coverage_of(g, words);
}

Diagnostics run_diagnostics(const std::vector<campaign::CellRecord>& records, const sim::SceneConfig& scene,
                            const DiagnosticsOptions& options) {
  Diagnostics d;
  d.factors = sim::scenario_factors(scene);
  d.stop_boundary = check_stop_boundary(records, scene);
  d.monotonicity = check_monotonicity(records);
  d.reference = check_against_reference(records, scene, options.reference_sample, options.seed, options.threads);
  d.emrm_fsm = emrm_fsm_coverage(records, sim::default_emrm_fsm());
  d.loss_evaluation_fsm = loss_evaluation_fsm_coverage(records, sim::default_loss_evaluation_fsm());
  return d;
}

nlohmann::ordered_json to_json(const Diagnostics& d) {
  const auto& sb = d.stop_boundary;
  Json stop{{"definition",
             "feasible cells with v TTC >= v (perception latency + brake dead time + ramp/2) + v^2/(2a) - a ramp^2/24 "
             "(a = mu g or the brake cap) are analytically stoppable"},
            {"latency_s", sb.latency_s},
            {"brake_dead_time_s", sb.actuation.brake_dead_time_s},
            {"brake_ramp_s", sb.actuation.brake_ramp_s},
            {"max_decel_mps2", sb.actuation.max_decel_mps2},
            {"feasible", sb.feasible},
            {"stoppable", sb.stoppable},
            {"stoppable_red_count", sb.stoppable_red.size()},
            {"ok", sb.stoppable_red.empty()},
            {"stoppable_red", cells_json(sb.stoppable_red, d.factors)},
            {"stoppable_not_green_count", sb.stoppable_not_green.size()},
            {"stoppable_not_green", cells_json(sb.stoppable_not_green, d.factors)},
            {"green_not_stoppable_count", sb.green_not_stoppable.size()},
            {"green_not_stoppable", cells_json(sb.green_not_stoppable, d.factors)},
            {"green_clear_path_count", sb.green_clear_path.size()},
            {"green_clear_path", cells_json(sb.green_clear_path, d.factors)}};
  if (!sb.applies) {  // a family without the boundary (a key of its own: the T-junction's file stays as it was)
    stop["applies"] = false;
    stop["definition"] = "the scene's family has no analytic stop boundary (its hazard does not stand v TTC ahead)";
  }
  Json counts = Json::array();
  for (const auto& c : d.monotonicity.counts)
    counts.push_back({{"grid", c.grid},
                      {"strategy", c.strategy},
                      {"factor", c.factor},
                      {"pairs", c.pairs},
                      {"reversals", c.reversals}});
  Json examples = Json::array();
  for (const auto& e : d.monotonicity.examples)
    examples.push_back({{"grid", e.grid},
                        {"strategy", e.strategy},
                        {"factor", e.factor},
                        {"avoided_at", cell_json(e.lower, d.factors)},
                        {"not_avoided_at", cell_json(e.higher, d.factors)}});
  Json mono{{"definition", "a strategy avoided at a lower TTC (mu) but not at the next higher, other factors equal"},
            {"total_reversals", d.monotonicity.total_reversals},
            {"counts", counts},
            {"examples", examples}};
  const auto& rc = d.reference;
  Json disagreements = Json::array();
  for (const auto& x : rc.disagreements)
    disagreements.push_back({{"cell", cell_json(x.cell, d.factors)},
                             {"strategy", x.strategy},
                             {"reference_avoids", x.reference_avoids},
                             {"stored_avoided", x.stored_avoided}});
  Json reference{{"definition",
                  "sim::plan_reference with each checked strategy's control limits on a seeded sample of "
                  "feasible cells, against the stored outcomes of the strategies that search for an avoidance "
                  "of their own (docs/results.md)"},
                 {"sampled", rc.sampled},
                 {"seed", rc.seed}};
  for (const auto& c : rc.strategies)
    reference[c.strategy] = {{"reference_avoids", c.reference_avoids},
                             {"rrt_missed", c.missed},
                             {"rrt_beyond_reference", c.beyond_reference}};
  reference["disagreements"] = disagreements;
  return {{"stop_boundary", stop},
          {"monotonicity", mono},
          {"rrt_vs_reference", reference},
          {"fsm_coverage",
           {{"emrm_fsm", coverage_json(d.emrm_fsm)}, {"loss_evaluation_fsm", coverage_json(d.loss_evaluation_fsm)}}}};
}

std::string summary(const Diagnostics& d) {
  const auto& sb = d.stop_boundary;
  const auto& rc = d.reference;
  std::vector<std::string> missed;
  for (const auto& c : rc.strategies) missed.push_back(fmt::format("{} {}", c.missed, c.strategy));
  const std::string stop =
      !sb.applies
          ? std::string("no analytic stop boundary in this scene's family")
          : fmt::format("{} analytically stoppable cells classified R{}; {} G cells below the stop boundary{}",
                        sb.stoppable_red.size(), sb.stoppable_red.empty() ? "" : " (WARNING: see diagnostics.json)",
                        sb.green_not_stoppable.size(),
                        sb.green_clear_path.empty()
                            ? std::string()
                            : fmt::format(" with the hazard in the car's path ({} more where it leaves the path clear)",
                                          sb.green_clear_path.size()));
  return fmt::format(
      "{}; {} monotonicity reversals; reference planner on {} cells: RRT missed {}; FSM transition coverage {}/{} "
      "(EMRM), {}/{} (loss evaluation)",
      stop, d.monotonicity.total_reversals, rc.sampled,
      missed.empty() ? std::string("nothing (no strategy checked)") : core::join(missed, ", "),
      d.emrm_fsm.coverage.covered, d.emrm_fsm.coverage.counts.size(), d.loss_evaluation_fsm.coverage.covered,
      d.loss_evaluation_fsm.coverage.counts.size());
}

bool contradicts_physics(const Diagnostics& d) noexcept {
  return !d.stop_boundary.stoppable_red.empty() || !d.stop_boundary.green_not_stoppable.empty();
}

std::vector<std::filesystem::path> write_diagnostics(const std::filesystem::path& dir, const Diagnostics& d) {
  // Every file rendered before the first is written, then all together: a failing Graphviz leaves
  // no diagnostics.json without its diagrams.
  std::vector<core::FileContent> files{{ResultsDir(dir).diagnostics_json(), to_json(d).dump(2) + "\n"}};
  const bool svg = fsm::dot_available();
  for (const auto& [stem, c] :
       {std::pair{"emrm_fsm", &d.emrm_fsm}, std::pair{"loss_evaluation_fsm", &d.loss_evaluation_fsm}}) {
    if (c->generator == nullptr) continue;
    fsm::DotOptions options;
    options.transition_counts = c->coverage.counts;
    const std::string dot = fsm::to_dot(*c->generator, options);
    const auto base = ResultsDir(dir).fsm_dir() / stem;
    files.push_back({base.string() + ".dot", dot});
    if (svg) files.push_back({base.string() + ".svg", fsm::render_svg(dot)});
  }
  core::write_files(files);
  std::vector<std::filesystem::path> written;
  for (const auto& f : files) written.push_back(f.path);
  return written;
}

DiagnosticsSummary read_diagnostics_summary(const std::filesystem::path& path) {
  const core::YamlNode root = core::load_json_file(path);  // JSON is YAML: errors at line:column
  const auto count = [](const core::YamlNode& object, std::string_view key) {
    std::size_t value = 0;
    core::YamlCodec<std::size_t>::read(object.at(key), value);
    return value;
  };
  DiagnosticsSummary s;
  const auto stop = root.at("stop_boundary");
  if (const auto applies = stop.find("applies")) core::YamlCodec<bool>::read(*applies, s.stop_boundary);
  s.feasible = count(stop, "feasible");
  s.stoppable = count(stop, "stoppable");
  s.stoppable_red = count(stop, "stoppable_red_count");
  s.green_not_stoppable = count(stop, "green_not_stoppable_count");
  const auto mono = root.at("monotonicity");
  s.total_reversals = count(mono, "total_reversals");
  for (const auto& c : mono.at("counts").elements())
    s.reversal_counts.push_back({c.at("grid").as_string(), c.at("strategy").as_string(), c.at("factor").as_string(),
                                 count(c, "pairs"), count(c, "reversals")});
  const auto reference = root.at("rrt_vs_reference");
  s.sampled = count(reference, "sampled");
  core::YamlCodec<std::uint64_t>::read(reference.at("seed"), s.seed);
  for (const auto& [key, value] : reference.entries())  // a member per checked strategy, besides the fixed ones
    if (value.is_map())
      s.reference.push_back({key.as_string(), count(value, "reference_avoids"), count(value, "rrt_missed"),
                             count(value, "rrt_beyond_reference")});
  for (const auto& [key, value] : root.at("fsm_coverage").entries())
    s.fsm_coverage.push_back({key.as_string(), count(value, "covered"), count(value, "total"), count(value, "traces")});
  return s;
}

}  // namespace emrm::results
