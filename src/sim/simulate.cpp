#include "emrm/sim/simulate.hpp"

#include <fmt/format.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/fsm/operations.hpp"
#include "emrm/sim/falsifier.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::sim {

namespace detail {
extern const char* const kShippedEmrmFsmYaml;
extern const char* const kShippedLossEvaluationFsmYaml;
}  // namespace detail

const fsm::Generator& default_emrm_fsm() {
  static const fsm::Generator g = fsm::parse_generator(detail::kShippedEmrmFsmYaml, "emrm_fsm.yaml (built in)");
  return g;
}

const fsm::Generator& default_loss_evaluation_fsm() {
  static const fsm::Generator g =
      fsm::parse_generator(detail::kShippedLossEvaluationFsmYaml, "loss_evaluation_fsm.yaml (built in)");
  return g;
}

std::vector<std::string> strategy_names() { return registered_strategies().names(); }

bool known_strategy(std::string_view name) { return registered_strategies().find(name) != nullptr; }

std::string unknown_strategy_message(std::string_view name) {
  const std::vector<std::string> names = registered_strategies().names();
  return fmt::format("unknown strategy '{}'{}; expected one of: {}", name, core::did_you_mean(name, names),
                     core::join(names, ", "));
}

void validate_strategy(std::string_view name) {
  if (!known_strategy(name)) throw UsageError(unknown_strategy_message(name) + ", or all");
}

namespace {

std::vector<std::string> emrm_events(bool at_risk, bool avoided) {
  if (!at_risk) return {"hazard_detected", "no_risk"};
  if (avoided) return {"hazard_detected", "high_risk", "execute_maneuver", "emrm_done"};
  return {"hazard_detected", "high_risk", "execute_maneuver", "timeout_error", "post_incident_response", "safe"};
}

// G when the baseline avoids; Y when another strategy does; O when the best of them lowers the
// loss level below the unmitigated one; R otherwise. A chooser (EMRM, the oracle) does not count.
Region region_of(const StrategyTable& strategies, const std::map<std::string, StrategyOutcome>& outcomes,
                 const ImpactAssessment& unmitigated) {
  const StrategyInfo* baseline = strategies.first_of(StrategyRole::kBaseline);
  if (baseline != nullptr && outcomes.at(baseline->name).avoided) return Region::kG;
  int best_level = unmitigated.loss_level;
  for (const auto& entry : strategies.entries()) {
    if (entry.info.role == StrategyRole::kChooser) continue;
    const StrategyOutcome& o = outcomes.at(entry.info.name);
    if (o.avoided) return Region::kY;
    best_level = std::min(best_level, o.impact.loss_level);
  }
  return best_level < unmitigated.loss_level ? Region::kO : Region::kR;
}

// An avoidance found by a later strategy is just as good for an earlier searching one that failed,
// when it obeys that one's limits (a drift to accident that avoided is a legal drift to avoid):
// adopting it makes the outcomes independent of which search happened to find the way first.
// Fixed maneuvers (no planner, like the emergency stop) adopt nothing.
void share_avoidance(const StrategyTable& strategies, const StrategyInfo& finder, const StrategyOutcome& found,
                     std::map<std::string, StrategyOutcome>& outcomes, const std::vector<std::string>& avoided_trace) {
  for (auto& [name, earlier] : outcomes) {
    const StrategyInfo* info = strategies.info(name);
    if (earlier.avoided || info == nullptr || info->role == StrategyRole::kChooser || info->planner.empty() ||
        !avoidance_admissible(finder.limits, info->limits))
      continue;
    const PlannerStats searched = earlier.planner;
    std::vector<TreeEdge> tree = std::move(earlier.tree);
    earlier = adopted(name, finder.name, found);
    earlier.planner = searched;
    earlier.tree = std::move(tree);
    earlier.fsm_trace = avoided_trace;
  }
}

// The searching strategy whose limits admit every other searching strategy's avoidance (the
// shipped drift to avoid): an avoidance it finds is the region's answer, so the strengthened search
// runs on its behalf. Nullptr when no strategy is that permissive.
const StrategyInfo* most_permissive_search(const StrategyTable& strategies) {
  for (const auto& candidate : strategies.entries()) {
    const StrategyInfo& c = candidate.info;
    if (c.role != StrategyRole::kEvasive || c.planner.empty() || c.limits.accept_contact) continue;
    bool admits_all = true;
    for (const auto& other : strategies.entries())
      if (other.info.role == StrategyRole::kEvasive && !other.info.planner.empty())
        admits_all = admits_all && avoidance_admissible(other.info.limits, c.limits);
    if (admits_all) return &c;
  }
  return nullptr;
}

// More search where the first found no avoidance and nothing proves that none exists: the
// falsifier (deterministic: its grid, then trajectory optimisation from the searches' own least-loss
// failures, `hints`, and from its grid's nearest misses), then, where it came within
// planner.plausible_miss_m of an avoidance (across the hazard's edge, or short of stopping),
// restarts of the strategy's planner with seeds that depend on the cell alone (not on the campaign's
// seed). An avoidance any of them finds is replayed into the strategy's outcome.
std::optional<StrategyOutcome> strengthened_search(const Scene& scene, const VehicleModel& model,
                                                   const StrategyInfo& info, const ImpactAssessment& unmitigated,
                                                   const std::vector<Maneuver>& hints, PlannerStats& stats) {
  const PlannerConfig& budget = scene.config().planner;
  const auto found = [&](const PlanResult& plan) -> std::optional<StrategyOutcome> {
    stats.add(plan.stats);
    if (!plan.avoidance) return std::nullopt;
    return outcome_of(info.name, replay(scene, model, info.limits, plan.avoidance->maneuver), unmitigated, scene);
  };
  const PlanResult falsified = falsify(scene, model, info.limits, hints);
  if (auto outcome = found(falsified)) return outcome;
  if (!(falsified.closest_miss_m <= budget.plausible_miss_m)) return std::nullopt;
  const Planner* own = find_planner(info.planner);
  if (own == nullptr) return std::nullopt;
  const CellInput& c = scene.cell();
  const std::uint64_t key = cell_key(c, 0x5eed5eed5eed5eedULL);
  // The restarts are independent: they run side by side where a worker is free (a sweep's other
  // cells keep the workers busy, a lone cell or the tail of a sweep does not), and the outcome is
  // the first in order that avoids, counted as if they had run one after another: a restart after
  // an avoiding one is skipped, or, if it ran, neither used nor counted.
  //
  // Their context is isolated: when the caller's parallel work is cancelled (an exception in a
  // neighbouring task, as an adaptive search stopping at an interrupt throws), restarts that had
  // not started would otherwise be skipped and this cell's result would rest on part of them.
  const int restarts = std::max(0, budget.restarts);
  std::vector<std::optional<PlanResult>> plans(static_cast<std::size_t>(restarts));
  std::atomic<int> first_avoiding{restarts};
  tbb::task_group_context isolated(tbb::task_group_context::isolated);
  tbb::parallel_for(
      0, restarts,
      [&](int k) {
        if (k > first_avoiding.load()) return;
        auto& plan = plans[static_cast<std::size_t>(k)];
        plan = own->plan({scene, model, info.limits, derive_seed(key, fmt::format("restart-{}", k)), false});
        if (!plan->avoidance) return;
        int current = first_avoiding.load();
        while (k < current && !first_avoiding.compare_exchange_weak(current, k)) {
        }
      },
      isolated);
  for (auto& plan : plans) {  // every restart up to the first avoiding one has run
    if (!plan) throw std::logic_error("strengthened search: a restart before the first avoiding one did not run");
    if (auto outcome = found(*plan)) return outcome;
  }
  return std::nullopt;
}

}  // namespace

