// Triggers fire at the step their condition first holds on the states at its start, and their
// event's action shows in the next sample (esmini's order: docs/import.md, "The player's step").

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "emrm/openscenario/reader.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

using namespace test;

// esmini's rules: lessThan holds below the threshold by more than 1e-6, greaterThan above it.
constexpr double kSlack = 1e-6;

// Ego from the origin along x at 10 m/s; Lead at `lead_x` at `lead_v`. The event stops the ego
// (speed 0 at once) when `start_trigger` fires.
Trajectories play_stop_on(const std::string& name, const std::string& start_trigger, double lead_x, double lead_v,
                          const std::string& extra_events = "") {
  XoscParts parts;
  parts.entities = vehicle("Ego") + vehicle("Lead");
  parts.init = init_at("Ego", 0, 0, 0, 10) + init_at("Lead", lead_x, 0, 0, lead_v);
  parts.acts = act("Ego", event("stop", speed("0"), start_trigger) + extra_events);
  return play(load_openscenario(write_scenario(name, parts)), {.dt_s = 0.01, .duration_s = 12.0});
}

// The index of the first sample at which `holds` is true of the states, and checks that the
// ego's speed is 10 up to the next sample and 0 from it on: the trigger evaluated those states.
std::size_t expect_fired_at_first(const Trajectories& played, const std::function<bool(std::size_t)>& holds) {
  const auto& ego = played.at("Ego");
  std::size_t first = ego.size();
  for (std::size_t i = 0; i < ego.size(); ++i)
    if (holds(i)) {
      first = i;
      break;
    }
  EXPECT_LT(first + 1, ego.size()) << "the condition never held";
  if (first + 1 >= ego.size()) return first;
  for (std::size_t i = 0; i <= first; ++i) EXPECT_DOUBLE_EQ(ego[i].speed_mps, 10.0) << "t = " << ego[i].t_s;
  for (std::size_t i = first + 1; i < ego.size(); ++i) EXPECT_DOUBLE_EQ(ego[i].speed_mps, 0.0) << "t = " << ego[i].t_s;
  return first;
}

TEST(Triggers, SimulationTimeFiresAtTheFirstStepPastItsValue) {
  const auto played = play_stop_on("time", trigger("StartTrigger", time_condition(2.0)), 1000, 0);
  const auto& ego = played.at("Ego");
  const std::size_t i = expect_fired_at_first(played, [&](std::size_t k) { return ego[k].t_s > 2.0 + kSlack; });
  EXPECT_NEAR(ego[i].t_s, 2.0, 0.01 + 1e-9);
}

