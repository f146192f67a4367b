// Parameters, `$name` references and `${...}` expressions (openscenario/parameters.hpp).

#include "emrm/openscenario/parameters.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "emrm/openscenario/reader.hpp"
#include "input_error.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

double eval(const std::string& text, const ParameterScope& scope = ParameterScope{}) {
  return evaluate_expression(text, scope, {"f.xosc", 3, 10});
}

TEST(OpenScenarioExpression, ArithmeticFollowsThePrecedenceOfTheStandard) {
  EXPECT_DOUBLE_EQ(eval("1 + 2 * 3"), 7.0);
  EXPECT_DOUBLE_EQ(eval("(1 + 2) * 3"), 9.0);
  EXPECT_DOUBLE_EQ(eval("2 + 3 * 4 - 8 / 2"), 10.0);
  EXPECT_DOUBLE_EQ(eval("7 % 3"), 1.0);
  EXPECT_DOUBLE_EQ(eval("-2 * -3"), 6.0);
  EXPECT_DOUBLE_EQ(eval("- (1 + 2)"), -3.0);
  EXPECT_DOUBLE_EQ(eval("10 - 4 - 3"), 3.0);  // left-associative
  EXPECT_DOUBLE_EQ(eval("12 / 2 / 3"), 2.0);
  EXPECT_DOUBLE_EQ(eval("1.5e1 + .5"), 15.5);
}

TEST(OpenScenarioExpression, FunctionsAndBooleans) {
  EXPECT_DOUBLE_EQ(eval("pow(2, 10)"), 1024.0);
  EXPECT_DOUBLE_EQ(eval("round(2.5)"), 3.0);
  EXPECT_DOUBLE_EQ(eval("floor(-1.5)"), -2.0);
  EXPECT_DOUBLE_EQ(eval("ceil(1.2)"), 2.0);
  EXPECT_DOUBLE_EQ(eval("sqrt(16) + 1"), 5.0);
  EXPECT_DOUBLE_EQ(eval("1 < 2 and not (3 == 4)"), 1.0);
  EXPECT_DOUBLE_EQ(eval("not 1 == 1"), 0.0);  // not binds looser than a comparison
  EXPECT_DOUBLE_EQ(eval("false or 2 >= 2"), 1.0);
  EXPECT_DOUBLE_EQ(eval("true and 1 != 1"), 0.0);
  EXPECT_DOUBLE_EQ(eval("1 + 1 == 2 or 0"), 1.0);  // arithmetic before comparison before or
}

TEST(OpenScenarioExpression, ParametersAreReadByReference) {
  ParameterScope scope;
  scope.declare("speed", ParameterType::kDouble, "20", {});
  scope.declare("double_speed", ParameterType::kDouble, "${$speed * 2}", {});
  EXPECT_DOUBLE_EQ(eval("-$speed * 2", scope), -40.0);
  EXPECT_EQ(scope.find("double_speed")->value, "40");
  EXPECT_EQ(scope.resolve("$double_speed", {}), "40");
  EXPECT_EQ(scope.resolve("plain", {}), "plain");
  // 20 / 8 = 2.5 is not an int.
  ParameterScope other;
  other.declare("speed", ParameterType::kDouble, "20", {});
  const InputError e = emrm::testing::input_error_of(
      [&] {
        other.declare("lanes", ParameterType::kInt, "${$speed / 8}", {"f.xosc", 1, 1});
      },
      "int");
  EXPECT_NE(std::string(e.what()).find("expected an integer"), std::string::npos) << e.what();
}

TEST(OpenScenarioParameters, ANameDeclaredAgainTakesTheLaterDeclaration) {
  // esmini's rule: a later declaration in the same scope replaces the earlier one.
  ParameterScope scope;
  scope.declare("duration", ParameterType::kDouble, "3", {});
  scope.declare("duration", ParameterType::kDouble, "${$duration * 2}", {});
  EXPECT_EQ(scope.find("duration")->value, "6");
  EXPECT_EQ(scope.declared().size(), 1U);
}

