// EMRM as a controller (docs/simulate.md, "emrm"): it decides from its own predictions, never from
// the cell's simulated outcomes; it picks the stop without searching where braking is predicted to
// avoid; the oracle (best_strategy, the best outcome in hindsight) is never worse than it; and its
// outcome does not depend on the campaign's seed.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "emrm/sim/json.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/strategy.hpp"
#include "outcomes.hpp"

namespace emrm::sim {
namespace emrm_controller_test {

using test::outcome;

// Everything of an outcome that the controller decides and does.
void expect_same_decision(const StrategyOutcome& a, const StrategyOutcome& b, const std::string& where) {
  EXPECT_EQ(a.chosen_strategy, b.chosen_strategy) << where;
  EXPECT_EQ(a.loss_evaluation_trace, b.loss_evaluation_trace) << where;
  EXPECT_EQ(a.avoided, b.avoided) << where;
  EXPECT_EQ(a.impact.loss_level, b.impact.loss_level) << where;
  EXPECT_EQ(a.impact.delta_v_mps, b.impact.delta_v_mps) << where;
  EXPECT_EQ(to_json(a.maneuver).dump(), to_json(b.maneuver).dump()) << where;
  EXPECT_EQ(a.planner.nodes, b.planner.nodes) << where;
}

// The controller run by hand on a cell, with `earlier` as the outcomes it is handed.
StrategyOutcome run_controller(const SceneConfig& config, const CellInput& cell,
                               const std::map<std::string, StrategyOutcome>& earlier) {
  const Scene scene(config, cell);
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  const RolloutResult no_action = no_action_rollout(scene, *model);
  const bool at_risk = no_action.termination == Termination::kContact;
  const ImpactAssessment unmitigated = at_risk ? no_action.impact : ImpactAssessment{};
  const StrategyTable table = registered_strategies();
  const RegisteredStrategy* emrm = table.find("emrm");
  const StrategyContext context{scene,
                                *model,
                                table,
                                12345,
                                false,
                                unmitigated,
                                no_action,
                                at_risk,
                                earlier,
                                default_emrm_fsm(),
                                default_loss_evaluation_fsm(),
                                false};
  return emrm->strategy->run(emrm->info, context);
}

const std::vector<CellInput> kSample{
    {40.0, 1.5, 1.0, 3.0, 10.0}, {60.0, 0.8, 1.0, 3.0, 10.0}, {50.0, 0.6, 1.0, 3.0, 10.0}, {66.0, 0.55, 1.0, 3.0, 10.0},
    {72.0, 0.3, 1.0, 3.0, 10.0}, {45.0, 0.7, 0.5, 3.0, 10.0}, {55.0, 0.9, 0.2, 3.0, 10.0}};

TEST(EmrmController, NeverReadsTheCellsSimulatedOutcomes) {
  const SceneConfig config;
  for (const CellInput& cell : kSample) {
    const CellResult all = simulate_cell(config, cell, {});
    if (!all.feasible) continue;
    const std::string where = fmt::format("{} km/h, TTC {} s, mu {}", cell[0], cell[1], cell[2]);
    const StrategyOutcome& simulated = outcome(all, "emrm");
    // Handed no outcome at all, or outcomes that lie (every strategy avoids), it decides the same.
    expect_same_decision(run_controller(config, cell, {}), simulated, where + " (no outcomes)");
    std::map<std::string, StrategyOutcome> lies;
    for (const auto& name : strategy_names()) {
      lies[name].strategy = name;
      lies[name].avoided = true;
    }
    expect_same_decision(run_controller(config, cell, lies), simulated, where + " (false outcomes)");
    // Asked for alone, it is what it is among all the others.
    CellOptions alone;
    alone.strategies = {"emrm"};
    expect_same_decision(outcome(simulate_cell(config, cell, alone), "emrm"), simulated, where + " (alone)");
  }
}

TEST(EmrmController, PicksTheStopWithoutSearchingWhereBrakingIsPredictedToAvoid) {
  const CellResult r = simulate_cell(SceneConfig{}, {40.0, 1.5, 1.0, 3.0, 10.0}, {});
  ASSERT_TRUE(outcome(r, "emergency_stop").avoided);
  const StrategyOutcome& emrm = outcome(r, "emrm");
  EXPECT_EQ(emrm.chosen_strategy, "emergency_stop");
  EXPECT_TRUE(emrm.avoided);
  EXPECT_EQ(emrm.planner.nodes, 0);     // no evasive search
  EXPECT_EQ(emrm.planner.rollouts, 1);  // the stop's own rollout
  EXPECT_EQ(emrm.loss_evaluation_trace.at(5), "C0");
  EXPECT_TRUE(emrm.adopted_from.empty());  // its own maneuver, not another strategy's outcome
}

TEST(EmrmController, TheOracleIsNeverWorseAndAvoidsWhereTheOnBoardBudgetFindsNothing) {
  // An on-board budget of one extension attempt: where the full search finds an avoidance the
  // controller's own search may not, and then it does not avoid while the oracle does.
  SceneConfig config;
  config.controller.max_nodes = 1;
  int only_oracle_avoids = 0;
  for (const double speed : {45.0, 55.0, 65.0})
    for (const double ttc : {0.45, 0.55, 0.65, 0.75}) {
      const CellResult r = simulate_cell(config, {speed, ttc, 1.0, 3.0, 10.0}, {});
      if (!r.feasible) continue;
      const std::string where = fmt::format("{} km/h, TTC {} s", speed, ttc);
      const StrategyOutcome& emrm = outcome(r, "emrm");
      const StrategyOutcome& oracle = outcome(r, "best_strategy");
      EXPECT_FALSE(better_outcome(emrm, oracle)) << where;
      if (!oracle.avoided || emrm.avoided) continue;
      ++only_oracle_avoids;
      // It saw no avoidance in its own predictions: controllability C3.
      EXPECT_EQ(emrm.loss_evaluation_trace.at(5), "C3") << where;
    }
  EXPECT_GT(only_oracle_avoids, 0);
  RecordProperty("only_oracle_avoids", only_oracle_avoids);
}

TEST(EmrmController, TheOracleIsNeverWorseOnTheDefaultBudget) {
  const SceneConfig config;
  const StrategyTable table = registered_strategies();
  for (const CellInput& cell : kSample) {
    const CellResult r = simulate_cell(config, cell, {});
    if (!r.feasible) continue;
    const std::string where = fmt::format("{} km/h, TTC {} s, mu {}", cell[0], cell[1], cell[2]);
    const StrategyOutcome& oracle = outcome(r, "best_strategy");
    EXPECT_FALSE(better_outcome(outcome(r, "emrm"), oracle)) << where;
    for (const auto& o : r.strategies) {
      const StrategyInfo* info = table.info(o.strategy);
      if (info == nullptr || !info->emrm_may_choose) continue;
      EXPECT_FALSE(better_outcome(o, oracle)) << o.strategy << " beats the oracle at " << where;
    }
  }
}

TEST(EmrmController, DoesNotDependOnTheCampaignSeed) {
  const SceneConfig config;
  for (const CellInput& cell : {CellInput{60.0, 0.8, 1.0, 3.0, 10.0}, CellInput{66.0, 0.55, 1.0, 3.0, 10.0}}) {
    CellOptions one, other;
    one.seed = 1;
    other.seed = 987654321;
    const std::string where = fmt::format("{} km/h, TTC {} s", cell[0], cell[1]);
    expect_same_decision(outcome(simulate_cell(config, cell, one), "emrm"),
                         outcome(simulate_cell(config, cell, other), "emrm"), where);
  }
}

}  // namespace emrm_controller_test
}  // namespace emrm::sim