TEST(Triggers, TimeToCollisionWithAStandingEntity) {
  // Centre to centre 100 - 10 t at 10 m/s: TTC < 3 s from t = 7 s.
  const auto played = play_stop_on(
      "ttc",
      trigger("StartTrigger",
              entity_condition("Ego", R"(<TimeToCollisionCondition value="3" freespace="false" rule="lessThan"
                 relativeDistanceType="euclidianDistance" coordinateSystem="entity"><TimeToCollisionConditionTarget>
                 <EntityRef entityRef="Lead"/></TimeToCollisionConditionTarget></TimeToCollisionCondition>)")),
      100, 0);
  const auto& ego = played.at("Ego");
  const std::size_t i =
      expect_fired_at_first(played, [&](std::size_t k) { return (100 - ego[k].x_m) / 10 < 3 - kSlack; });
  EXPECT_NEAR(ego[i].t_s, 7.0, 0.01 + 1e-9);
}

TEST(Triggers, FreespaceTimeToCollisionMeasuresBetweenTheBoxes) {
  // Boxes 4 m long: the gap is the centre distance less 4 m; TTC < 3 s from t = 6.6 s.
  const auto played = play_stop_on(
      "ttc_freespace",
      trigger("StartTrigger",
              entity_condition("Ego", R"(<TimeToCollisionCondition value="3" freespace="true" rule="lessThan"
                 relativeDistanceType="longitudinal" coordinateSystem="entity"><TimeToCollisionConditionTarget>
                 <EntityRef entityRef="Lead"/></TimeToCollisionConditionTarget></TimeToCollisionCondition>)")),
      100, 0);
  const auto& ego = played.at("Ego");
  const std::size_t i =
      expect_fired_at_first(played, [&](std::size_t k) { return (96 - ego[k].x_m) / 10 < 3 - kSlack; });
  EXPECT_NEAR(ego[i].t_s, 6.6, 0.01 + 1e-9);
}

TEST(Triggers, TimeHeadwayToAMovingLead) {
  // Lead 50 m ahead at 5 m/s: distance 50 - 5 t, headway (50 - 5 t) / 10 < 2 s from t = 6 s.
  const auto played = play_stop_on(
      "headway", trigger("StartTrigger", entity_condition("Ego", R"(<TimeHeadwayCondition entityRef="Lead" value="2"
                 freespace="false" rule="lessThan" coordinateSystem="entity" relativeDistanceType="longitudinal"/>)")),
      50, 5);
  const auto& ego = played.at("Ego");
  const auto& lead = played.at("Lead");
  const std::size_t i =
      expect_fired_at_first(played, [&](std::size_t k) { return (lead[k].x_m - ego[k].x_m) / 10 < 2 - kSlack; });
  EXPECT_NEAR(ego[i].t_s, 6.0, 0.01 + 1e-9);
}

TEST(Triggers, RelativeDistance) {
  // 50 - 5 t < 30 m from t = 4 s.
  const auto played = play_stop_on(
      "relative_distance",
      trigger("StartTrigger", entity_condition("Ego", R"(<RelativeDistanceCondition entityRef="Lead" value="30"
                 freespace="false" rule="lessThan" relativeDistanceType="euclidianDistance" coordinateSystem="entity"/>)")),
      50, 5);
  const auto& ego = played.at("Ego");
  const auto& lead = played.at("Lead");
  const std::size_t i =
      expect_fired_at_first(played, [&](std::size_t k) { return lead[k].x_m - ego[k].x_m < 30 - kSlack; });
  EXPECT_NEAR(ego[i].t_s, 4.0, 0.01 + 1e-9);
}

TEST(Triggers, ReachPosition) {
  // Within 1 m of x = 50 from t = 4.9 s.
  const auto played = play_stop_on(
      "reach",
      trigger("StartTrigger", entity_condition("Ego", R"(<ReachPositionCondition tolerance="1">)" +
                                                          world_position(50, 0, 0) + "</ReachPositionCondition>")),
      1000, 0);
  const auto& ego = played.at("Ego");
  const std::size_t i = expect_fired_at_first(played, [&](std::size_t k) { return std::fabs(ego[k].x_m - 50) < 1; });
  EXPECT_NEAR(ego[i].t_s, 4.9, 0.01 + 1e-9);
}

TEST(Triggers, ADelayPostponesTheFiringByItsDuration) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  parts.acts = act("Ego", event("stop", speed("0"),
                                fmt::format("<StartTrigger><ConditionGroup>{}</ConditionGroup></StartTrigger>",
                                            condition(R"(<ByValueCondition><SimulationTimeCondition value="1"
                                                rule="greaterThan"/></ByValueCondition>)",
                                                      "none", 0.5))));
  const auto played = play(load_openscenario(write_scenario("delay", parts)), {.dt_s = 0.01, .duration_s = 3.0});
  const auto& ego = played.at("Ego");
  std::size_t first_stopped = 0;
  while (first_stopped < ego.size() && ego[first_stopped].speed_mps != 0.0) ++first_stopped;
  // Without the delay the first stopped sample is at 1.02 s (fired at 1.01 s): 0.5 s later with it.
  EXPECT_NEAR(ego[first_stopped].t_s, 1.52, 0.01 + 1e-9);
}

TEST(Triggers, AStoryboardElementStateChainsTwoEvents) {
  // Event "accelerate" from 1 s: 10 -> 20 m/s linear in 1 s. Event "stop" on its end transition.
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  const std::string on_end = trigger(
      "StartTrigger", condition(R"(<ByValueCondition><StoryboardElementStateCondition storyboardElementType="event"
          storyboardElementRef="accelerate" state="endTransition"/></ByValueCondition>)"));
  parts.acts = act("Ego", event("accelerate", speed("20", "linear", "time", "1"),
                                trigger("StartTrigger", time_condition(1.0)), "parallel") +
                              event("stop", speed("0"), on_end, "parallel"));
  const auto played = play(load_openscenario(write_scenario("chain", parts)), {.dt_s = 0.01, .duration_s = 4.0});
  const auto& ego = played.at("Ego");
  // The first sample at 20 m/s is where "accelerate" ends; the next shows "stop".
  std::size_t reached = 0;
  while (reached < ego.size() && ego[reached].speed_mps != 20.0) ++reached;
  ASSERT_LT(reached + 1, ego.size());
  EXPECT_NEAR(ego[reached].t_s, 2.01, 1e-9);  // fired at 1.01 s, 100 steps of 0.01 s
  EXPECT_DOUBLE_EQ(ego[reached + 1].speed_mps, 0.0);
  for (std::size_t i = reached + 1; i < ego.size(); ++i) EXPECT_DOUBLE_EQ(ego[i].speed_mps, 0.0);
}

TEST(Triggers, TheStoryboardStopTriggerEndsThePlay) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  parts.stop = "<ConditionGroup>" + time_condition(1.5) + "</ConditionGroup>";
  const auto played = play(load_openscenario(write_scenario("stop", parts)), {.dt_s = 0.01, .duration_s = 5.0});
  // The step at the first time past 1.5 s (1.51 s) does not run: the last sample is at 1.51 s.
  EXPECT_NEAR(played.at("Ego").back().t_s, 1.51, 1e-9);
}

}  // namespace
}  // namespace emrm::openscenario