CellResult simulate_cell(const SceneConfig& config, const CellInput& cell, const CellOptions& options) {
  validate(config);
  validate_cell(config, cell);
  const StrategyTable strategies = registered_strategies();
  for (const auto& s : options.strategies)
    if (strategies.find(s) == nullptr) validate_strategy(s);
  const fsm::Generator& emrm_fsm = options.emrm_fsm ? *options.emrm_fsm : default_emrm_fsm();
  const fsm::Generator& loss_fsm =
      options.loss_evaluation_fsm ? *options.loss_evaluation_fsm : default_loss_evaluation_fsm();

  CellResult result;
  result.input = cell;
  const Scene scene(config, cell);
  result.feasible = scene.feasible();
  if (!result.feasible) return result;
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);

  // Risk evaluation: does doing nothing hit the truck? The unmitigated reference is then that
  // contact, assessed by the same impact model as every strategy's (docs/physics.md).
  const RolloutResult no_action = no_action_rollout(scene, *model);
  const bool at_risk = no_action.termination == Termination::kContact;
  result.unmitigated = at_risk ? no_action.impact : ImpactAssessment{};

  // The EMRM FSM's trace depends only on (at risk, avoided): traced once per cell for each.
  std::optional<std::vector<std::string>> traces[2];
  const auto trace_for = [&](bool avoided) -> const std::vector<std::string>& {
    auto& trace = traces[avoided ? 1 : 0];
    if (!trace) trace = fsm::trace_word(emrm_fsm, emrm_events(at_risk, avoided));
    return *trace;
  };

  // A proof first: in a cell that nothing can avoid, no search for an avoidance is needed.
  if (options.certify && at_risk) result.certificate = certify_unavoidable(scene);
  const bool certified = result.certificate.has_value();
  std::map<std::string, StrategyOutcome> outcomes;
  const auto any_avoided = [&] {
    for (const auto& [name, o] : outcomes)
      if (o.avoided) return true;
    return false;
  };
  const auto run = [&](const RegisteredStrategy& entry) {
    const std::string& name = entry.info.name;
    const StrategyContext context{scene,
                                  *model,
                                  strategies,
                                  derive_seed(options.seed, name),
                                  options.keep_trees,
                                  result.unmitigated,
                                  no_action,
                                  at_risk,
                                  outcomes,
                                  emrm_fsm,
                                  loss_fsm,
                                  certified};
    StrategyOutcome o = entry.strategy->run(entry.info, context);
    o.fsm_trace = trace_for(o.avoided);
    if (o.avoided && o.adopted_from.empty() && entry.info.role != StrategyRole::kChooser)
      share_avoidance(strategies, entry.info, o, outcomes, trace_for(true));
    outcomes.insert_or_assign(name, std::move(o));
  };
  for (const auto& entry : strategies.entries())
    if (entry.info.role != StrategyRole::kChooser) run(entry);

  // A failed search is not a proof: strengthen it before the region rests on it.
  if (options.strengthen && at_risk && !certified && !any_avoided()) {
    if (const StrategyInfo* permissive = most_permissive_search(strategies)) {
      result.strengthened = true;
      std::vector<Maneuver> hints;  // the searches' least-loss failures
      for (const auto& entry : strategies.entries())
        if (const auto it = outcomes.find(entry.info.name);
            it != outcomes.end() && !entry.info.planner.empty() && !it->second.maneuver.plan.empty())
          hints.push_back(it->second.maneuver);
      StrategyOutcome& current = outcomes.at(permissive->name);
      if (auto found = strengthened_search(scene, *model, *permissive, result.unmitigated, hints, current.planner)) {
        found->planner = current.planner;
        found->fsm_trace = trace_for(true);
        share_avoidance(strategies, *permissive, *found, outcomes, trace_for(true));
        current = std::move(*found);
      }
    }
  }
  for (auto& [name, o] : outcomes) {
    const StrategyInfo* info = strategies.info(name);
    o.evidence = o.avoided || info == nullptr || info->planner.empty()
                     ? Evidence::kWitness
                     : (certified ? Evidence::kCertificate : Evidence::kUndecided);
  }
  // The choosers decide nothing the other strategies or the region depend on: they run only when
  // one of them is asked for (the controller's on-board searches are a quarter of a sweep's
  // rollouts), all of them then, since the oracle weighs the controller's outcome.
  const auto asked = [&](const RegisteredStrategy& entry) {
    return std::find(options.strategies.begin(), options.strategies.end(), entry.info.name) != options.strategies.end();
  };
  const auto& entries = strategies.entries();
  const bool choosers_asked = std::any_of(entries.begin(), entries.end(), [&](const RegisteredStrategy& e) {
    return e.info.role == StrategyRole::kChooser && asked(e);
  });
  for (const auto& entry : entries)
    if (entry.info.role == StrategyRole::kChooser && choosers_asked) run(entry);

  result.region = region_of(strategies, outcomes, result.unmitigated);
  double best_p_mais3 = result.unmitigated.p_mais3;
  double best_p_fatal = result.unmitigated.p_fatal;
  for (const auto& [name, o] : outcomes) {
    best_p_mais3 = std::min(best_p_mais3, o.impact.p_mais3);
    best_p_fatal = std::min(best_p_fatal, o.impact.p_fatal);
  }
  result.p_mais3_reduction = result.unmitigated.p_mais3 - best_p_mais3;
  result.p_fatal_reduction = result.unmitigated.p_fatal - best_p_fatal;
  if (result.region == Region::kO || result.region == Region::kR) {
    result.evidence = certified ? Evidence::kCertificate : Evidence::kUndecided;
    if (!certified && options.certify) result.no_certificate = no_certificate_bound(config).value_or("");
    // "Nothing scores below the reference" is a proof at L4 only when no avoidance (L0) exists
    // either, which needs the certificate; without one it rests on the search.
    result.mitigation_evidence = result.region == Region::kO                       ? MitigationEvidence::kWitness
                                 : certified && result.unmitigated.loss_level <= 4 ? MitigationEvidence::kProof
                                                                                   : MitigationEvidence::kSearch;
  }
  result.strategies.reserve(options.strategies.size());
  for (const auto& name : options.strategies) result.strategies.push_back(outcomes.at(name));
  return result;
}

}  // namespace emrm::sim
