// SpeedAction shapes against their closed forms (openscenario/dynamics.hpp, the player's speed).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "emrm/openscenario/dynamics.hpp"
#include "emrm/openscenario/reader.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

using std::numbers::pi;

// The shape's closed form f on [0, T] and its integral F (the distance covered).
struct ClosedForm {
  DynamicsShape shape;
  double v0, v1, T;
  [[nodiscard]] double speed(double t) const {
    const double u = std::clamp(t / T, 0.0, 1.0), b = v1 - v0;
    switch (shape) {
      case DynamicsShape::kLinear:
        return v0 + b * u;
      case DynamicsShape::kCubic:
        return v0 + b * (3 * u * u - 2 * u * u * u);
      case DynamicsShape::kSinusoidal:
        return v0 + b * (1 - std::cos(pi * u)) / 2;
      case DynamicsShape::kStep:
        break;
    }
    return v1;
  }
  [[nodiscard]] double distance(double t) const {
    const double tc = std::clamp(t, 0.0, T), u = tc / T, b = v1 - v0;
    double d = v0 * tc;
    switch (shape) {
      case DynamicsShape::kLinear:
        d += b * T * u * u / 2;
        break;
      case DynamicsShape::kCubic:
        d += b * T * (u * u * u - u * u * u * u / 2);
        break;
      case DynamicsShape::kSinusoidal:
        d += b * (tc - T * std::sin(pi * u) / pi) / 2;
        break;
      case DynamicsShape::kStep:
        d = v1 * tc;
        break;
    }
    return d + v1 * std::max(0.0, t - T);
  }
};

TEST(TransitionShapes, ValuesAndSlopesAreTheStandardsClosedForms) {
  for (const DynamicsShape shape : {DynamicsShape::kLinear, DynamicsShape::kCubic, DynamicsShape::kSinusoidal}) {
    const Transition tr{shape, 2.0, 10.0, 4.0};
    const ClosedForm f{shape, 2.0, 10.0, 4.0};
    EXPECT_DOUBLE_EQ(tr.value(0.0), 2.0);
    EXPECT_DOUBLE_EQ(tr.value(4.0), 10.0);
    EXPECT_NEAR(tr.value(2.0), 6.0, 1e-12);  // every shape is symmetric about its middle
    for (double x = 0.0; x <= 4.0; x += 0.25) {
      EXPECT_NEAR(tr.value(x), f.speed(x), 1e-12);
      const double h = 1e-6;  // the slope is the derivative of the value
      if (x > h && x < 4.0 - h) {
        EXPECT_NEAR(tr.slope(x), (tr.value(x + h) - tr.value(x - h)) / (2 * h), 1e-6);
      }
    }
    // The peak slope of the range computed for a rate is that rate.
    const double range = range_for_peak_rate(shape, 2.0, 10.0, 3.0);
    const Transition by_rate{shape, 2.0, 10.0, range};
    EXPECT_NEAR(by_rate.slope(range / 2.0), 3.0, 1e-12);
    // The peak second derivative of the range computed for it (cubic and sinusoidal: at the ends).
    if (shape != DynamicsShape::kLinear) {
      const double r2 = range_for_peak_second_derivative(shape, 2.0, 10.0, 1.5);
      const Transition by_acc{shape, 2.0, 10.0, r2};
      EXPECT_NEAR(by_acc.slope(1e-6) / 1e-6, 1.5, 1e-4);
    }
  }
  EXPECT_TRUE((Transition{DynamicsShape::kStep, 1.0, 5.0, 3.0}.jumps()));
  EXPECT_DOUBLE_EQ((Transition{DynamicsShape::kStep, 1.0, 5.0, 3.0}.value(0.0)), 5.0);
}

// An entity at the origin heading along x at v0, then one SpeedAction at t = 0.
Trajectories play_speed(const std::string& test, const std::string& shape, const std::string& dimension, double value,
                        double v0, double v1, double duration) {
  using namespace test;
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, v0);
  parts.acts = act("Ego", event("change", speed(fmt::format("{}", v1), shape, dimension, fmt::format("{}", value)),
                                trigger("StartTrigger", time_condition(0.0, "greaterOrEqual"))));
  return play(load_openscenario(write_scenario(test, parts)), {.dt_s = 0.01, .duration_s = duration});
}

