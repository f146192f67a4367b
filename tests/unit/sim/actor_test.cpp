// Actors' open-loop motion (sim/actor.hpp): the closed forms, and the T-junction's truck written
// as an actor, bit for bit as the scene moves it.

#include "emrm/sim/actor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace actor_test {

// Braking from the start: the distance to rest is v²/2a, reached at v/a, and the actor stays.
TEST(ActorMotion, BrakesToRestWhereTheClosedFormSays) {
  ActorMotion m{.front = {0.0, 0.0}, .direction = {0.0, -1.0}, .speed_mps = 5.0, .decel_mps2 = 4.0};
  EXPECT_DOUBLE_EQ(m.rest_time_s(), 1.25);
  EXPECT_DOUBLE_EQ(m.travelled_m(1.25), 25.0 / 8.0);
  EXPECT_DOUBLE_EQ(m.travelled_m(10.0), 25.0 / 8.0);
  EXPECT_EQ(m.speed_at_mps(2.0), 0.0);
  EXPECT_DOUBLE_EQ(m.speed_at_mps(0.5), 3.0);
  EXPECT_EQ(m.travelled_m(-1.0), 0.0);
  // The travel's slope is the speed (central difference), everywhere but at the stop.
  for (const double t : {0.1, 0.4, 0.9, 1.2}) {
    const double h = 1e-6;
    EXPECT_NEAR((m.travelled_m(t + h) - m.travelled_m(t - h)) / (2 * h), m.speed_at_mps(t), 1e-6) << t;
  }
  // An axis-aligned motion moves no other coordinate.
  EXPECT_EQ(m.front_at(1.0).x, 0.0);
}

// Cruising first, braking later: continuous travel and speed at the moment braking starts.
TEST(ActorMotion, BrakingLaterContinuesFromTheCruise) {
  ActorMotion m{
      .front = {10.0, 0.0}, .direction = {1.0, 0.0}, .speed_mps = 20.0, .decel_mps2 = 5.0, .brake_from_s = 2.0};
  EXPECT_DOUBLE_EQ(m.travelled_m(2.0), 40.0);
  EXPECT_NEAR(m.travelled_m(2.0 + 1e-9), 40.0, 1e-7);
  EXPECT_DOUBLE_EQ(m.rest_time_s(), 6.0);
  EXPECT_DOUBLE_EQ(m.travelled_m(100.0), 40.0 + 400.0 / 10.0);
  EXPECT_DOUBLE_EQ(m.speed_at_mps(4.0), 10.0);
  ActorMotion cruise = m;
  cruise.decel_mps2 = 0.0;
  EXPECT_EQ(cruise.rest_time_s(), std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(cruise.travelled_m(3.0), 60.0);
}

// A cut-in: the box translates sideways by lateral speed × duration, then holds its lane.
TEST(Actor, CutsInByItsLateralSpeedForItsDuration) {
  const Actor car{
      {ActorKind::kCar, 4.5, 1.8, 1500.0, 2500.0},
      {.front = {30.0, 3.5}, .direction = {1.0, 0.0}, .speed_mps = 15.0, .lateral_mps = -1.0, .lateral_for_s = 3.5}};
  EXPECT_DOUBLE_EQ(car.at(0.0).box.center.y, 3.5);
  EXPECT_DOUBLE_EQ(car.at(2.0).box.center.y, 1.5);
  EXPECT_DOUBLE_EQ(car.at(3.5).box.center.y, 0.0);
  EXPECT_DOUBLE_EQ(car.at(9.0).box.center.y, 0.0);
  EXPECT_DOUBLE_EQ(car.at(1.0).velocity_mps.y, -1.0);
  EXPECT_EQ(car.at(4.0).velocity_mps.y, 0.0);
  EXPECT_DOUBLE_EQ(car.at(2.0).box.center.x, 30.0 + 30.0 - 2.25);  // front 2 s on, less half its length
  EXPECT_EQ(car.at(1.0).box.heading_rad, 0.0);
}

// The T-junction's truck as the scene wrote it before it was an actor: crossing along -y from the
// side road and braking to a stop, in closed form.
ActorState crossing_truck(const SceneConfig& config, const Scene& scene, double passage_m, double t_s,
                          double* front_y_out = nullptr) {
  const TruckConfig& truck = config.truck;
  const double v = scene.hazard_speed_mps(), a = truck.decel_mps2;
  const double travel_m = a > 0.0 ? v * v / (2.0 * a) : v * scene.ttc_s();
  const double front_y0 = config.road.drivable_min_y_m() + passage_m + travel_m;
  const double t = std::max(t_s, 0.0);
  double front_y = front_y0 - v * t;
  if (a > 0.0) {
    const double moving_s = std::min(t, v / a);
    front_y = front_y0 - (v * moving_s - 0.5 * a * moving_s * moving_s);
  }
  const double speed = a > 0.0 ? std::max(v - a * t, 0.0) : v;
  if (front_y_out != nullptr) *front_y_out = front_y;
  ActorState out;
  out.box.center = {scene.initial_distance_m() + truck.width_m / 2.0, front_y + truck.length_m / 2.0};
  out.box.heading_rad = -std::numbers::pi / 2.0;
  out.box.length_m = truck.length_m;
  out.box.width_m = truck.width_m;
  out.velocity_mps = {0.0, -speed};
  return out;
}

// The scene's truck is an actor now: the same boxes and velocities as that closed form, to the bit
// (the stores of the T-junction stay byte-identical).
TEST(Actor, TheTJunctionsTruckMovesAsItDidToTheBit) {
  for (const double decel : {4.0, 0.0}) {
    SceneConfig config;
    config.truck.decel_mps2 = decel;
    for (const TJunctionCell named :
         {TJunctionCell{50.0, 1.0, 0.8, 3.0, 10.0}, TJunctionCell{72.0, 0.35, 0.3, 1.2, 0.0},
          TJunctionCell{30.0, 2.0, 1.0, 4.0, 25.0}}) {
      const Scene scene(config, named);
      EXPECT_EQ(scene.hazard().body().kind, ActorKind::kTruck);
      for (double t = -0.5; t < 6.0; t += 0.0137) {
        double front_y = 0.0;
        const ActorState want = crossing_truck(config, scene, named.passage_m, t, &front_y);
        const ActorState got = scene.hazard_at(t);
        ASSERT_EQ(got.box.center, want.box.center) << t;
        ASSERT_EQ(got.box.heading_rad, want.box.heading_rad);
        ASSERT_EQ(got.box.length_m, want.box.length_m);
        ASSERT_EQ(got.box.width_m, want.box.width_m);
        ASSERT_EQ(got.velocity_mps, want.velocity_mps) << t;
        ASSERT_EQ(std::signbit(got.velocity_mps.y), std::signbit(want.velocity_mps.y)) << t;
        ASSERT_EQ(scene.truck_front_y_at(t), front_y) << t;
      }
    }
  }
}

TEST(ActorKind, NamedOnce) {
  EXPECT_EQ(core::enum_text(ActorKind::kStaticObject), "static_object");
  EXPECT_EQ(core::enum_from_name<ActorKind>("animal"), ActorKind::kAnimal);
  EXPECT_FALSE(core::enum_from_name<ActorKind>("deer"));
}

}  // namespace actor_test
}  // namespace emrm::sim
