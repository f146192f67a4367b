// Rollouts, the RRT and the reference planner.

#include "emrm/sim/planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <utility>

#include "emrm/sim/simulate.hpp"
#include "test_scale.hpp"

namespace emrm::sim {
namespace planner_test {

constexpr int kComparisonCells = test::sample(200, 40);  // tests/common/test_scale.hpp

TEST(Roller, CoastingHitsTheTruckAtTheTimeToCollision) {
  const SceneConfig config;
  const Scene scene(config, {50.0, 1.2, 1.0, 3.0, 10.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const Roller roller(scene, *model, {});
  const auto r = roller.roll(scene.ego_initial(), 0.0, {}, Tail{}, 5);
  ASSERT_EQ(r.termination, Termination::kContact);
  EXPECT_NEAR(r.end_time_s, 1.2, config.simulation.dt_s / 100);
  EXPECT_NEAR(r.impact.impact_speed_mps, 50.0 / 3.6, 1e-6);
}

// The public check() of the checkers (for a caller that runs them outside a Roller) answers as
// the per-step ends() does: nothing for a free car mid-road, contact for a car inside the truck,
// the horizon at its end.
// The first step of a car going straight from its start: no check ends it.
Step first_step(const Scene& scene, const SceneConfig& config) {
  Step free;
  free.before = free.state = scene.ego_initial();
  free.t_s = free.dt_s = config.simulation.dt_s;
  free.ego = scene.ego_box(free.state);
  free.truck = scene.hazard_at(free.t_s);
  free.ego_extent = extent_of(free.ego);
  free.truck_extent = extent_of(free.truck.box);
  return free;
}

TEST(Roller, CheckersAnswerThroughCheckAsTheyDoPerStep) {
  const SceneConfig config;
  const Scene scene(config, {50.0, 1.2, 1.0, 3.0, 10.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const ValidityChecker validity(scene, *model, ControlLimits{});
  const TerminationTest termination(scene);
  RolloutResult result;

  Step free = first_step(scene, config);
  EXPECT_EQ(validity.check(free, result), std::nullopt);
  EXPECT_EQ(termination.check(free, result), std::nullopt);

  Step late = free;
  late.t_s = config.simulation.horizon_s;
  EXPECT_EQ(termination.check(late, result), Termination::kHorizon);

  Step inside = free;
  inside.state.x_m = inside.before.x_m = scene.hazard_at(free.t_s).box.center.x;
  inside.state.y_m = inside.before.y_m = scene.hazard_at(free.t_s).box.center.y;
  inside.ego = scene.ego_box(inside.state);
  EXPECT_EQ(validity.check(inside, result), Termination::kContact);
}

// A check added to a checker, answering `answer` and counting its calls.
class CountingCheck final : public StepCheck {
 public:
  CountingCheck(Termination answer, int& calls) : answer_(answer), calls_(calls) {}
  [[nodiscard]] std::optional<Termination> check(Step& /*step*/, RolloutResult& /*result*/) const override {
    ++calls_;
    return answer_;
  }

 private:
  Termination answer_;
  int& calls_;
};

// Both checkers run the checks added to them after their built-in ones, in the order added: a step a
// built-in check ends never reaches them; one it lets through gets the first added check's answer.
TEST(Roller, ChecksAddedToEitherCheckerRunAfterItsBuiltInOnes) {
  const SceneConfig config;
  const Scene scene(config, {50.0, 1.2, 1.0, 3.0, 10.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  int validity_calls = 0, termination_calls = 0, second_calls = 0;
  ValidityChecker validity(scene, *model, ControlLimits{});
  validity.add(std::make_unique<CountingCheck>(Termination::kOpen, validity_calls))
      .add(std::make_unique<CountingCheck>(Termination::kConstraint, second_calls));
  TerminationTest termination(scene);
  termination.add(std::make_unique<CountingCheck>(Termination::kStabilised, termination_calls));
  RolloutResult result;

  Step free = first_step(scene, config);
  Step inside = free;
  inside.state.x_m = inside.before.x_m = scene.hazard_at(free.t_s).box.center.x;
  inside.state.y_m = inside.before.y_m = scene.hazard_at(free.t_s).box.center.y;
  inside.ego = scene.ego_box(inside.state);
  EXPECT_EQ(validity.check(inside, result), Termination::kContact);
  EXPECT_EQ(validity_calls, 0);
  EXPECT_EQ(validity.check(free, result), Termination::kOpen);
  EXPECT_EQ(validity_calls, 1);
  EXPECT_EQ(second_calls, 0);

  Step late = free;
  late.t_s = config.simulation.horizon_s;
  EXPECT_EQ(termination.check(late, result), Termination::kHorizon);
  EXPECT_EQ(termination_calls, 0);
  Termination why = Termination::kHorizon;
  EXPECT_TRUE(termination.ends(free, result, why));
  EXPECT_EQ(why, Termination::kStabilised);
  EXPECT_EQ(termination_calls, 1);

  // In a Roller: the added validity check ends the first step that the built-in ones let through.
  const Roller roller(scene, *model, {}, std::move(validity), std::move(termination));
  const RolloutResult r = roller.roll(scene.ego_initial(), 0.0, {}, Tail{}, 1);
  EXPECT_EQ(r.termination, Termination::kOpen);
  EXPECT_NEAR(r.end_time_s, config.simulation.dt_s, 1e-12);
  EXPECT_EQ(validity_calls, 2);
}

TEST(Roller, FullStopOnAnOpenRoadStopsAtTheClosedFormDistance) {
  const SceneConfig config;
  const Scene scene(config, {60.0, 2.0, 0.7, 3.0, 10.0});  // 33 m to the truck, 20 m needed
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const auto r = Roller(scene, *model, {}).roll(scene.ego_initial(), 0.0, {}, Tail::full_stop(), 1);
  ASSERT_EQ(r.termination, Termination::kStopped);
  const double v = 60.0 / 3.6;
  const double travelled = r.end_state.x_m - scene.ego_initial().x_m;
  EXPECT_NEAR(travelled, v * v / (2 * 0.7 * kGravity_mps2), v * config.simulation.dt_s);
}

TEST(Rrt, SameSeedSamePlan) {
  const SceneConfig config;
  const Scene scene(config, {60.0, 0.8, 1.0, 3.0, 10.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const ControlLimits drift{.allow_rear_lock = true};
  const auto a = plan_rrt(scene, *model, drift, 42, true);
  const auto b = plan_rrt(scene, *model, drift, 42, true);
  EXPECT_EQ(a.stats.nodes, b.stats.nodes);
  EXPECT_EQ(a.stats.rollouts, b.stats.rollouts);
  ASSERT_EQ(a.tree.size(), b.tree.size());
  ASSERT_EQ(a.avoidance.has_value(), b.avoidance.has_value());
  if (a.avoidance) {
    ASSERT_EQ(a.avoidance->path.size(), b.avoidance->path.size());
    EXPECT_EQ(a.avoidance->path.back().state.x_m, b.avoidance->path.back().state.x_m);
  }
}

TEST(Rrt, DodgePathsNeverLockOrSlideTheRearAxle) {
  const SceneConfig config;
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  int found = 0;
  for (double ttc : {0.7, 0.8, 0.9})
    for (double speed : {50.0, 60.0, 70.0}) {
      const Scene scene(config, {speed, ttc, 1.0, 3.0, 10.0});
      const auto plan = plan_rrt(scene, *model, {.forbid_rear_sliding = true}, 3, false);
      if (!plan.avoidance) continue;
      ++found;
      for (const auto& p : plan.avoidance->path) {
        EXPECT_FALSE(p.control.rear_lock);
        const auto rear = model->tire_forces(p.state, p.control, 1.0).rear;
        EXPECT_FALSE(rear.saturated && std::abs(rear.slip_angle_rad) > 0.035)
            << "t " << p.t_s << " v " << p.state.speed_mps() << " slip " << rear.slip_angle_rad << " brake "
            << p.control.brake;
      }
    }
  EXPECT_GT(found, 0);
}

// The RRT must find an avoidance wherever the dense reference family finds one, in at least 99 %
// of the cells of a seeded sample of the ODD (200 feasible cells, the first 40 of them under the
// sanitizers; dodge and drift_to_avoid).
TEST(Rrt, FindsAnAvoidanceWhereverTheReferencePlannerDoesIn99PercentOfCells) {
  const SceneConfig config;
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> speed(30, 72), ttc(0.25, 2.95), mu(0.1, 1.0), passage(1.0, 3.0);
  int cells = 0;
  int reference_avoids = 0;
  int rrt_misses = 0;
  while (cells < kComparisonCells) {
    const TJunctionCell cell{speed(rng), ttc(rng), mu(rng), passage(rng), 10.0};
    const Scene scene(config, cell);
    if (!scene.feasible()) continue;
    ++cells;
    const auto result = simulate_cell(config, cell, {});
    for (const auto& [name, limits] :
         {std::pair{std::string("dodge"), ControlLimits{.forbid_rear_sliding = true}},
          std::pair{std::string("drift_to_avoid"), ControlLimits{.allow_rear_lock = true}}}) {
      const auto reference = plan_reference(scene, *model, limits);
      if (!reference.avoidance) continue;
      ++reference_avoids;
      bool avoided = false;
      for (const auto& o : result.strategies)
        if (o.strategy == name) avoided = o.avoided;
      if (!avoided) {
        ++rrt_misses;
        std::printf("miss: %s at %.1f km/h, TTC %.2f s, mu %.2f, passage %.2f m\n", name.c_str(), cell.speed_kph,
                    cell.ttc_s, cell.mu, cell.passage_m);
      }
    }
  }
  std::printf("RRT vs reference: %d cells, reference avoids %d strategy-cells, RRT misses %d\n", cells,
              reference_avoids, rrt_misses);
  RecordProperty("reference_avoids", reference_avoids);
  RecordProperty("rrt_misses", rrt_misses);
  EXPECT_GT(reference_avoids, 0);
  EXPECT_LE(rrt_misses * 100, reference_avoids);
}

}  // namespace planner_test
}  // namespace emrm::sim