// Speeds at the samples are the closed form at their time; positions its integral, to within the
// right Riemann sum's error (the player moves by the speed at each step's end): dt |v1 - v0|.
void expect_closed_form(const Trajectories& played, const ClosedForm& f, double dt) {
  for (const Sample& s : played.at("Ego")) {
    EXPECT_NEAR(s.speed_mps, f.speed(s.t_s), 1e-9) << "t = " << s.t_s;
    EXPECT_NEAR(s.x_m, f.distance(s.t_s), dt * std::fabs(f.v1 - f.v0) + 1e-9) << "t = " << s.t_s;
    EXPECT_NEAR(s.y_m, 0.0, 1e-12);
  }
}

TEST(SpeedAction, EachShapeInTimeFollowsItsClosedForm) {
  const std::pair<const char*, DynamicsShape> shapes[] = {
      {"linear", DynamicsShape::kLinear}, {"cubic", DynamicsShape::kCubic}, {"sinusoidal", DynamicsShape::kSinusoidal}};
  for (const auto& [name, shape] : shapes) {
    SCOPED_TRACE(name);
    expect_closed_form(play_speed(std::string("time_") + name, name, "time", 4.0, 5.0, 15.0, 6.0),
                       {shape, 5.0, 15.0, 4.0}, 0.01);
    expect_closed_form(play_speed(std::string("brake_") + name, name, "time", 2.0, 20.0, 8.0, 3.0),
                       {shape, 20.0, 8.0, 2.0}, 0.01);
  }
}

TEST(SpeedAction, AStepChangesTheSpeedAtOnce) {
  const auto played = play_speed("step", "step", "time", 0.0, 5.0, 12.0, 1.0);
  expect_closed_form(played, {DynamicsShape::kStep, 5.0, 12.0, 0.0}, 0.0);
}

TEST(SpeedAction, DistanceIsCoveredOverTheDurationOfTheMeanSpeed) {
  // 60 m from 10 to 20 m/s: T = 2 d / (v0 + v1) = 4 s for every symmetric shape.
  const std::pair<const char*, DynamicsShape> shapes[] = {
      {"linear", DynamicsShape::kLinear}, {"cubic", DynamicsShape::kCubic}, {"sinusoidal", DynamicsShape::kSinusoidal}};
  for (const auto& [name, shape] : shapes) {
    SCOPED_TRACE(name);
    const auto played = play_speed(std::string("distance_") + name, name, "distance", 60.0, 10.0, 20.0, 5.0);
    expect_closed_form(played, {shape, 10.0, 20.0, 4.0}, 0.01);
    const Sample& at_end = played.at("Ego")[400];
    EXPECT_NEAR(at_end.t_s, 4.0, 1e-9);
    EXPECT_NEAR(at_end.x_m, 60.0, 0.01 * 10.0 + 1e-9);
  }
}

TEST(SpeedAction, ARateSetsThePeakAcceleration) {
  // 2 m/s² from 10 to 16 m/s: linear in 3 s, sinusoidal in pi/2 * 3 s, cubic in 1.5 * 3 s.
  expect_closed_form(play_speed("rate_linear", "linear", "rate", 2.0, 10.0, 16.0, 6.0),
                     {DynamicsShape::kLinear, 10.0, 16.0, 3.0}, 0.01);
  expect_closed_form(play_speed("rate_sinusoidal", "sinusoidal", "rate", 2.0, 10.0, 16.0, 6.0),
                     {DynamicsShape::kSinusoidal, 10.0, 16.0, pi / 2 * 3.0}, 0.01);
  expect_closed_form(play_speed("rate_cubic", "cubic", "rate", 2.0, 10.0, 16.0, 6.0),
                     {DynamicsShape::kCubic, 10.0, 16.0, 4.5}, 0.01);
}

}  // namespace
}  // namespace emrm::openscenario
