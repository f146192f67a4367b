#include "emrm/core/config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "emrm/core/yaml.hpp"
#include "input_error.hpp"

namespace emrm::core {
namespace config_test {

using ::testing::HasSubstr;

std::vector<std::string> colours() { return {"red", "green"}; }

// A toy configuration: a nested part, a list of parts and a rule across fields.
struct Wheel {
  double radius_m = 0.3;
  int spokes = 5;
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, radius_m, positive);
    EMRM_FIELD(a, spokes, at_least(3, "spoke"));
  }
};

struct Bike {
  std::string colour = "red";
  double min_speed_mps = 1.0;
  double max_speed_mps = 10.0;
  double share = 0.5;
  double tilt_rad = 0.1;
  Wheel front;
  std::vector<Wheel> spares;
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, colour, one_of(colours, "colour"));
    EMRM_FIELD(a, min_speed_mps, non_negative);
    EMRM_FIELD(a, max_speed_mps, positive);
    a.ensure(min_speed_mps <= max_speed_mps, "min_speed_mps", "expected at most max_speed_mps ({} m/s), got {} m/s",
             max_speed_mps, min_speed_mps);
    EMRM_FIELD(a, share, probability, within(0.0, 0.9));
    EMRM_FIELD(a, tilt_rad, open_interval(-1.0, 1.0, "(-1, 1)"));
    EMRM_FIELD(a, front);
    EMRM_FIELD(a, spares);
    a.ensure(front.radius_m < 1.0, "front.radius_m", "expected a wheel smaller than {} m", 1.0);
  }
};

ConfigError error_of(const Bike& bike) {
  try {
    validate_fields("bike", bike);
  } catch (const ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a ConfigError";
  return ConfigError("none", {}, "none");
}

TEST(Validator, AcceptsTheDefaults) { EXPECT_NO_THROW(validate_fields("bike", Bike{})); }

TEST(Validator, NamesTheSubjectThePathAndTheRule) {
  Bike bike;
  bike.max_speed_mps = -1;
  const ConfigError e = error_of(bike);
  EXPECT_EQ(e.path().str(), "max_speed_mps");
  EXPECT_EQ(e.detail(), "expected a value > 0, got -1");
  EXPECT_EQ(e.message(), "bike: max_speed_mps: expected a value > 0, got -1");
  EXPECT_STREQ(e.what(), "error: bike: max_speed_mps: expected a value > 0, got -1");
  EXPECT_TRUE(e.where().file.empty());
}

TEST(Validator, EachConstraintSaysWhatItExpected) {
  const auto detail = [](auto edit) {
    Bike bike;
    edit(bike);
    return error_of(bike).detail();
  };
  EXPECT_EQ(detail([](Bike& b) { b.min_speed_mps = -0.5; }), "expected a value >= 0, got -0.5");
  EXPECT_EQ(detail([](Bike& b) { b.share = 0; }), "expected a probability in (0, 1], got 0");
  EXPECT_EQ(detail([](Bike& b) { b.share = 0.95; }),
            "expected a value in [0, 0.9], got 0.95");  // the second one
  EXPECT_EQ(detail([](Bike& b) { b.tilt_rad = 1; }), "expected a value in (-1, 1), got 1");
  EXPECT_EQ(detail([](Bike& b) { b.front.spokes = 2; }), "expected at least 3 spoke, got 2");
  EXPECT_EQ(detail([](Bike& b) { b.colour = "blue"; }), "unknown colour 'blue'; expected one of: red, green");
  EXPECT_EQ(detail([](Bike& b) { b.min_speed_mps = 11; }), "expected at most max_speed_mps (10 m/s), got 11 m/s");
}

TEST(Validator, NanBreaksEveryNumericConstraint) {
  Bike bike;
  bike.front.radius_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of(bike).path().str(), "front.radius_m");
}