namespace emrm::openscenario {
namespace {

using namespace test;

TEST(Player, StopAtEndsThePlayAfterTheStepItReturnsTrue) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  const Scenario scenario = load_openscenario(write_scenario("stop_at", parts));
  const auto played = play(scenario, {.dt_s = 0.01, .duration_s = 9.0, .stop_at = [](double, const StepStates& states) {
                                        return states.at("Ego").x_m >= 25.0;
                                      }});
  EXPECT_NEAR(played.at("Ego").back().x_m, 25.0, 1e-9);
  EXPECT_NEAR(played.at("Ego").back().t_s, 2.5, 1e-9);
}

TEST(Triggers, RelativeSpeedIsTheSpeedMinusTheReferencedEntitys) {
  // The Lead speeds up from 10 m/s at 1 m/s² from t = 0; the Ego (10 m/s) stops when its speed
  // minus the Lead's is below -3 m/s: when the Lead is faster than 13 m/s.
  XoscParts parts;
  parts.entities = vehicle("Ego") + vehicle("Lead");
  parts.init = init_at("Ego", 0, 0, 0, 10) + init_at("Lead", 50, 0, 0, 10);
  parts.acts =
      act("Ego", event("stop", speed("0"),
                       trigger("StartTrigger", entity_condition("Ego", R"(<RelativeSpeedCondition entityRef="Lead"
                           value="-3" rule="lessThan"/>)")))) +
      act("Lead",
          event("faster", speed("20", "linear", "rate", "1"),
                trigger("StartTrigger", time_condition(0.0, "greaterOrEqual"))),
          "lead_act");
  const auto played =
      play(load_openscenario(write_scenario("relative_speed", parts)), {.dt_s = 0.01, .duration_s = 6.0});
  const auto& lead = played.at("Lead");
  const std::size_t i =
      expect_fired_at_first(played, [&](std::size_t k) { return 10.0 - lead[k].speed_mps < -3.0 - kSlack; });
  EXPECT_NEAR(lead[i].speed_mps, 13.0, 0.01 + 1e-9);
}

TEST(Triggers, AnEmptyStartTriggerStartsItsActAtOnceAnEmptyStopTriggerNever) {
  // esmini reads a StartTrigger without a ConditionGroup as true, a StopTrigger without one as
  // false: the act runs and its event stops the Ego at the first step past 1 s.
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  std::string acts = act("Ego", event("stop", speed("0"), trigger("StartTrigger", time_condition(1.0))));
  const std::string end = "</ManeuverGroup></Act>";
  acts.replace(acts.rfind(end), end.size(), "</ManeuverGroup><StartTrigger/><StopTrigger/></Act>");
  parts.acts = acts;
  const auto played =
      play(load_openscenario(write_scenario("empty_triggers", parts)), {.dt_s = 0.01, .duration_s = 2.0});
  for (const Sample& s : played.at("Ego")) EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 1.015 ? 10.0 : 0.0) << "t = " << s.t_s;
}

TEST(Triggers, AHeadwayToAnEntityBehindIsUndefined) {
  // The Lead is 5 m behind the Ego: the euclidean distance is negative (esmini signs it by ahead or
  // behind), so the headway of 0.5 s never counts as below 1 s.
  const auto played =
      play_stop_on("headway_behind",
                   trigger("StartTrigger", entity_condition("Ego", R"(<TimeHeadwayCondition entityRef="Lead" value="1"
          freespace="false" rule="lessThan" relativeDistanceType="euclidianDistance" coordinateSystem="entity"/>)")),
                   -5, 10);
  for (const Sample& s : played.at("Ego")) EXPECT_DOUBLE_EQ(s.speed_mps, 10.0) << "t = " << s.t_s;
}

TEST(Triggers, AVisibilityActionEndsInItsFirstStepAsInEsmini) {
  // Event "hide" (a VisibilityAction) starts in the evaluation at 1.01 s and ends when the actions
  // are stepped; event "stop" waits for it to complete, sees that at 1.02 s, and the Ego's speed is
  // 0 from 1.03 s (ending at its start would show at 1.02 s; esmini's light_state).
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  parts.acts =
      act("Ego",
          event("hide",
                R"(<PrivateAction><VisibilityAction graphics="false" traffic="true" sensors="false"/></PrivateAction>)",
                trigger("StartTrigger", time_condition(1.0))) +
              event("stop", speed("0"), trigger("StartTrigger", condition(R"(<ByValueCondition>
              <StoryboardElementStateCondition storyboardElementType="event" storyboardElementRef="hide"
              state="completeState"/></ByValueCondition>)"))));
  const auto played =
      play(load_openscenario(write_scenario("visibility_step", parts)), {.dt_s = 0.01, .duration_s = 2.0});
  for (const Sample& s : played.at("Ego")) EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 1.025 ? 10.0 : 0.0) << "t = " << s.t_s;
}

TEST(Triggers, ACollisionIsTheBoundingBoxesOverlapping) {
  // 4 m boxes centred on the reference points; the Lead stands at 20.05 m: they overlap once the
  // Ego is at 16.05 m or beyond. By entity and by type alike.
  for (const char* target : {R"(<EntityRef entityRef="Lead"/>)", R"(<ByType type="vehicle"/>)"}) {
    const auto played = play_stop_on(
        "collision",
        trigger("StartTrigger",
                entity_condition("Ego", fmt::format("<CollisionCondition>{}</CollisionCondition>", target))),
        20.05, 0);
    const auto& ego = played.at("Ego");
    const std::size_t i = expect_fired_at_first(played, [&](std::size_t k) { return ego[k].x_m >= 16.05; });
    EXPECT_NEAR(ego[i].t_s, 1.61, 1e-9) << target;
  }
}

TEST(Triggers, AParameterActionSetsWhatAParameterConditionCompares) {
  // Gap starts at 5; at t > 1 a SetAction makes it 11, at t > 2 a ModifyAction doubles it. As in
  // esmini the value is set when the action starts, so a condition evaluated after it in the same
  // pass (later in the document) sees it: "Gap > 10" holds at 1.01 s, "Gap == 22" at 2.01 s.
  XoscParts parts;
  parts.parameters = R"(<ParameterDeclaration name="Gap" parameterType="double" value="5"/>)";
  parts.entities = vehicle("Ego") + vehicle("Lead");
  parts.init = init_at("Ego", 0, 0, 0, 10) + init_at("Lead", 0, 10, 0, 10);
  const auto global = [](const std::string& inner) {
    return fmt::format(R"(<GlobalAction><ParameterAction parameterRef="Gap">{}</ParameterAction></GlobalAction>)",
                       inner);
  };
  const auto parameter_is = [](const std::string& rule, const std::string& value) {
    return trigger("StartTrigger",
                   condition(fmt::format(R"(<ByValueCondition><ParameterCondition parameterRef="Gap" value="{}"
                       rule="{}"/></ByValueCondition>)",
                                         value, rule)));
  };
  parts.acts =
      act("Ego", event("set", global(R"(<SetAction value="11"/>)"), trigger("StartTrigger", time_condition(1.0))) +
                     event("stop_ego", speed("0"), parameter_is("greaterThan", "10"))) +
      act("Lead",
          event("double", global(R"(<ModifyAction><Rule><MultiplyByValue value="2"/></Rule></ModifyAction>)"),
                trigger("StartTrigger", time_condition(2.0))) +
              event("stop_lead", speed("0"), parameter_is("equalTo", "22")),
          "lead_act");
  const auto played = play(load_openscenario(write_scenario("parameters", parts)), {.dt_s = 0.01, .duration_s = 3.0});
  for (const Sample& s : played.at("Ego")) EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 1.015 ? 10.0 : 0.0) << "t = " << s.t_s;
  for (const Sample& s : played.at("Lead"))
    EXPECT_DOUBLE_EQ(s.speed_mps, s.t_s < 2.015 ? 10.0 : 0.0) << "t = " << s.t_s;
}

}  // namespace
}  // namespace emrm::openscenario
