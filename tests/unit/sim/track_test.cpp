// An actor's motion given as samples (sim/actor.hpp, Track): interpolation, rest and top speed
// against closed forms, and a cut-in whose cars move by tracks sampled from their closed-form
// motion simulating as the cut-in itself does.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "emrm/sim/actor.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/validity.hpp"

namespace emrm::sim {
namespace {

// Samples of a closed-form motion: the box's centre, heading and speed every dt over `until_s`.
std::shared_ptr<const Track> sampled(const Actor& actor, double dt_s, double until_s) {
  std::vector<Track::Sample> samples;
  for (int k = 0; k * dt_s <= until_s + 1e-9; ++k) {
    const ActorState s = actor.at(k * dt_s);
    samples.push_back({s.box.center.x, s.box.center.y, s.box.heading_rad, s.velocity_mps.norm()});
  }
  return std::make_shared<const Track>(dt_s, std::move(samples));
}

TEST(Track, AStraightLineAtOneSpeedIsExactEverywhere) {
  std::vector<Track::Sample> samples;
  for (int k = 0; k <= 100; ++k) samples.push_back({3.0 + 0.2 * k, -1.0 + 0.1 * k, std::atan2(0.1, 0.2), 0.0});
  for (auto& s : samples) s.speed_mps = std::hypot(20.0, 10.0);
  const Track track(0.01, samples);
  for (const double t : {0.0, 0.003, 0.25, 0.555, 0.999, 1.0}) {
    core::Vec2 v;
    const Track::Sample p = track.at(t, &v);
    EXPECT_NEAR(p.x_m, 3.0 + 20.0 * t, 1e-12) << t;
    EXPECT_NEAR(p.y_m, -1.0 + 10.0 * t, 1e-12) << t;
    EXPECT_NEAR(v.x, 20.0, 1e-9);
    EXPECT_NEAR(v.y, 10.0, 1e-9);
  }
  // After the last sample it goes on at the last speed along its heading; it never rests.
  core::Vec2 v;
  const Track::Sample later = track.at(3.0, &v);
  EXPECT_NEAR(later.x_m, 3.0 + 20.0 * 3.0, 1e-9);
  EXPECT_NEAR(later.y_m, -1.0 + 10.0 * 3.0, 1e-9);
  EXPECT_EQ(track.rest_time_s(), std::numeric_limits<double>::infinity());
  EXPECT_EQ(track.at(-1.0, nullptr).x_m, 3.0);  // t < 0 counts as 0
}

TEST(Track, TheHeadingTurnsTheShortWayAcrossPi) {
  const double a = std::numbers::pi - 0.05;
  const double b = -std::numbers::pi + 0.05;  // 0.1 rad further on, across ±π
  const Track track(0.1, {{0.0, 0.0, a, 1.0}, {0.0, 0.0, b, 1.0}});
  EXPECT_NEAR(track.at(0.05, nullptr).heading_rad, std::numbers::pi, 1e-12);
  // Turning 0.1 rad in 0.1 s: a 4 × 3 box's corners move at most 1 rad/s × 2.5 m (plus 0 travel).
  EXPECT_NEAR(track.top_speed_mps(4.0, 3.0), 2.5, 1e-9);
}

TEST(Track, ItRestsFromTheFirstSampleThatStandsForGood) {
  // Braking at 4 m/s² from 2 m/s: it stops at 0.5 s, 0.5 m on, and stands.
  std::vector<Track::Sample> samples;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.01 * k;
    const double tau = std::min(t, 0.5);
    samples.push_back({2.0 * tau - 2.0 * tau * tau, 0.0, 0.0, std::max(2.0 - 4.0 * t, 0.0)});
  }
  const Track track(0.01, samples);
  EXPECT_NEAR(track.rest_time_s(), 0.5, 1e-12);
  EXPECT_NEAR(track.at(5.0, nullptr).x_m, 0.5, 1e-12);
  // Between samples the path is the chord: within a·dt²/8 of the parabola.
  EXPECT_NEAR(track.at(0.125, nullptr).x_m, 2.0 * 0.125 - 2.0 * 0.125 * 0.125, 4.0 * 0.01 * 0.01 / 8.0 + 1e-12);
  EXPECT_NEAR(track.top_speed_mps(0.0, 0.0), 2.0, 0.05);
}

TEST(Track, RefusesWhatIsNoMotion) {
  EXPECT_THROW(Track(0.01, {}), std::invalid_argument);
  EXPECT_THROW(Track(0.0, {{0.0, 0.0, 0.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(Track(0.01, {{std::nan(""), 0.0, 0.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(Track(0.01, {{0.0, 0.0, 0.0, -1.0}}), std::invalid_argument);
}

TEST(Track, AnActorOnATrackIsWhereItsSamplesSay) {
  const ActorBody body{ActorKind::kCar, 4.0, 2.0, 1500.0, 2500.0};
  const Actor closed(body, {.front = {10.0, 1.0}, .direction = {1.0, 0.0}, .speed_mps = 8.0, .decel_mps2 = 3.0});
  const Actor tracked(body, {.front = {}, .direction = {1.0, 0.0}, .track = sampled(closed, 0.01, 4.0)});
  for (const double t : {0.0, 0.5, 1.37, 2.66, 3.9}) {
    EXPECT_NEAR(tracked.at(t).box.center.x, closed.at(t).box.center.x, 3.0 * 0.01 * 0.01 / 8.0 + 1e-9) << t;
    EXPECT_EQ(tracked.at(t).box.length_m, 4.0);
    const auto [low, high] = tracked.y_extent_at(t);
    EXPECT_NEAR(low, 0.0, 1e-12);
    EXPECT_NEAR(high, 2.0, 1e-12);
  }
  EXPECT_NEAR(tracked.motion().rest_time_s(), closed.motion().rest_time_s(), 0.01 + 1e-12);
}

// The cut-in family, its cars moved by tracks sampled every 10 ms from their own closed forms.
ScenarioFamilyInfo tracked_cut_in() {
  ScenarioFamilyInfo info = *find_family("cut_in");
  info.name = "toy_tracked_cut_in";
  info.layout = [layout = info.layout](const SceneConfig& config, const CellInput& cell) {
    SceneLayout out = layout(config, cell);
    for (Actor& actor : out.actors) {
      ActorMotion motion{.front = {},
                         .direction = actor.motion().direction,
                         .track = sampled(actor, 0.01, config.simulation.horizon_s + 1.0)};
      actor = Actor(actor.body(), motion);
    }
    return out;
  };
  return info;
}

TEST(Track, ACutInOnTracksEndsAsTheClosedFormsDo) {
  const FamilyRegistration toy(tracked_cut_in());
  SceneConfig closed;
  closed.family = "cut_in";
  SceneConfig tracked = closed;
  tracked.family = "toy_tracked_cut_in";
  CellOptions options;
  options.strengthen = false;
  options.strategies = {"emergency_stop"};
  // speed, TTC, mu, relative speed, lateral speed, deceleration, following car
  for (const CellInput& cell :
       {CellInput{100.0, 1.5, 1.0, 20.0, 1.0, 4.0, 0.0}, CellInput{80.0, 0.75, 1.0, 30.0, 2.0, 8.0, 1.0},
        CellInput{120.0, 1.0, 0.5, 30.0, 2.0, 8.0, 0.0}}) {
    const CellResult want = simulate_cell(closed, cell, options);
    const CellResult got = simulate_cell(tracked, cell, options);
    SCOPED_TRACE(cell_text(scenario_factors(closed), cell));
    EXPECT_EQ(got.unmitigated.loss_level, want.unmitigated.loss_level);
    EXPECT_NEAR(got.unmitigated.delta_v_mps, want.unmitigated.delta_v_mps, 0.02);
    ASSERT_EQ(got.strategies.size(), 1U);
    EXPECT_EQ(got.strategies[0].avoided, want.strategies[0].avoided);
    EXPECT_EQ(got.strategies[0].contact, want.strategies[0].contact);
    EXPECT_NEAR(got.strategies[0].impact.delta_v_mps, want.strategies[0].impact.delta_v_mps, 0.02);
  }
}

}  // namespace
}  // namespace emrm::sim