TEST(OpenScenarioExpression, ErrorsNameTheColumnOfTheOffendingToken) {
  // The text starts at column 10: its character i is at column 10 + i.
  const auto column_of = [](const std::string& text) {
    return emrm::testing::input_error_of([&] { (void)eval(text); }, text).where().column;
  };
  EXPECT_EQ(column_of("1 + * 2"), 10 + 4);
  EXPECT_EQ(column_of("1 + $nope"), 10 + 4);
  EXPECT_EQ(column_of("2 * frobnicate(1)"), 10 + 4);
  EXPECT_EQ(column_of("(1 + 2"), 10 + 6);
  EXPECT_EQ(column_of("1 / 0"), 10 + 2);
  EXPECT_EQ(column_of("1 2"), 10 + 2);
  // Nesting deep enough to exhaust a recursive parser's stack is refused, not followed.
  EXPECT_EQ(column_of(std::string(100000, '(') + "1" + std::string(100000, ')')), 10 + 200);
  EXPECT_DOUBLE_EQ(eval(std::string(100001, '-') + "1"), -1.0);
  EXPECT_DOUBLE_EQ(eval("not not not 0"), 1.0);
  const InputError e = emrm::testing::input_error_of([&] { (void)eval("$nope"); }, "");
  EXPECT_EQ(e.where().line, 3);
  EXPECT_NE(e.message().find("unknown parameter 'nope'"), std::string::npos) << e.what();
}

TEST(OpenScenarioParameters, OverridesReplaceDefaultsAndAreListedWithTypes) {
  using namespace test;
  XoscParts parts;
  parts.parameters = R"(<ParameterDeclaration name="EgoSpeed" parameterType="double" value="10"/>
      <ParameterDeclaration name="Twice" parameterType="double" value="${$EgoSpeed * 2}"/>
      <ParameterDeclaration name="Name" parameterType="string" value="ego"/>
      <ParameterDeclaration name="On" parameterType="boolean" value="true"/>)";
  parts.entities = vehicle("Ego");
  parts.init = R"(<Private entityRef="Ego">)" + teleport(world_position(0, 0, 0)) + speed("$Twice") + "</Private>";
  const auto file = write_scenario("overrides", parts);

  const auto declared = declared_parameters(file);
  ASSERT_EQ(declared.size(), 4U);
  EXPECT_EQ(declared[0].name, "EgoSpeed");
  EXPECT_EQ(declared[0].type, ParameterType::kDouble);
  EXPECT_EQ(declared[0].default_text, "10");
  EXPECT_EQ(declared[1].value, "20");
  EXPECT_EQ(declared[3].type, ParameterType::kBoolean);

  const Scenario scenario = load_openscenario(file, {.overrides = overrides_from({{"EgoSpeed", 7.5}}), .ego = {}});
  const auto played = play(scenario, {.dt_s = 0.01, .duration_s = 0.1});
  EXPECT_DOUBLE_EQ(played.at("Ego").back().speed_mps, 15.0);  // the override reached the derived parameter

  // The same override given to play() re-reads the scenario.
  const auto replayed =
      play(load_openscenario(file), {.dt_s = 0.01, .duration_s = 0.1, .overrides = {{"EgoSpeed", "4"}}});
  EXPECT_DOUBLE_EQ(replayed.at("Ego").back().speed_mps, 8.0);

  const InputError unknown = emrm::testing::input_error_of(
      [&] {
        (void)load_openscenario(file, {.overrides = {{"Nope", "1"}}, .ego = {}});
      },
      "override");
  EXPECT_NE(unknown.message().find("'Nope'"), std::string::npos) << unknown.what();
  const InputError typed = emrm::testing::input_error_of(
      [&] {
        (void)load_openscenario(file, {.overrides = {{"On", "maybe"}}, .ego = {}});
      },
      "override");
  EXPECT_NE(typed.message().find("true or false"), std::string::npos) << typed.what();
}

TEST(OpenScenarioParameters, AnExpressionErrorInADocumentNamesItsLineAndColumn) {
  using namespace test;
  XoscParts parts;
  parts.parameters = R"(<ParameterDeclaration name="A" parameterType="double" value="${1 + * 2}"/>)";
  parts.entities = vehicle("Ego");
  const std::string text = xosc(parts);
  const auto file = write_scenario("expression_error", parts);
  const InputError e = emrm::testing::input_error_of([&] { (void)load_openscenario(file); }, text);
  // The '*' of the expression: its line and column in the text.
  const std::size_t at = text.find("* 2}");
  const std::size_t line_start = text.rfind('\n', at) + 1;
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, static_cast<int>(at - line_start) + 1) << e.what();
}

TEST(ParameterText, NumbersAndReferencesAreReadFromTheWholeText) {
  EXPECT_EQ(parse_number(" 1.5 "), 1.5);
  for (const std::string_view bad : {"", "1x", "nan", "inf", "1 2", "$A"})
    EXPECT_FALSE(parse_number(bad).has_value()) << bad;
  EXPECT_EQ(parameter_references("${$A - $B_2 * 2} $ $$C"), (std::vector<std::string_view>{"A", "B_2", "C"}));
  EXPECT_TRUE(parameter_references("3.5").empty());
  EXPECT_EQ(trim_spaces("  a b "), "a b");
}

}  // namespace
}  // namespace emrm::openscenario
