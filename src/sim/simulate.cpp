#include "emrm/sim/simulate.hpp"

#include <fmt/format.h>

#include <map>

#include "emrm/core/text.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::sim {

namespace detail {
extern const char* const kShippedEmrmFsmYaml;
extern const char* const kShippedLossEvaluationFsmYaml;
}  // namespace detail

std::string_view region_name(Region r) noexcept {
  switch (r) {
    case Region::kG: return "G";
    case Region::kY: return "Y";
    case Region::kO: return "O";
    case Region::kR: return "R";
    case Region::kInfeasible: return "infeasible";
  }
  return "?";
}

const fsm::Generator& default_emrm_fsm() {
  static const fsm::Generator g = fsm::parse_generator(detail::kShippedEmrmFsmYaml, "emrm_fsm.yaml (built in)");
  return g;
}

const fsm::Generator& default_loss_evaluation_fsm() {
  static const fsm::Generator g =
      fsm::parse_generator(detail::kShippedLossEvaluationFsmYaml, "loss_evaluation_fsm.yaml (built in)");
  return g;
}

const std::vector<std::string>& strategy_names() {
  static const std::vector<std::string> names{"emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident",
                                              "emrm"};
  return names;
}

void validate_strategy(std::string_view name) {
  for (const auto& n : strategy_names())
    if (n == name) return;
  throw UsageError(fmt::format("unknown strategy '{}'; expected one of: {}, or all", name,
                               core::join(strategy_names(), ", ")));
}

namespace {

// Reads `events` from s0 and records s0 e1 s1 e2 s2 …; stops where δ is undefined.
std::vector<std::string> trace_through(const fsm::Generator& g, const std::vector<std::string>& events) {
  std::vector<std::string> trace;
  auto state = g.initial();
  if (!state) return trace;
  trace.push_back(*state);
  for (const auto& e : events) {
    auto next = g.step(*state, e);
    if (!next) break;
    trace.push_back(e);
    trace.push_back(*next);
    state = next;
  }
  return trace;
}

std::vector<std::string> emrm_events(bool at_risk, bool avoided) {
  if (!at_risk) return {"hazard_detected", "no_risk"};
  if (avoided) return {"hazard_detected", "high_risk", "execute_maneuver", "emrm_done"};
  return {"hazard_detected", "high_risk", "execute_maneuver", "timeout_error", "post_incident_response", "safe"};
}

std::string severity_event(int unmitigated_level) {
  if (unmitigated_level >= 7) return "Se3";
  if (unmitigated_level >= 6) return "Se2";
  return "Se1";
}

std::string maneuverability_event(double mu) {
  if (mu >= 0.7) return "Mi3";
  if (mu >= 0.35) return "Mi2";
  return "Mi1";
}

std::string controllability_event(const std::map<std::string, StrategyOutcome>& outcomes) {
  if (outcomes.at("emergency_stop").avoided) return "C0";
  if (outcomes.at("dodge").avoided) return "C1";
  if (outcomes.at("drift_to_avoid").avoided || outcomes.at("drift_to_accident").avoided) return "C2";
  return "C3";
}

Region region_of(const std::map<std::string, StrategyOutcome>& outcomes, const ImpactAssessment& unmitigated) {
  if (outcomes.at("emergency_stop").avoided) return Region::kG;
  int best_level = unmitigated.loss_level;
  for (const auto& [name, o] : outcomes) {
    if (name == "emrm") continue;
    if (o.avoided) return Region::kY;
    best_level = std::min(best_level, o.impact.loss_level);
  }
  return best_level < unmitigated.loss_level ? Region::kO : Region::kR;
}

}  // namespace

CellResult simulate_cell(const SceneConfig& config, const CellInput& cell, const CellOptions& options) {
  validate_cell(config, cell);
  for (const auto& s : options.strategies) validate_strategy(s);
  const fsm::Generator& emrm_fsm = options.emrm_fsm ? *options.emrm_fsm : default_emrm_fsm();
  const fsm::Generator& loss_fsm =
      options.loss_evaluation_fsm ? *options.loss_evaluation_fsm : default_loss_evaluation_fsm();

  CellResult result;
  result.input = cell;
  const Scene scene(config, cell);
  result.feasible = scene.feasible();
  if (!result.feasible) return result;
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);

  // Risk evaluation: does doing nothing hit the truck? The unmitigated reference is then the
  // head-on contact at the initial speed (DESIGN.md §8).
  const Roller coast(scene, *model, ControlLimits{});
  const RolloutResult no_action = coast.roll(scene.ego_initial(), 0.0, {}, Tail{}, 10);
  const bool at_risk = no_action.termination == Termination::kContact;
  result.unmitigated = at_risk ? unmitigated_impact(scene) : ImpactAssessment{};

  std::map<std::string, StrategyOutcome> outcomes;
  for (const auto& name : strategy_names()) {
    if (name == "emrm") continue;
    const StrategyContext context{scene,          *model, derive_seed(options.seed, name), options.keep_trees,
                                  result.unmitigated, outcomes};
    StrategyOutcome o = find_strategy(name)->run(context);
    o.fsm_trace = trace_through(emrm_fsm, emrm_events(at_risk, o.avoided));
    outcomes.emplace(name, std::move(o));
  }

  // emrm: the loss-evaluation FSM chooses among the strategies from what physics says of the cell.
  const std::vector<std::string> word{severity_event(result.unmitigated.loss_level), "E0",
                                      controllability_event(outcomes), maneuverability_event(cell.mu)};
  const auto loss_trace = trace_through(loss_fsm, word);
  const std::string chosen = loss_trace.size() == 2 * word.size() + 1 ? loss_trace.back() : "emergency_stop";
  StrategyOutcome emrm = outcomes.count(chosen) ? outcomes.at(chosen) : outcomes.at("emergency_stop");
  emrm.strategy = "emrm";
  emrm.chosen_strategy = chosen;
  emrm.adopted_from = chosen;
  emrm.loss_evaluation_trace = loss_trace;
  if (!at_risk) {
    // Nothing to evade: the EMRM FSM returns to normal driving and the car carries on.
    emrm = outcome_of("emrm", no_action, result.unmitigated, scene);
    emrm.chosen_strategy = "none";
    emrm.fsm_trace = trace_through(emrm_fsm, emrm_events(false, true));
  }
  outcomes.emplace("emrm", std::move(emrm));

  result.region = region_of(outcomes, result.unmitigated);
  for (const auto& name : options.strategies) result.strategies.push_back(outcomes.at(name));
  return result;
}

}  // namespace emrm::sim
