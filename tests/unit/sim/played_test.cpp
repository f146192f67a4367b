// A scenario played open loop laid out as one cell's scene (sim/played.hpp): the threat onset at
// the TTC's closed form, and a layout that does not depend on where the road lies in the world.

#include "emrm/sim/played.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace emrm::sim {
namespace {

// On a straight road through `origin` along `heading`: the ego at 20 m/s in its lane (1.75 m right
// of the line), a car 100 m ahead (box to box) at 10 m/s in the same lane; 12 s every 10 ms.
PlayedScenario closing_in(core::Vec2 origin, double heading) {
  const core::Vec2 along = core::Vec2::unit(heading);
  const core::Vec2 across{-along.y, along.x};
  PlayedScenario p;
  p.dt_s = 0.01;
  p.ego.body = {ActorKind::kCar, 4.5, 1.8, 1500.0, 2500.0, "ego"};
  p.others.push_back({{ActorKind::kCar, 4.0, 1.8, 1400.0, 2400.0, "lead"}, {}});
  for (int k = 0; k <= 1200; ++k) {
    const double t = 0.01 * k;
    const core::Vec2 e = origin + along * (20.0 * t) - across * 1.75;
    const core::Vec2 c = origin + along * (4.5 / 2.0 + 100.0 + 4.0 / 2.0 + 10.0 * t) - across * 1.75;
    p.ego.path.push_back({e.x, e.y, heading, 20.0});
    p.others[0].path.push_back({c.x, c.y, heading, 10.0});
  }
  return p;
}

TEST(Played, TheThreatAppearsWhenTheGapOverTheClosingSpeedFallsToTheTtc) {
  const PlayedScenario p = closing_in({0.0, 0.0}, 0.0);
  const auto onset = threat_onset(p, 2.0, 4.5, 1.8);
  ASSERT_TRUE(onset);
  // The gap 100 − 10 t falls to 20 m at t = 8 s: the first step at or after it.
  EXPECT_NEAR(static_cast<double>(onset->step) * p.dt_s, 8.0, 0.01 + 1e-9);
  EXPECT_LE(onset->ttc_s, 2.0);
  EXPECT_GT(onset->ttc_s, 2.0 - 0.011);
  EXPECT_EQ(onset->hazard, 0U);
  // A shorter TTC is reached later, never earlier: at t = 9.5 s (gap 5 m).
  const auto later = threat_onset(p, 0.5, 4.5, 1.8);
  ASSERT_TRUE(later);
  EXPECT_NEAR(static_cast<double>(later->step) * p.dt_s, 9.5, 0.01 + 1e-9);
}

TEST(Played, TheLayoutIsTheSameWhereverTheRoadLies) {
  const Road band{-3.5, 3.5, Roadside::kBarrier, Roadside::kOpen};
  const PlayedScenario here = closing_in({0.0, 0.0}, 0.0);
  const PlayedScenario there = closing_in({120.0, -45.0}, 0.7);
  const auto onset = threat_onset(here, 1.5, 4.5, 1.8);
  const auto onset_there = threat_onset(there, 1.5, 4.5, 1.8);
  ASSERT_TRUE(onset && onset_there);
  EXPECT_EQ(onset->step, onset_there->step);
  const SceneLayout a = layout_from_onset(here, {{0.0, 0.0}, 0.0, band}, onset, 4.5);
  const SceneLayout b = layout_from_onset(there, {{120.0, -45.0}, 0.7, band}, onset_there, 4.5);
  EXPECT_TRUE(a.infeasible.empty()) << a.infeasible;
  EXPECT_NEAR(a.ego_y_m, -1.75, 1e-9);
  EXPECT_NEAR(*a.ego_speed_mps, 20.0, 1e-12);
  // The front bumper at x = 0: the car's rear is the gap ahead, 15 m at TTC 1.5 s (within a step).
  EXPECT_NEAR(a.initial_distance_m, 15.0, 0.1 + 1e-9);
  EXPECT_NEAR(a.passed_x_m, a.initial_distance_m + 4.0, 1e-9);
  for (const double t : {0.0, 0.7, 1.5, 3.0, 20.0}) {
    const ActorState sa = a.actors.front().at(t);
    const ActorState sb = b.actors.front().at(t);
    EXPECT_NEAR(sa.box.center.x, sb.box.center.x, 1e-9) << t;
    EXPECT_NEAR(sa.box.center.y, sb.box.center.y, 1e-9) << t;
    EXPECT_NEAR(sa.box.heading_rad, 0.0, 1e-12);
    EXPECT_NEAR(sb.box.heading_rad, 0.0, 1e-12);
    EXPECT_NEAR(sa.box.center.x, a.initial_distance_m + 2.0 + 10.0 * t, 1e-9) << t;
  }
}

TEST(Played, WithoutAnOnsetOrTurningTheCellIsInfeasible) {
  const Road band{-3.5, 3.5, Roadside::kBarrier, Roadside::kBarrier};
  PlayedScenario p = closing_in({0.0, 0.0}, 0.0);
  p.others[0].path.resize(10);  // the car is only there for 0.1 s: no onset at 1 s
  EXPECT_FALSE(threat_onset(p, 1.0, 4.5, 1.8));
  const SceneLayout none = layout_from_onset(p, {{0.0, 0.0}, 0.0, band}, std::nullopt, 4.5, "no threat");
  EXPECT_EQ(none.infeasible, "no threat");
  const PlayedScenario q = closing_in({0.0, 0.0}, 0.0);
  const SceneLayout askew = layout_from_onset(q, {{0.0, 0.0}, 0.1, band}, threat_onset(q, 1.0, 4.5, 1.8), 4.5);
  EXPECT_NE(askew.infeasible.find("off the road"), std::string::npos) << askew.infeasible;
}

}  // namespace
}  // namespace emrm::sim
