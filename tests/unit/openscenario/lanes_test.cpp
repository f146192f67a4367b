// Entities on OpenDRIVE lanes: the default controller along a lane and across a road link, a lane
// change ending on the target lane's centre, a lane offset reaching its target.

#include <gtest/gtest.h>

#include <array>
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

std::string follow_trajectory(const std::string& shape, const std::string& time_reference) {
  return fmt::format(R"(<PrivateAction><RoutingAction><FollowTrajectoryAction>
      <TrajectoryRef><Trajectory name="path" closed="false"><Shape>{}</Shape></Trajectory></TrajectoryRef>
      <TimeReference>{}</TimeReference><TrajectoryFollowingMode followingMode="position"/>
    </FollowTrajectoryAction></RoutingAction></PrivateAction>)",
                     shape, time_reference);
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

TEST(OnLanes, ARelativeLanePositionHeadsAsEsminisReferenceFrameSays) {
  // The Ego drives lane 1 along s (turned round by its orientation; the lane's own direction is
  // against s). `ds` counts along s and heads along s; `dsLane` counts in the Ego's lane's driving
  // direction (against s) and heads in the driving direction of the lane it lands in.
  XoscParts parts;
  parts.entities = vehicle("Ego") + vehicle("ByS") + vehicle("ByLane");
  parts.init = fmt::format(
      R"(<Private entityRef="Ego">{}{}</Private>)",
      teleport(R"(<Position><LanePosition roadId="1" laneId="1" s="50" offset="0"><Orientation type="relative"
          h="3.141592653589793"/></LanePosition></Position>)"),
      speed("10"));
  parts.init += fmt::format(
      R"(<Private entityRef="ByS">{}{}</Private>)",
      teleport(R"(<Position><RelativeLanePosition entityRef="Ego" dLane="-2" ds="-30"/></Position>)"), speed("10"));
  parts.init += fmt::format(
      R"(<Private entityRef="ByLane">{}{}</Private>)",
      teleport(R"(<Position><RelativeLanePosition entityRef="Ego" dLane="0" dsLane="20"/></Position>)"), speed("5"));
  const auto played = play(load_openscenario(scenario_on_roads("relative_lane", road("1", 0, 200, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 1.0});
  const Sample& ego = played.at("Ego").front();
  EXPECT_NEAR(ego.heading_rad, 0.0, 1e-9);
  // ds = -30 along s, dLane -2 from lane 1 (lane 0 skipped): lane -2, heading along s; it drives along s.
  const Sample& by_s = played.at("ByS").front();
  EXPECT_NEAR(by_s.x_m, 20.0, 1e-9);
  EXPECT_NEAR(by_s.y_m, -5.25, 1e-9);
  EXPECT_NEAR(by_s.heading_rad, 0.0, 1e-9);
  EXPECT_NEAR(played.at("ByS").back().x_m, 30.0, 1e-6);
  // dsLane = 20 in lane 1's driving direction (against s): s = 30, heading against s; it drives so.
  const Sample& by_lane = played.at("ByLane").front();
  EXPECT_NEAR(by_lane.x_m, 30.0, 1e-9);
  EXPECT_NEAR(by_lane.y_m, 1.75, 1e-9);
  EXPECT_NEAR(std::fabs(by_lane.heading_rad), std::numbers::pi, 1e-9);
  EXPECT_NEAR(played.at("ByLane").back().x_m, 25.0, 1e-6);
}

TEST(OnLanes, AFollowingTrajectoryStartsFromTheHeadingThePreviousOneEndedWith) {
  // An arc of 15 m at curvature 0.01 (heading 0.15 at its end), then a 5 m line relative to the
  // entity (relative orientation 0), on a road: the line goes on at 0.15 rad (esmini keeps the
  // heading relative to the road when a trajectory ends; it is not snapped to the lane's).
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", -1, 10, 10);
  const auto relative_clothoid = [](double curvature, double length) {
    return fmt::format(R"(<Clothoid curvature="{}" curvaturePrime="0" length="{}"><Position>
        <RelativeObjectPosition entityRef="Ego" dx="0" dy="0"><Orientation type="relative" h="0"/>
        </RelativeObjectPosition></Position></Clothoid>)",
                       curvature, length);
  };
  parts.acts = act("Ego", event("arc", follow_trajectory(relative_clothoid(0.01, 15), "<None/>"),
                                trigger("StartTrigger", time_condition(0.0, "greaterOrEqual"))) +
                              event("line", follow_trajectory(relative_clothoid(0.0, 5), "<None/>"),
                                    trigger("StartTrigger", condition(R"(<ByValueCondition>
        <StoryboardElementStateCondition storyboardElementType="event" storyboardElementRef="arc"
        state="completeState"/></ByValueCondition>)"))));
  const auto played = play(load_openscenario(scenario_on_roads("arc_then_line", road("1", 0, 200, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 2.5});
  // The arc's end from its start (10, -1.75) heading 0: radius 100 m, turned by 0.15 rad.
  const std::array<double, 2> arc_end{10.0 + 100.0 * std::sin(0.15), -1.75 + 100.0 * (1.0 - std::cos(0.15))};
  bool on_line = false;
  for (const Sample& s : played.at("Ego")) {
    // Along the line: on the ray from the arc's end at its end heading.
    const double dx = s.x_m - arc_end[0], dy = s.y_m - arc_end[1];
    const double along = dx * std::cos(0.15) + dy * std::sin(0.15);
    if (along < 0.5 || along > 4.5) continue;
    on_line = true;
    EXPECT_NEAR(-dx * std::sin(0.15) + dy * std::cos(0.15), 0.0, 1e-6) << "t = " << s.t_s;
    EXPECT_NEAR(s.heading_rad, 0.15, 1e-9) << "t = " << s.t_s;
  }
  EXPECT_TRUE(on_line);
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

TEST(OnLanes, EndOfRoadHoldsOnceTheEntityHasStoodAtALanesEndForItsDuration) {
  // Road 1 ends at s = 100 without a successor; the Ego (10 m/s from s = 90) passes it in the step
  // from 1.00 s (stamped 1.01 s, the time after it) and stops there. With duration 0.5 the
  // condition holds from 1.51 s; the Other then stops, seen in the sample after.
  XoscParts parts;
  parts.entities = vehicle("Ego") + vehicle("Other");
  parts.init = init_on_lane("Ego", "1", -1, 90, 10) + init_on_lane("Other", "1", 1, 90, 5);
  parts.acts =
      act("Other", event("stop", speed("0"),
                         trigger("StartTrigger", entity_condition("Ego", R"(<EndOfRoadCondition duration="0.5"/>)"))));
  const auto played = play(load_openscenario(scenario_on_roads("end_of_road", road("1", 0, 100, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 3.0});
  for (const Sample& s : played.at("Ego"))
    if (s.t_s > 1.005) {
      EXPECT_NEAR(s.x_m, 100.0, 1e-9) << "t = " << s.t_s;
    }
  for (const Sample& s : played.at("Other"))
    EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 1.515 ? 5.0 : 0.0) << "t = " << s.t_s;
}

TEST(OnLanes, LaneZeroIsAPositionOnTheCentreLane) {
  // esmini's samples name lane 0 as a point on the centre lane (t = the lane offset, 0 here).
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_on_lane("Ego", "1", 0, 50, 10);
  const auto played = play(load_openscenario(scenario_on_roads("lane_zero", road("1", 0, 100, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 1.0});
  for (const Sample& s : played.at("Ego")) {
    EXPECT_NEAR(s.x_m, 50.0 + 10.0 * s.t_s, 1e-6) << "t = " << s.t_s;
    EXPECT_NEAR(s.y_m, 0.0, 1e-9) << "t = " << s.t_s;
  }
}

TEST(OnLanes, AFreespaceRoadDistanceCountsEachBoxFromItsReferencePoint) {
  // Boxes 4 m long centred 1.4 m ahead of the reference point: the Ego's front is 3.4 m ahead of
  // it, the Lead's rear 0.6 m behind its own. 100 m apart the gap is 96 m; at 10 m/s it is below
  // 50 m from t = 4.6 s, and the Ego stops in the step after.
  const auto centred = [](const std::string& name) {
    std::string v = vehicle(name);
    v.replace(v.find(R"(<Center x="0")"), 13, R"(<Center x="1.4")");
    return v;
  };
  XoscParts parts;
  parts.entities = centred("Ego") + centred("Lead");
  parts.init = init_on_lane("Ego", "1", -1, 0, 10) + init_on_lane("Lead", "1", -1, 100, 0);
  parts.acts =
      act("Ego", event("stop", speed("0"), trigger("StartTrigger", entity_condition("Ego", R"(<RelativeDistanceCondition
                                    entityRef="Lead" value="50" freespace="true" rule="lessThan"
                                    relativeDistanceType="longitudinal" coordinateSystem="road"/>)"))));
  const auto played = play(load_openscenario(scenario_on_roads("freespace_road", road("1", 0, 200, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 6.0});
  for (const Sample& s : played.at("Ego")) EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 4.615 ? 10.0 : 0.0) << "t = " << s.t_s;
}

TEST(OnLanes, AlongRouteMeansRoadCoordinatesWithTheEuclideanDistance) {
  // OpenSCENARIO 1.0's alongRoute="true" (deprecated since 1.1, still in the schema), read as esmini does: the road's s
  // and t, combined euclidean. The Lead stands one lane over (3.5 m in t); the headway sqrt(ds² + 3.5²) / 10 is below 1
  // s once ds < 9.367 m: from t = 9.07 s (longitudinal alone would give 9.01 s).
  XoscParts parts;
  parts.entities = vehicle("Ego") + vehicle("Lead");
  parts.init = init_on_lane("Ego", "1", -1, 0, 10) + init_on_lane("Lead", "1", 1, 100, 0);
  parts.acts =
      act("Ego", event("stop", speed("0"), trigger("StartTrigger", entity_condition("Ego", R"(<TimeHeadwayCondition
                                    entityRef="Lead" value="1" freespace="false" alongRoute="true"
                                    rule="lessThan"/>)"))));
  const auto played = play(load_openscenario(scenario_on_roads("along_route", road("1", 0, 200, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 9.5});
  const double fires_s = (100.0 - std::sqrt(100.0 - 3.5 * 3.5)) / 10.0;  // 9.0633
  for (const Sample& s : played.at("Ego"))
    EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < std::ceil(fires_s * 100.0) / 100.0 + 0.005 ? 10.0 : 0.0) << "t = " << s.t_s;
}

TEST(OnLanes, OffroadHoldsOnceTheEntityHasBeenBeyondTheLanesForLongerThanItsDuration) {
  // The right lanes reach t = -7 m; the Ego drives at t = -8 m, off road from the first step
  // (stamped 0.01 s, the time after it). With duration 0.505 the condition holds from 0.52 s; the
  // Other then stops, seen in the sample after.
  XoscParts parts;
  parts.entities = vehicle("Ego") + vehicle("Other");
  parts.init = fmt::format(R"(<Private entityRef="Ego">{}{}</Private>)",
                           teleport(R"(<Position><RoadPosition roadId="1" s="10" t="-8"/></Position>)"), speed("10")) +
               init_on_lane("Other", "1", -1, 50, 5);
  parts.acts =
      act("Other", event("stop", speed("0"),
                         trigger("StartTrigger", entity_condition("Ego", R"(<OffroadCondition duration="0.505"/>)"))));
  const auto played = play(load_openscenario(scenario_on_roads("off_road", road("1", 0, 100, ""), parts)),
                           {.dt_s = 0.01, .duration_s = 1.0});
  for (const Sample& s : played.at("Other"))
    EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 0.525 ? 5.0 : 0.0) << "t = " << s.t_s;
}

}  // namespace
}  // namespace emrm::openscenario
