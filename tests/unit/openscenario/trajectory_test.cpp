// FollowTrajectoryAction: a timed polyline and a clothoid against their closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "emrm/openscenario/reader.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

using namespace test;

std::string follow(const std::string& shape, const std::string& time_reference) {
  return fmt::format(R"(<PrivateAction><RoutingAction><FollowTrajectoryAction>
      <TrajectoryRef><Trajectory name="path" closed="false"><Shape>{}</Shape></Trajectory></TrajectoryRef>
      <TimeReference>{}</TimeReference><TrajectoryFollowingMode followingMode="position"/>
    </FollowTrajectoryAction></RoutingAction></PrivateAction>)",
                     shape, time_reference);
}

constexpr const char* kAbsoluteTiming = R"(<Timing domainAbsoluteRelative="absolute" scale="1" offset="0"/>)";

Trajectories play_follow(const std::string& name, const std::string& action, double duration) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 0);
  parts.acts = act("Ego", event("follow", action, trigger("StartTrigger", time_condition(0.0, "greaterOrEqual"))));
  return play(load_openscenario(write_scenario(name, parts)), {.dt_s = 0.01, .duration_s = duration});
}

TEST(FollowTrajectory, ATimedPolylineIsAtItsInterpolatedVertexAtEachSample) {
  // (0,0) at 0 s, (20,0) at 2 s, (20,20) at 4 s: 10 m/s along x, then along y.
  const std::string shape = "<Polyline><Vertex time=\"0\">" + world_position(0, 0, 0) + "</Vertex><Vertex time=\"2\">" +
                            world_position(20, 0, 0) + "</Vertex><Vertex time=\"4\">" + world_position(20, 20, 0) +
                            "</Vertex></Polyline>";
  const auto played = play_follow("polyline", follow(shape, kAbsoluteTiming), 4.0);
  for (const Sample& s : played.at("Ego")) {
    const double t = s.t_s;
    const double x = t <= 2.0 ? 10.0 * t : 20.0;
    const double y = t <= 2.0 ? 0.0 : 10.0 * (t - 2.0);
    EXPECT_NEAR(s.x_m, x, 1e-9) << "t = " << t;
    EXPECT_NEAR(s.y_m, y, 1e-9) << "t = " << t;
    if (t > 0.0 && std::fabs(t - 2.0) > 0.015) {
      EXPECT_NEAR(s.speed_mps, 10.0, 1e-6) << "t = " << t;
      EXPECT_NEAR(s.heading_rad, t < 2.0 ? 0.0 : std::numbers::pi / 2, 1e-12) << "t = " << t;
    }
  }
}

// The clothoid's pose by its definition: heading h0 + k s + k' s²/2, position the integral of its
// direction (midpoint rule, fine enough for 1e-7 m here).
std::array<double, 3> clothoid_pose(double k, double dk, double s) {
  const int n = 200000;
  double x = 0.0, y = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = (i + 0.5) * s / n;
    const double h = k * u + dk * u * u / 2.0;
    x += std::cos(h) * s / n;
    y += std::sin(h) * s / n;
  }
  return {x, y, k * s + dk * s * s / 2.0};
}

TEST(FollowTrajectory, AClothoidIsFollowedAtTheSpeedItsTimesGive) {
  // 50 m from 0 s to 5 s: s = 10 t.
  const std::string shape = R"(<Clothoid curvature="0.01" curvaturePrime="0.001" length="50" startTime="0"
      stopTime="5">)" + world_position(0, 0, 0) +
                            "</Clothoid>";
  const auto played = play_follow("clothoid", follow(shape, kAbsoluteTiming), 5.0);
  for (const Sample& s : played.at("Ego")) {
    if (std::fmod(s.t_s + 1e-9, 0.5) > 1e-6) continue;  // every half second
    const auto pose = clothoid_pose(0.01, 0.001, 10.0 * s.t_s);
    EXPECT_NEAR(s.x_m, pose[0], 1e-6) << "t = " << s.t_s;
    EXPECT_NEAR(s.y_m, pose[1], 1e-6) << "t = " << s.t_s;
    EXPECT_NEAR(s.heading_rad, std::remainder(pose[2], 2 * std::numbers::pi), 1e-9) << "t = " << s.t_s;
    if (s.t_s > 0.0) {
      EXPECT_NEAR(s.speed_mps, 10.0, 1e-6);
    }
  }
}

TEST(FollowTrajectory, WithoutTimingTheEntityKeepsItsSpeedAlongThePath) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 5);
  const std::string shape = "<Polyline><Vertex>" + world_position(0, 0, 0) + "</Vertex><Vertex>" +
                            world_position(10, 0, 0) + "</Vertex><Vertex>" + world_position(10, 10, 0) +
                            "</Vertex></Polyline>";
  parts.acts = act(
      "Ego", event("follow", follow(shape, "<None/>"), trigger("StartTrigger", time_condition(0.0, "greaterOrEqual"))));
  const auto played = play(load_openscenario(write_scenario("untimed", parts)), {.dt_s = 0.01, .duration_s = 3.0});
  // 5 m/s: 10 m along x in 2 s, then along y; after the path's 20 m (4 s) it would go on straight.
  for (const Sample& s : played.at("Ego")) {
    const double d = 5.0 * s.t_s;
    EXPECT_NEAR(s.x_m, std::min(d, 10.0), 1e-9) << "t = " << s.t_s;
    EXPECT_NEAR(s.y_m, std::max(0.0, d - 10.0), 1e-9) << "t = " << s.t_s;
    EXPECT_DOUBLE_EQ(s.speed_mps, 5.0);
  }
}

}  // namespace
}  // namespace emrm::openscenario
