// Entities on OpenDRIVE lanes: the default controller along a lane and across a road link, a lane
// change ending on the target lane's centre, a lane offset reaching its target.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "emrm/openscenario/reader.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

using namespace test;

// A straight road along x from (x0, 0): two right lanes of 3.5 m (-1 centred at t = -1.75, -2 at
// t = -5.25) and one left lane, each linked to the lane of its id in the roads before and after.
std::string road(const std::string& id, double x0, double length, const std::string& links,
                 const std::string& shape = "<line/>") {
  const auto lane = [](int id_, const char* type) {
    return fmt::format(
        R"(<lane id="{0}" type="{1}" level="false"><link><predecessor id="{0}"/><successor id="{0}"/></link>
        <width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>)",
        id_, type);
  };
  return fmt::format(R"(<road name="r{0}" length="{1}" id="{0}" junction="-1"><link>{2}</link>
    <planView><geometry s="0" x="{3}" y="0" hdg="0" length="{1}">{7}</geometry></planView>
    <lanes><laneSection s="0"><left>{4}</left><center><lane id="0" type="none" level="false"/></center>
    <right>{5}{6}</right></laneSection></lanes></road>)",
                     id, length, links, x0, lane(1, "driving"), lane(-1, "driving"), lane(-2, "driving"), shape);
}

std::string xodr(const std::string& roads) {
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE><header revMajor="1" revMinor="7" name="test" version="1" date="2026-01-01"/>)" +
         roads + "</OpenDRIVE>\n";
}

std::filesystem::path scenario_on_roads(const std::string& name, const std::string& roads, const XoscParts& parts_in) {
  XoscParts parts = parts_in;
  parts.road_file = "roads.xodr";
  const auto file = write_scenario(name, parts);
  write_file(file.parent_path() / "roads.xodr", xodr(roads));
  return file;
}

std::string lane_position(const std::string& road_id, int lane, double s, double offset = 0.0) {
  return fmt::format(R"(<Position><LanePosition roadId="{}" laneId="{}" s="{}" offset="{}"/></Position>)", road_id,
                     lane, s, offset);
}

std::string init_on_lane(const std::string& entity, const std::string& road_id, int lane, double s, double v) {
  return fmt::format(R"(<Private entityRef="{}">{}{}</Private>)", entity, teleport(lane_position(road_id, lane, s)),
                     speed(fmt::format("{}", v)));
}

TEST(OnLanes, AnEntityKeepsItsLaneAcrossARoadLink) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", -1, 90, 10);
  const std::string roads =
      road("1", 0, 100, R"(<successor elementType="road" elementId="2" contactPoint="start"/>)") +
      road("2", 100, 100, R"(<predecessor elementType="road" elementId="1" contactPoint="end"/>)");
  const auto played =
      play(load_openscenario(scenario_on_roads("link", roads, parts)), {.dt_s = 0.01, .duration_s = 3.0});
  for (const Sample& s : played.at("Ego")) {
    EXPECT_NEAR(s.x_m, 90.0 + 10.0 * s.t_s, 1e-6) << "t = " << s.t_s;  // on road 2 past 1 s
    EXPECT_NEAR(s.y_m, -1.75, 1e-9) << "t = " << s.t_s;
    EXPECT_NEAR(s.heading_rad, 0.0, 1e-9);
  }
}

TEST(OnLanes, OnACurveTheLaneIsCoveredAtTheEntitysSpeed) {
  // An arc of radius 100 m turning left; lane -1 (t = -1.75) runs on the radius 101.75 m outside it.
  // At 10 m/s the entity covers 10 m of that circle a second (esmini: ds = distance / (1 - k t)).
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", -1, 0, 10);
  const auto played =
      play(load_openscenario(scenario_on_roads("arc", road("1", 0, 300, "", R"(<arc curvature="0.01"/>)"), parts)),
           {.dt_s = 0.01, .duration_s = 5.0});
  const double radius = 100.0 + 1.75;
  for (const Sample& s : played.at("Ego")) {
    const double angle = 10.0 * s.t_s / radius;
    EXPECT_NEAR(s.x_m, radius * std::sin(angle), 1e-6) << "t = " << s.t_s;
    EXPECT_NEAR(s.y_m, 100.0 - radius * std::cos(angle), 1e-6) << "t = " << s.t_s;
    EXPECT_NEAR(s.heading_rad, angle, 1e-9) << "t = " << s.t_s;
  }
}

