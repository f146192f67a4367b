// The outcome model: what counts as an avoidance (a safe state after the truck), one impact model
// for the unmitigated reference and the strategies, road departures assessed against the roadside,
// contact and departure found between samples, and the oracle never worse than EMRM's options
// (docs/physics.md, docs/simulate.md).

#include <gtest/gtest.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_group.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "emrm/core/random.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/strategy.hpp"
#include "outcomes.hpp"

namespace emrm::sim {
namespace outcome_model_test {

using test::outcome;

// The safe state written out independently of the termination tests: at rest on the road, or
// stable (the scene's bounds) with a straight full stop from here staying on the road.
::testing::AssertionResult ends_safe(const SceneConfig& config, const TJunctionCell& cell, const StrategyOutcome& o) {
  const Scene scene(config, cell);
  const VehicleState& s = o.path.back().state;
  const auto box = scene.ego_box(s);
  if (!scene.on_drivable_area(box)) return ::testing::AssertionFailure() << o.strategy << " ends off the road";
  if (s.speed_mps() < 0.05) return ::testing::AssertionSuccess();
  const auto& b = config.safe_state;
  const double heading = std::remainder(s.yaw_rad, 2.0 * std::numbers::pi);
  if (std::abs(s.yaw_rate_radps) > b.max_yaw_rate_radps || std::abs(s.slip_angle_rad()) > b.max_slip_angle_rad ||
      std::abs(heading) > b.max_heading_error_rad || std::abs(s.steer_rad) > b.max_steer_rad)
    return ::testing::AssertionFailure() << o.strategy << " ends unstable: r " << s.yaw_rate_radps << " rad/s, beta "
                                         << s.slip_angle_rad() << " rad, heading " << heading << " rad, steer "
                                         << s.steer_rad << " rad at " << s.speed_mps() << " m/s";
  const double stop_m = s.speed_mps() * s.speed_mps() / (2.0 * cell.mu * kGravity_mps2);
  auto at_rest = box;
  at_rest.center = at_rest.center + core::Vec2::unit(s.yaw_rad) * stop_m;
  if (!scene.on_drivable_area(at_rest))
    return ::testing::AssertionFailure() << o.strategy << " has no room to stop on the road";
  return ::testing::AssertionSuccess();
}

double lowest_corner_y(const Scene& scene, const VehicleState& state) {
  double lowest = 1e9;
  for (const auto& corner : scene.ego_box(state).corners()) lowest = std::min(lowest, corner.y);
  return lowest;
}

// Cells across the band where braking alone fails (dry road, wide and tight passages, wet road).
std::vector<TJunctionCell> evasion_cells() {
  std::vector<TJunctionCell> cells;
  for (const double speed : {40.0, 55.0, 70.0})
    for (const double ttc : {0.45, 0.7})
      for (const double passage : {3.0, 2.0}) cells.push_back({speed, ttc, 1.0, passage, 10.0});
  cells.push_back({65.0, 1.1, 0.5, 2.0, 10.0});
  cells.push_back({50.0, 1.3, 0.5, 3.0, 10.0});
  return cells;
}

TEST(SafeState, EveryAvoidanceEndsStoppedOrStableWithRoomToStop) {
  const SceneConfig config;
  int avoided = 0;
  for (const TJunctionCell& cell : evasion_cells()) {
    const CellResult r = simulate_cell(config, cell, {});
    for (const auto& o : r.strategies) {
      if (!o.avoided) continue;
      ++avoided;
      EXPECT_TRUE(ends_safe(config, cell, o)) << cell.speed_kph << " km/h, TTC " << cell.ttc_s << " s, mu " << cell.mu
                                              << ", passage " << cell.passage_m << " m";
    }
  }
  EXPECT_GT(avoided, 0);  // the property is not vacuous
}

TEST(SafeState, PassingTheTruckHandsOverToRecoveryUntilStable) {
  // Coasting past a truck that has already crossed (a wide passage, the car in its lane) with the
  // wheels turned a little: passing is not the end; the recovery straightens and brakes the car.
  SceneConfig config;
  config.simulation.horizon_s = 6.0;
  const Scene scene(config, {50.0, 1.0, 1.0, 8.0, 10.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const Roller roller(scene, *model, ControlLimits{});
  Control swerve;
  swerve.steer_rate_radps = 0.02;
  const std::vector<ControlSegment> plan{hold(swerve, 0.5)};
  const RolloutResult r = roller.roll(scene.ego_initial(), 0.0, plan, Tail{}, 1);
  ASSERT_TRUE(r.avoided()) << static_cast<int>(r.termination);
  EXPECT_TRUE(r.termination == Termination::kStabilised || r.termination == Termination::kStopped);
  EXPECT_GT(scene.ego_box(r.end_state).center.x, scene.passed_x_m());

  Roller without(scene, *model, ControlLimits{});
  without.set_recovery(false);
  const RolloutResult passed = without.roll(scene.ego_initial(), 0.0, plan, Tail{}, 1);
  EXPECT_EQ(passed.termination, Termination::kPassed);
  EXPECT_LT(passed.end_time_s, r.end_time_s);
}

TEST(OneImpactModel, AStopThatNeverBrakesBeforeContactIsTheUnmitigatedReference) {
  // With the latency longer than the time to collision the emergency stop is the no-action
  // trajectory: its impact must be the reference's, number for number (one model for both).
  for (const double speed : {40.0, 55.0, 70.0}) {
    SceneConfig config;
    config.actuation.perception_latency_s = 1.0;
    config.planner.max_nodes = 1;
    const CellResult r = simulate_cell(config, {speed, 0.3, 1.0, 3.0, 10.0}, {});
    const auto& stop = outcome(r, "emergency_stop");
    ASSERT_TRUE(stop.contact);
    EXPECT_NEAR(stop.impact.delta_v_mps, r.unmitigated.delta_v_mps, 1e-9) << speed;
    EXPECT_EQ(stop.impact.loss_level, r.unmitigated.loss_level);
    EXPECT_EQ(stop.delta_loss, 0);
  }
}

TEST(OneImpactModel, BrakingNeverScoresWorseThanTheReference) {
  // Same contact geometry, lower speed: the stop's Δv is below the unmitigated one in every cell
  // where both hit (the reference used a central formula that overstated Δv before).
  SceneConfig config;
  config.planner.max_nodes = 1;
  for (const double speed : {35.0, 50.0, 65.0, 72.0})
    for (const double ttc : {0.25, 0.4, 0.6}) {
      const CellResult r = simulate_cell(config, {speed, ttc, 1.0, 3.0, 10.0}, {});
      const auto& stop = outcome(r, "emergency_stop");
      if (!stop.contact) continue;
      EXPECT_LT(stop.impact.delta_v_mps, r.unmitigated.delta_v_mps) << speed << " " << ttc;
      EXPECT_LE(stop.impact.loss_level, r.unmitigated.loss_level);
    }
}

// A car coasting straight across the right edge of an open road, heading `heading_rad` (< 0).
RolloutResult leave_the_road(const SceneConfig& config, double speed_kph, double heading_rad) {
  const Scene scene(config, {speed_kph, 2.0, 1.0, 5.0, 0.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const Roller roller(scene, *model, ControlLimits{});
  VehicleState start = scene.ego_initial();
  start.yaw_rad = heading_rad;
  return roller.roll(start, 0.0, {}, Tail{}, 1);
}

TEST(Roadside, ADepartureIntoTheBarrierIsAnImpactScoredLikeAnyOther) {
  const SceneConfig config;  // roadside: barrier
  const SeverityConfig& c = config.severity;
  for (const double heading : {-0.2, -0.5, -0.9}) {
    double previous_delta_v = 0.0;
    for (const double speed : {30.0, 50.0, 70.0, 100.0}) {
      const RolloutResult r = leave_the_road(config, speed, heading);
      ASSERT_EQ(r.termination, Termination::kRoadDeparture) << speed;
      EXPECT_NEAR(r.impact.impact_speed_mps, r.end_state.speed_mps(), 1e-9);
      // A wall takes at most the normal speed of the corner that meets it (plastic impact).
      const double normal_speed = r.end_state.speed_mps() * std::sin(-heading);
      EXPECT_GT(r.impact.delta_v_mps, 0.3 * normal_speed);
      EXPECT_LE(r.impact.delta_v_mps, normal_speed * (1.0 + c.contact_friction) + 1e-9);
      EXPECT_NEAR(r.impact.p_mais3, p_mais3(r.impact.delta_v_mps, c), 1e-12);
      EXPECT_EQ(r.impact.loss_level, loss_level(true, true, r.impact.p_mais3, r.impact.p_fatal, c));
      EXPECT_GT(r.impact.delta_v_mps, previous_delta_v) << "faster departures at one angle hit harder";
      previous_delta_v = r.impact.delta_v_mps;
    }
  }
  EXPECT_GT(leave_the_road(config, 70.0, -0.5).impact.delta_v_mps,
            leave_the_road(config, 70.0, -0.2).impact.delta_v_mps);  // steeper hits harder
  // A steep departure at 100 km/h is no longer a free L4: it scores as the impact it is.
  EXPECT_GE(leave_the_road(config, 100.0, -0.9).impact.loss_level, 6);
}

TEST(Roadside, OpenGroundScoresADepartureAtL4WithoutImpact) {
  SceneConfig config;
  config.roadside.type = "open";
  const RolloutResult r = leave_the_road(config, 70.0, -0.5);
  ASSERT_EQ(r.termination, Termination::kRoadDeparture);
  EXPECT_EQ(r.impact.delta_v_mps, 0.0);
  EXPECT_EQ(r.impact.loss_level, 4);
  EXPECT_NEAR(r.impact.impact_speed_mps, r.end_state.speed_mps(), 1e-9);
}

TEST(Roadside, TheDepartureIsTimedAtTheEdge) {
  const SceneConfig config;
  const RolloutResult r = leave_the_road(config, 60.0, -0.3);
  ASSERT_EQ(r.termination, Termination::kRoadDeparture);
  const Scene scene(config, {60.0, 2.0, 1.0, 5.0, 0.0});
  EXPECT_NEAR(lowest_corner_y(scene, r.end_state), config.road.drivable_min_y_m(), 1e-3);
}

TEST(ContinuousCollision, ACoarseStepDoesNotTunnelThroughTheTruck) {
  // 50 m/s with 0.2 s steps: from 2 m before the truck's near side the car's samples jump past its
  // 2.5 m depth (10 m per step). Checking only the samples would let the car drive through it.
  SceneConfig config;
  config.simulation.dt_s = 0.2;
  config.simulation.horizon_s = 4.0;
  const Scene scene(config, {180.0, 2.0 / 50.0, 1.0, 3.0, 0.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const RolloutResult r = no_action_rollout(scene, *model);
  ASSERT_EQ(r.termination, Termination::kContact);
  EXPECT_NEAR(r.end_time_s, 2.0 / 50.0, 1e-5);  // the moment the bumper meets the near side
  EXPECT_NEAR(r.impact.impact_speed_mps, 50.0, 1e-6);
}

TEST(ContinuousCollision, ACoarseStepDoesNotJumpAcrossTheRoadEdge) {
  // A car crossing the shoulder diagonally within one coarse step is caught at the edge.
  SceneConfig config;
  config.simulation.dt_s = 0.25;
  const Scene scene(config, {100.0, 2.0, 1.0, 5.0, 0.0});
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const Roller roller(scene, *model, ControlLimits{});
  VehicleState start = scene.ego_initial();
  start.yaw_rad = -0.6;  // heading across the road at 27.8 m/s: ~15 m of lateral travel per step
  const RolloutResult r = roller.roll(start, 0.0, {}, Tail{}, 1);
  ASSERT_EQ(r.termination, Termination::kRoadDeparture);
  EXPECT_LT(r.end_time_s, 0.25);
  EXPECT_NEAR(lowest_corner_y(scene, r.end_state), config.road.drivable_min_y_m(), 1e-3);
}

TEST(EmrmChoice, TheOracleIsNeverWorseThanTheStrategiesEmrmMayChoose) {
  // Dry, wet and icy cells, where the loss-evaluation FSM's class-based choice and the simulated
  // outcomes can disagree: the oracle (best_strategy) takes the best outcome in hindsight and says
  // whose it took; the controller (emrm), which commits before it knows the outcome, may be worse
  // than an option but never better than the oracle.
  SceneConfig config;
  config.planner.max_nodes = 400;
  const StrategyTable table = registered_strategies();
  int controller_worse = 0;
  for (const double mu : {0.1, 0.15, 0.2, 0.5, 1.0})
    for (const double speed : {40.0, 60.0})
      for (const double ttc : {0.5, 1.0}) {
        const CellResult r = simulate_cell(config, {speed, ttc, mu, 3.0, 10.0}, {});
        const auto& oracle = outcome(r, "best_strategy");
        for (const auto& o : r.strategies) {
          const StrategyInfo* info = table.info(o.strategy);
          if (info == nullptr || !info->emrm_may_choose) continue;
          EXPECT_FALSE(better_outcome(o, oracle))
              << o.strategy << " beats the oracle at " << speed << " km/h, TTC " << ttc << ", mu " << mu;
        }
        EXPECT_FALSE(better_outcome(outcome(r, "emrm"), oracle))
            << "emrm beats the oracle at " << speed << " km/h, TTC " << ttc << ", mu " << mu;
        if (better_outcome(oracle, outcome(r, "emrm"))) ++controller_worse;
      }
  RecordProperty("controller_worse", controller_worse);
}

TEST(EmrmChoice, ALaterStrategysAvoidanceIsSharedWithAnEarlierOneWhoseLimitsItObeys) {
  const ControlLimits dodge{.forbid_rear_sliding = true};
  const ControlLimits drift{.allow_rear_lock = true};
  const ControlLimits accident{.allow_rear_lock = true, .accept_contact = true};
  EXPECT_TRUE(avoidance_admissible(accident, drift));  // a drift to accident that avoids is a drift to avoid
  EXPECT_TRUE(avoidance_admissible(dodge, drift));     // a dodge is a legal drift
  EXPECT_FALSE(avoidance_admissible(drift, dodge));    // a drift may slide the rear: not a dodge
  EXPECT_FALSE(avoidance_admissible(accident, dodge));
}

}  // namespace outcome_model_test
}  // namespace emrm::sim

namespace emrm::sim {
namespace outcome_model_test {

TEST(Witness, TheStitchedManeuverOfAPlannerReplaysItsRunStepForStep) {
  // The RRT builds its answer from tree edges rolled out from nodes at various times, recorded every
  // fifth step; the maneuver it reports (the edges' controls chained, through JSON and back) must
  // replay from t = 0 to the very same run: same end, same time, same impact, and every point the
  // planner recorded found again at its time.
  const SceneConfig config;
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const ControlLimits drift{.allow_rear_lock = true};
  int compared = 0;
  for (const TJunctionCell& cell : evasion_cells()) {
    const Scene scene(config, cell);
    const PlanResult plan = plan_rrt(scene, *model, drift, 7, false);
    for (const auto* found : {&plan.avoidance, &plan.collision}) {
      if (!found->has_value()) continue;
      const RolloutResult& planned = **found;
      const Maneuver maneuver = maneuver_from_json(to_json(planned.maneuver), "test");
      const RolloutResult again = replay(scene, *model, drift, maneuver);
      ++compared;
      EXPECT_EQ(again.termination, planned.termination) << cell.speed_kph << " " << cell.ttc_s;
      EXPECT_EQ(again.end_time_s, planned.end_time_s);
      EXPECT_EQ(again.end_state.x_m, planned.end_state.x_m);
      EXPECT_EQ(again.end_state.y_m, planned.end_state.y_m);
      EXPECT_EQ(again.impact.delta_v_mps, planned.impact.delta_v_mps);
      std::size_t k = 0;
      for (const auto& point : planned.path) {
        while (k < again.path.size() && again.path[k].t_s < point.t_s - 1e-12) ++k;
        ASSERT_LT(k, again.path.size()) << "no replayed point at t = " << point.t_s;
        EXPECT_EQ(again.path[k].state.x_m, point.state.x_m) << "t = " << point.t_s;
        EXPECT_EQ(again.path[k].state.yaw_rad, point.state.yaw_rad) << "t = " << point.t_s;
      }
      for (std::size_t n = 1; n + 1 < again.path.size(); ++n)
        ASSERT_NEAR(again.path[n].t_s - again.path[n - 1].t_s, config.simulation.dt_s, 1e-9) << "every step";
    }
  }
  EXPECT_GT(compared, 10);
}

}  // namespace outcome_model_test
}  // namespace emrm::sim

namespace emrm::sim {
namespace outcome_model_test {

// The region of a cell for several seeds: the same for every seed, or undecided for every seed.
::testing::AssertionResult seed_stable(const SceneConfig& config, const TJunctionCell& cell, int seeds) {
  std::string regions;
  bool all_undecided = true;
  bool same = true;
  Region first = Region::kInfeasible;
  for (int seed = 1; seed <= seeds; ++seed) {
    CellOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    const CellResult r = simulate_cell(config, cell, options);
    if (seed == 1) first = r.region;
    same = same && r.region == first;
    all_undecided = all_undecided && r.evidence == Evidence::kUndecided;
    regions += std::string(region_name(r.region)) + "/" + std::string(evidence_name(r.evidence)) + " ";
  }
  if (same || all_undecided) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << cell.speed_kph << " km/h, TTC " << cell.ttc_s << " s, mu " << cell.mu
                                       << ", passage " << cell.passage_m << " m: " << regions;
}

TEST(SeedStability, TheRegionDoesNotDependOnThePlannersSeed) {
  // The wet-road cell that gave Y O O Y O O O Y for seeds 1…8 when a single search decided it,
  // and cells on the edges of the evasion band (dry, wet, narrow).
  const SceneConfig config;
  const std::vector<TJunctionCell> cells{{65.0, 1.1, 0.5, 2.0, 10.0},  {60.0, 0.4, 1.0, 3.0, 10.0},
                                         {45.0, 0.35, 1.0, 3.0, 10.0}, {70.0, 0.5, 1.0, 2.0, 10.0},
                                         {50.0, 0.9, 0.6, 2.5, 10.0},  {40.0, 0.3, 1.0, 1.8, 10.0}};
  for (const auto& cell : cells) EXPECT_TRUE(seed_stable(config, cell, 3));
}

// The restarts of a strengthened search run side by side. When the caller's parallel work is
// cancelled around a cell in flight (an adaptive search stopping at an interrupt throws in a
// neighbouring task), they must not be cut short: the cell's result is its result alone, not one
// resting on the restarts that happened to start (before, a skipped restart was read as if it had
// run, and the sweep crashed).
TEST(SeedStability, AStrengthenedSearchIsNotCutShortWhenItsCallersWorkIsCancelled) {
  // A cell of the shipped scene whose region the restarts decide (Y, with a witness).
  const SceneConfig config = load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/scene.yaml");
  const TJunctionCell cell{61.0, 0.91, 1.0, 3.0, 10.0};
  CellOptions options;
  options.seed = 13957258665385695640ULL;
  const CellResult alone = simulate_cell(config, cell, options);
  ASSERT_TRUE(alone.strengthened);
  std::optional<CellResult> inside;
  tbb::task_group_context cancelled;
  tbb::parallel_for(
      0, 1,
      [&](int) {
        cancelled.cancel_group_execution();  // as a neighbouring task's exception would
        inside = simulate_cell(config, cell, options);
      },
      cancelled);
  ASSERT_TRUE(inside.has_value());
  const Scene scene(config, cell);
  EXPECT_EQ(inside->region, alone.region);
  EXPECT_EQ(to_json(*inside, scene, options.seed).dump(), to_json(alone, scene, options.seed).dump());
}

// The long run for the closing note: 100 random cells in the band below the stop boundary (where
// Y, O and R meet) × 5 seeds. Run with --gtest_also_run_disabled_tests.
TEST(SeedStability, DISABLED_HundredCellsNearTheBoundariesFiveSeeds) {
  const SceneConfig config;
  std::mt19937_64 random(20261124);
  const auto uniform = [&] { return core::uniform01(random); };
  int tried = 0;
  int stable = 0;
  while (tried < 100) {
    const double speed = 30.0 + 42.0 * uniform();
    const double mu = 0.3 + 0.7 * uniform();
    const double stop_ttc = speed / 3.6 / (2.0 * mu * kGravity_mps2);
    const TJunctionCell cell{speed, std::max(0.1, stop_ttc - 0.6 * uniform()), mu, 1.5 + 2.0 * uniform(), 10.0};
    if (!Scene(config, cell).feasible()) continue;
    ++tried;
    const auto verdict = seed_stable(config, cell, 5);
    stable += static_cast<bool>(verdict);
    EXPECT_TRUE(verdict);
  }
  RecordProperty("stable", stable);
  std::printf("seed stability: %d of %d cells stable over 5 seeds\n", stable, tried);
}

}  // namespace outcome_model_test
}  // namespace emrm::sim

namespace emrm::sim {
namespace outcome_model_test {

TEST(Evidence, ACertifiedCellSkipsTheAvoidanceSearchesAndSaysWhy) {
  // 70 km/h, 4.9 m to the truck: no car gets past it. The certificate settles the region, and
  // the searches it makes pointless are not run; with certify off they run and find nothing.
  const SceneConfig config;
  const TJunctionCell cell{70.0, 0.25, 1.0, 3.0, 10.0};
  const CellResult r = simulate_cell(config, cell, {});
  ASSERT_TRUE(r.certificate.has_value());
  EXPECT_TRUE(check_certificate(Scene(config, cell), *r.certificate));
  EXPECT_TRUE(r.region == Region::kO || r.region == Region::kR);
  EXPECT_EQ(r.evidence, Evidence::kCertificate);
  EXPECT_FALSE(r.strengthened);
  for (const char* name : {"dodge", "drift_to_avoid"}) {
    EXPECT_EQ(outcome(r, name).planner.nodes, 0) << name;
    EXPECT_EQ(outcome(r, name).evidence, Evidence::kCertificate) << name;
  }
  CellOptions full;
  full.certify = false;
  const CellResult searched = simulate_cell(config, cell, full);
  EXPECT_FALSE(searched.certificate.has_value());
  EXPECT_GT(outcome(searched, "dodge").planner.nodes, 0);
  for (const auto& o : searched.strategies) EXPECT_FALSE(o.avoided) << o.strategy;
  EXPECT_EQ(searched.evidence, Evidence::kUndecided);
}

TEST(Evidence, GreenAndYellowCellsCarryWitnessesOrangeAndRedNeverDo) {
  const SceneConfig config;
  for (const TJunctionCell& cell : evasion_cells()) {
    const CellResult r = simulate_cell(config, cell, {});
    if (r.region == Region::kG || r.region == Region::kY) {
      EXPECT_EQ(r.evidence, Evidence::kWitness);
      EXPECT_EQ(r.mitigation_evidence, MitigationEvidence::kNone);
    } else {
      EXPECT_NE(r.evidence, Evidence::kWitness);
      EXPECT_NE(r.mitigation_evidence, MitigationEvidence::kNone);
    }
    EXPECT_GE(r.p_mais3_reduction, 0.0);
    EXPECT_LE(r.p_mais3_reduction, r.unmitigated.p_mais3);
  }
}

}  // namespace outcome_model_test
}  // namespace emrm::sim
