#include "emrm/core/yaml.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "input_error.hpp"

namespace emrm::core {
namespace yaml_test {

using ::testing::HasSubstr;

enum class Colour { kRed, kGreen };

struct Inner {
  double width_m = 1.5;
  std::vector<int> counts;
  template <class A>
  void serialize(A& a) {
    a.optional("width_m", width_m);
    a.optional("counts", counts);
  }
};

struct Outer {
  std::string name;
  bool enabled = false;
  std::optional<Colour> colour;
  Inner inner;
  SourceLocation where;
  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("name", name);
    a.optional("enabled", enabled);
    a.optional("colour", colour);
    a.optional("inner", inner);
  }
};

InputError read_error(const std::string& text) {
  return emrm::testing::input_error_of(
      [&] {
        Outer o;
        read_yaml(YamlNode::parse(text, "t.yaml"), o);
      },
      text);
}

}  // namespace yaml_test

template <>
struct EnumNames<yaml_test::Colour> {
  static constexpr std::array kNames{std::pair{yaml_test::Colour::kRed, std::string_view("red")},
                                     std::pair{yaml_test::Colour::kGreen, std::string_view("green")}};
};

namespace yaml_test {

TEST(YamlReader, FillsFieldsAndKeepsDefaults) {
  Outer o;
  read_yaml(YamlNode::parse("name: a\ncolour: green\ninner: {counts: [1, 2]}\n", "t.yaml"), o);
  EXPECT_EQ(o.name, "a");
  EXPECT_FALSE(o.enabled);
  EXPECT_EQ(o.colour, Colour::kGreen);
  EXPECT_DOUBLE_EQ(o.inner.width_m, 1.5);
  EXPECT_EQ(o.inner.counts, (std::vector<int>{1, 2}));
  EXPECT_EQ(o.where.line, 1);
}

TEST(YamlReader, WriteThenReadGivesTheSameStruct) {
  Outer o;
  o.name = "with, comma: and colon";
  o.enabled = true;
  o.colour = Colour::kRed;
  o.inner.width_m = 0.1 + 0.2;
  o.inner.counts = {-3, 7};
  const std::string text = to_yaml_text(write_yaml(o));
  Outer back;
  read_yaml(YamlNode::parse(text, "t.yaml"), back);
  EXPECT_EQ(back.name, o.name);
  EXPECT_EQ(back.enabled, o.enabled);
  EXPECT_EQ(back.colour, o.colour);
  EXPECT_EQ(back.inner.width_m, o.inner.width_m) << "doubles must survive a round trip exactly";
  EXPECT_EQ(back.inner.counts, o.inner.counts);
}

TEST(YamlReader, MissingRequiredFieldPointsAtTheMapping) {
  const auto e = read_error("enabled: true\n");
  EXPECT_EQ(e.where().line, 1);
  EXPECT_THAT(e.message(), HasSubstr("missing required field 'name'"));
}

TEST(YamlReader, UnknownFieldPointsAtTheKey) {
  const auto e = read_error("name: a\ninner:\n  widht_m: 2\n");
  EXPECT_EQ(e.where().line, 3);
  EXPECT_EQ(e.where().column, 3);
  EXPECT_THAT(e.message(),
              HasSubstr("unknown field 'widht_m' (did you mean 'width_m'?); expected one of: width_m, counts"));
  // Nothing near: no suggestion.
  EXPECT_THAT(read_error("name: a\ninner:\n  colour_of_sky: 2\n").message(),
              HasSubstr("unknown field 'colour_of_sky'; expected one of: width_m, counts"));
}

TEST(YamlReader, WrongTypesSayWhatWasExpected) {
  EXPECT_THAT(read_error("name: [a]\n").message(), HasSubstr("expected a text value, got a list"));
  EXPECT_THAT(read_error("name: a\nenabled: 3\n").message(), HasSubstr("expected true or false"));
  EXPECT_THAT(read_error("name: a\ninner: {width_m: wide}\n").message(), HasSubstr("expected a number, got 'wide'"));
  EXPECT_THAT(read_error("name: a\ninner: {counts: [1.5]}\n").message(), HasSubstr("expected an integer"));
  EXPECT_THAT(read_error("name: a\ncolour: blue\n").message(), HasSubstr("expected red or green, got 'blue'"));
  EXPECT_THAT(read_error("- a\n- b\n").message(), HasSubstr("expected a mapping"));
}

TEST(YamlReader, NonFiniteNumbersAreRejected) {
  for (const char* bad : {".nan", ".inf", "-.inf", ".NaN"})
    EXPECT_THAT(read_error(std::string("name: a\ninner: {width_m: ") + bad + "}\n").message(),
                HasSubstr("expected a finite number"))
        << bad;
}

TEST(YamlReader, IntegerOutOfRangeIsRejected) {
  EXPECT_THAT(read_error("name: a\ninner: {counts: [99999999999]}\n").message(), HasSubstr("out of range"));
}

TEST(YamlNode, DuplicateKeysAreRejected) {
  const auto e = read_error("name: a\nname: b\n");
  EXPECT_EQ(e.where().line, 2);
  EXPECT_THAT(e.message(), HasSubstr("duplicate key 'name'"));
}

TEST(YamlNode, MalformedYamlNamesLineAndColumn) {
  try {
    (void)YamlNode::parse("a: 1\nb: [1, 2\n", "bad.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "bad.yaml");
    EXPECT_GE(e.where().line, 2);
    EXPECT_THAT(std::string(e.what()), HasSubstr("bad.yaml:"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("error: malformed YAML"));
  }
}

TEST(YamlNode, UnreadableFileIsAnInputErrorNamingIt) {
  try {
    (void)YamlNode::load_file("/no/such/file.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "/no/such/file.yaml");
    EXPECT_EQ(e.message(), "the file does not exist");
  }
  try {
    (void)YamlNode::load_file(std::filesystem::temp_directory_path());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.message(), "this is a folder; expected a file");
  }
}

// The stored scene as the report shows it: emrm's own noisy numbers readable, other text kept.
TEST(ReadableYaml, WritesNumbersAsPeopleReadThemAndKeepsTheRest) {
  const std::string text =
      "actuation:\n  max_decel_mps2: 4.9500000000000002\n  brake_ramp_s: 0.25\nname: 007\nlanes: [0.30000000000000004, "
      "2]\nlabel: \"1.4100000000000001 m\"\n";
  const std::string shown = readable_yaml(text);
  EXPECT_THAT(shown, ::testing::HasSubstr("max_decel_mps2: 4.95\n"));
  EXPECT_THAT(shown, ::testing::HasSubstr("brake_ramp_s: 0.25"));
  EXPECT_THAT(shown, ::testing::HasSubstr("name: 007"));  // not the shortest form of a number: kept
  EXPECT_THAT(shown, ::testing::HasSubstr("[0.3, 2]"));
  EXPECT_THAT(shown, ::testing::HasSubstr("1.4100000000000001 m"));  // a string that holds a number: kept
  EXPECT_EQ(readable_yaml("a: [unclosed"), "a: [unclosed");          // not YAML: as it is
}

}  // namespace yaml_test
}  // namespace emrm::core