TEST(Validator, PathsGoThroughNestedStructsListsAndDottedRules) {
  Bike bike;
  bike.front.radius_m = 0;
  EXPECT_EQ(error_of(bike).path().str(), "front.radius_m");
  bike = Bike{};
  bike.spares = {Wheel{}, Wheel{}, Wheel{}};
  bike.spares[2].spokes = 1;
  EXPECT_EQ(error_of(bike).path().str(), "spares[2].spokes");
  bike = Bike{};
  bike.front.radius_m = 1.5;
  const ConfigError e = error_of(bike);
  EXPECT_EQ(e.path().str(), "front.radius_m");
  EXPECT_EQ(e.detail(), "expected a wheel smaller than 1 m");
}

TEST(Validator, ReportsTheFirstFailureInSerializeOrder) {
  Bike bike;
  bike.tilt_rad = 5;
  bike.min_speed_mps = -1;
  EXPECT_EQ(error_of(bike).path().str(), "min_speed_mps");
}

TEST(Validator, HandWrittenChecksUseScopes) {
  Validator v("campaign");
  const Validator::Scope grids(v, "grids");
  const Validator::Scope second(v, std::size_t{1});
  try {
    v.fail("name", "a grid name must not be empty");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.message(), "campaign: grids[1].name: a grid name must not be empty");
  }
}

TEST(FormatMessage, FillsArgumentsOfEveryKindAsFmtDoes) {
  EXPECT_EQ(format_message("{} {} {} {:g} {}", {0.1, -3, std::size_t{7}, 0.25, "x"}), "0.1 -3 7 0.25 x");
  EXPECT_EQ(format_message("{:.9g}", {1.0 / 3}), "0.333333333");
}

// ---- readers and writers ignore constraints; node_at finds the field in a file --------------------

TEST(YamlArchives, ReadAndWriteFieldsWithConstraintsAsPlainFields) {
  Bike bike;
  read_yaml(YamlNode::parse("max_speed_mps: -2\nfront: {spokes: 1}\n", "bike.yaml"),
            bike);  // not checked here
  EXPECT_EQ(bike.max_speed_mps, -2.0);
  EXPECT_EQ(bike.front.spokes, 1);
  Bike written;
  read_yaml(YamlNode::parse(to_yaml_text(write_yaml(bike)), "saved.yaml"), written);
  EXPECT_EQ(written.max_speed_mps, -2.0);
  EXPECT_EQ(written.front.spokes, 1);
}

TEST(NodeAt, IsTheFieldsOwnNodeOrTheNearestEnclosingOne) {
  const std::string text = "front:\n  spokes: 1\nspares:\n  - radius_m: 0.2\n  - spokes: 2\n";
  const YamlNode root = YamlNode::parse(text, "bike.yaml");
  const auto at = [&](FieldPath path) {
    const SourceLocation where = node_at(root, path).location();
    return std::to_string(where.line) + ":" + std::to_string(where.column);
  };
  EXPECT_EQ(at({{std::string("front"), std::string("spokes")}}), "2:11");
  EXPECT_EQ(at({{std::string("front"), std::string("radius_m")}}), "2:3");  // the default: at the mapping
  EXPECT_EQ(at({{std::string("spares"), std::size_t{1}, std::string("spokes")}}), "5:13");
  EXPECT_EQ(at({{std::string("spares"), std::size_t{7}}}), "4:3");  // no such element: the list
  EXPECT_EQ(at({{std::string("colour")}}), "1:1");                  // not in the file: the root
}

TEST(FailAt, ReportsTheDetailAtTheFieldWithOrWithoutThePath) {
  const std::string text = "front:\n  spokes: 1\n";
  const YamlNode root = YamlNode::parse(text, "bike.yaml");
  Bike bike;
  read_yaml(root, bike);
  try {
    validate_fields("bike", bike);
    FAIL();
  } catch (const ConfigError& e) {
    const InputError with = emrm::testing::input_error_of([&] { fail_at(root, e, true); }, text);
    EXPECT_STREQ(with.what(), "bike.yaml:2:11: error: front.spokes: expected at least 3 spoke, got 1");
    const InputError without = emrm::testing::input_error_of([&] { fail_at(root, e, false); }, text);
    EXPECT_STREQ(without.what(), "bike.yaml:2:11: error: expected at least 3 spoke, got 1");
  }
}

}  // namespace config_test
}  // namespace emrm::core