TEST(OnLanes, ALaneOfTheOtherDirectionIsDrivenAgainstS) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", 1, 50, 10);
  const auto played = play(load_openscenario(scenario_on_roads("against", road("1", 0, 100, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 2.0});
  for (const Sample& s : played.at("Ego")) {
    EXPECT_NEAR(s.x_m, 50.0 - 10.0 * s.t_s, 1e-6);
    EXPECT_NEAR(s.y_m, 1.75, 1e-9);
    EXPECT_NEAR(std::fabs(s.heading_rad), std::numbers::pi, 1e-9);
  }
}

TEST(OnLanes, ALaneChangeEndsOnTheTargetLanesCentreAtTheEndOfItsDynamics) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", -1, 10, 20);
  const std::string change = R"(<PrivateAction><LateralAction><LaneChangeAction>
      <LaneChangeActionDynamics dynamicsShape="sinusoidal" value="3" dynamicsDimension="time"/>
      <LaneChangeTarget><AbsoluteTargetLane value="-2"/></LaneChangeTarget></LaneChangeAction></LateralAction></PrivateAction>)";
  parts.acts = act("Ego", event("change", change, trigger("StartTrigger", time_condition(1.0))));
  const auto played = play(load_openscenario(scenario_on_roads("lane_change", road("1", 0, 500, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 6.0});
  const auto& ego = played.at("Ego");
  // Started at the step at 1.01 s: its lateral offset is the sinusoid of the time since then.
  for (const Sample& s : ego) {
    const double tau = std::clamp(s.t_s - 1.01, 0.0, 3.0);
    const double y = -1.75 - 3.5 * (1.0 - std::cos(std::numbers::pi * tau / 3.0)) / 2.0;
    EXPECT_NEAR(s.y_m, y, 1e-9) << "t = " << s.t_s;
    if (s.t_s >= 4.01 - 1e-9) {
      EXPECT_NEAR(s.heading_rad, 0.0, 1e-12) << "t = " << s.t_s;
    }
  }
  EXPECT_NEAR(ego.back().y_m, -5.25, 1e-12);  // the target lane's centre
  // Moving sideways takes some of the step's length: behind where straight driving would be.
  EXPECT_LT(ego.back().x_m, 10.0 + 20.0 * 6.0);
  EXPECT_GT(ego.back().x_m, 10.0 + 20.0 * 6.0 - 1.0);
}

TEST(OnLanes, ALaneOffsetReachesItsTarget) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", -1, 10, 10);
  const std::string offset = R"(<PrivateAction><LateralAction><LaneOffsetAction continuous="false">
      <LaneOffsetActionDynamics dynamicsShape="cubic" maxLateralAcc="0.5"/>
      <LaneOffsetTarget><AbsoluteTargetLaneOffset value="0.75"/></LaneOffsetTarget></LaneOffsetAction></LateralAction></PrivateAction>)";
  parts.acts = act("Ego", event("offset", offset, trigger("StartTrigger", time_condition(0.0, "greaterOrEqual"))));
  const auto played = play(load_openscenario(scenario_on_roads("lane_offset", road("1", 0, 500, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 6.0});
  // Cubic over sqrt(6 * 0.75 / 0.5) = 3 s; t along the road, 0.75 m to the left of the lane centre.
  const auto& ego = played.at("Ego");
  EXPECT_NEAR(ego.back().y_m, -1.75 + 0.75, 1e-12);
  for (const Sample& s : ego) {
    EXPECT_GE(s.y_m, -1.75 - 1e-12);
    EXPECT_LE(s.y_m, -1.0 + 1e-12);
    EXPECT_NEAR(s.x_m, 10.0 + 10.0 * s.t_s, 1e-6);  // the offset does not slow it along the road
  }
}

}  // namespace
}  // namespace emrm::openscenario
