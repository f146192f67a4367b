// Strategies are an extension point: a strategy registered from outside the library (here a toy
// one, straight braking at half the ABS level) appears in the simulator, the region rule, the
// tables and the figures without any edit to them, and disappears when its registration ends.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/results/paper_reference.hpp"
#include "emrm/results/tables.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm {
namespace toy_strategy_test {

// Brakes straight at half the friction limit after the latency; never steers.
class HalfBrake final : public sim::Strategy {
 public:
  sim::StrategyOutcome run(const sim::StrategyInfo& self, const sim::StrategyContext& c) const override {
    const sim::Roller roller(c.scene, c.model, self.limits);
    const double latency = c.scene.config().actuation.perception_latency_s;
    std::vector<sim::ControlSegment> plan;
    if (latency > 0.0) plan.push_back(sim::hold(sim::Control{}, latency));
    const sim::Tail tail{sim::Control{0.0, 0.5, false}, true, false, std::nullopt};
    return sim::outcome_of(self.name, roller.roll(c.scene.ego_initial(), 0.0, plan, tail, 1), c.unmitigated, c.scene);
  }
};

sim::StrategyInfo half_brake_info() {
  return {.name = "half_brake",
          .label = "half brake",
          .title = "Half Brake",
          .colour = "#17becf",
          .order = 45,  // after the shipped evasive strategies, before EMRM
          .role = sim::StrategyRole::kEvasive,
          .limits = {},
          .planner = {},
          .may_adopt = {},
          .emrm_may_choose = false,
          .controllability = {}};
}

const sim::StrategyOutcome* outcome(const sim::CellResult& r, const std::string& name) {
  for (const auto& o : r.strategies)
    if (o.strategy == name) return &o;
  return nullptr;
}

TEST(ToyStrategy, IsListedInEvaluationOrderWhileRegistered) {
  const auto before = sim::strategy_names();
  {
    const sim::StrategyRegistration toy(half_brake_info(), std::make_shared<HalfBrake>());
    const auto names = sim::strategy_names();
    ASSERT_EQ(names.size(), before.size() + 1);
    const auto at = std::find(names.begin(), names.end(), "half_brake");
    ASSERT_NE(at, names.end());
    EXPECT_EQ(*(at + 1), "emrm");  // order 45 sorts it just before the chooser
    EXPECT_NO_THROW(sim::validate_strategy("half_brake"));
  }
  EXPECT_EQ(sim::strategy_names(), before);
  EXPECT_THROW(sim::validate_strategy("half_brake"), UsageError);
}

TEST(ToyStrategy, IsSimulatedWithEveryCell) {
  const sim::StrategyRegistration toy(half_brake_info(), std::make_shared<HalfBrake>());
  sim::SceneConfig config;
  config.planner.max_nodes = 1;  // the toy needs no search; keep the RRT strategies cheap
  // 50 km/h with 1.7 s (23.6 m) to go: half the friction limit stops in 19.7 m.
  const sim::CellResult easy = sim::simulate_cell(config, {50.0, 1.7, 1.0, 3.0, 10.0}, {});
  const auto* toy_easy = outcome(easy, "half_brake");
  ASSERT_NE(toy_easy, nullptr);
  EXPECT_TRUE(toy_easy->avoided);
  EXPECT_EQ(toy_easy->fsm_trace.back(), "S1");  // the EMRM FSM's trace is filled for it too
  // 60 km/h with 1.2 s (20 m) to go: full braking stops in 14.2 m, half braking needs 28 m.
  const sim::CellResult hard = sim::simulate_cell(config, {60.0, 1.2, 1.0, 3.0, 10.0}, {});
  const auto* toy_hard = outcome(hard, "half_brake");
  ASSERT_NE(toy_hard, nullptr);
  EXPECT_FALSE(toy_hard->avoided);
  EXPECT_TRUE(toy_hard->contact);
  EXPECT_GT(toy_hard->impact.impact_speed_mps, 0.0);
  EXPECT_EQ(hard.region, sim::Region::kG);  // the emergency stop still avoids
}

TEST(ToyStrategy, CountsForTheRegionAsAnEvasiveStrategy) {
  // A toy that always "avoids" (it reports itself stopped without driving) turns every cell in which
  // the emergency stop fails into Y: the region rule reads roles from the registry, not names.
  class Oracle final : public sim::Strategy {
   public:
    sim::StrategyOutcome run(const sim::StrategyInfo& self, const sim::StrategyContext& c) const override {
      sim::RolloutResult r;
      r.termination = sim::Termination::kStopped;
      r.path.push_back({0.0, c.scene.ego_initial(), {}});
      return sim::outcome_of(self.name, r, c.unmitigated, c.scene);
    }
  };
  sim::StrategyInfo info = half_brake_info();
  info.name = "oracle";
  sim::SceneConfig config;
  config.planner.max_nodes = 1;
  const sim::CellInput cell{70.0, 0.3, 1.0, 3.0, 10.0};  // nothing real avoids this
  const sim::Region without = sim::simulate_cell(config, cell, {}).region;
  ASSERT_NE(without, sim::Region::kY);
  {
    const sim::StrategyRegistration oracle(info, std::make_shared<Oracle>());
    EXPECT_EQ(sim::simulate_cell(config, cell, {}).region, sim::Region::kY);
  }
  info.role = sim::StrategyRole::kChooser;  // a chooser only repeats another's outcome: it never counts
  info.order = 200;
  const sim::StrategyRegistration chooser(info, std::make_shared<Oracle>());
  EXPECT_EQ(sim::simulate_cell(config, cell, {}).region, without);
}

// A few simulated cells of a grid named "toy", as the results store would hand them back.
std::vector<campaign::CellRecord> toy_records() {
  sim::SceneConfig config;
  config.planner.max_nodes = 20;
  std::vector<campaign::CellRecord> records;
  std::int64_t index = 0;
  for (double speed : {40.0, 50.0, 60.0})
    for (double ttc : {0.9, 1.3}) {
      const sim::CellResult r = sim::simulate_cell(config, {speed, ttc, 1.0, 3.0, 10.0}, {});
      records.push_back(campaign::to_record(sim::SceneConfig{}, "toy", index++, 1, r));
    }
  return records;
}

TEST(ToyStrategy, AppearsInTheTablesWithItsTitle) {
  const sim::StrategyRegistration toy(half_brake_info(), std::make_shared<HalfBrake>());
  const auto paper = results::load_paper_reference(EMRM_SOURCE_DIR "/examples/tjunction/paper_reference.yaml");
  const core::Table t = results::emrm_vs_baseline_table(toy_records(), paper, "toy");
  // The paper has no column for it: it is shown as ours only, under its registered title.
  EXPECT_NE(std::find(t.header.begin(), t.header.end(), "Half Brake (half_brake, ours only)"), t.header.end())
      << core::join(t.header, " | ");
  const std::string csv = results::kpis_csv(toy_records(), results::level_cuts(sim::SceneConfig{}));
  EXPECT_NE(csv.find("half_brake"), std::string::npos);
}

TEST(ToyStrategy, IsDrawnInItsColourWithItsLabel) {
  const sim::StrategyRegistration toy(half_brake_info(), std::make_shared<HalfBrake>());
  const core::TempDir dir("emrm-toy");
  const report::Figure f = report::draw_loss_comparison(toy_records(), "toy", dir.path());
  ASSERT_TRUE(f.note.empty()) << f.note;
  const std::string csv = core::read_file(f.csv);
  EXPECT_NE(csv.find("\nhalf_brake,"), std::string::npos) << csv;
  const std::string svg = core::read_file(f.svg);
  EXPECT_NE(svg.find("half brake"), std::string::npos);          // its label under its bar
  EXPECT_NE(svg.find("rgb( 23, 190, 207)"), std::string::npos);  // #17becf, its registered colour
}

TEST(ToyPlanner, IsFoundByNameAndDrivesAPlannedStrategy) {
  // A planner that never finds anything: a planned strategy using it falls back to the baseline's
  // outcome (documented for a strategy whose every branch breaks its constraint).
  class Nothing final : public sim::Planner {
   public:
    std::string_view name() const override { return "nothing"; }
    sim::PlanResult plan(const sim::PlanningProblem& /*problem*/) const override { return {}; }
  };
  {
    const sim::PlannerRegistration planner(std::make_unique<Nothing>());
    ASSERT_NE(sim::find_planner("nothing"), nullptr);
    EXPECT_THROW(sim::PlannerRegistration(std::make_unique<Nothing>()), UsageError);
    sim::StrategyInfo info = half_brake_info();
    info.name = "hopeless";
    info.planner = "nothing";
    const sim::StrategyRegistration hopeless(info, sim::planned_strategy());
    sim::SceneConfig config;
    config.planner.max_nodes = 1;
    const sim::CellResult r = sim::simulate_cell(config, {60.0, 1.2, 1.0, 3.0, 10.0}, {});
    const auto* o = outcome(r, "hopeless");
    const auto* stop = outcome(r, "emergency_stop");
    ASSERT_NE(o, nullptr);
    ASSERT_NE(stop, nullptr);
    EXPECT_EQ(o->adopted_from, "emergency_stop");
    EXPECT_EQ(o->avoided, stop->avoided);
  }
  EXPECT_EQ(sim::find_planner("nothing"), nullptr);
  EXPECT_NE(sim::find_planner("rrt"), nullptr);
  EXPECT_NE(sim::find_planner("reference"), nullptr);
}

TEST(ToyStrategy, RegistrationChecksItsRecord) {
  const sim::StrategyRegistration toy(half_brake_info(), std::make_shared<HalfBrake>());
  EXPECT_THROW(sim::StrategyRegistration(half_brake_info(), std::make_shared<HalfBrake>()), UsageError);
  sim::StrategyInfo unknown_planner = half_brake_info();
  unknown_planner.name = "lost";
  unknown_planner.planner = "no_such_planner";
  EXPECT_THROW(sim::StrategyRegistration(unknown_planner, std::make_shared<HalfBrake>()), UsageError);
  sim::StrategyInfo adopts_later = half_brake_info();
  adopts_later.name = "impatient";
  adopts_later.may_adopt = {"emrm"};  // evaluated after it
  EXPECT_THROW(sim::StrategyRegistration(adopts_later, std::make_shared<HalfBrake>()), UsageError);
  EXPECT_THROW(sim::StrategyRegistration(half_brake_info(), nullptr), UsageError);
}

}  // namespace toy_strategy_test
}  // namespace emrm
