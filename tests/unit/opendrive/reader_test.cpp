// The OpenDRIVE reader refuses what it cannot read with file:line:column and what was expected:
// an unsupported geometry, a missing attribute, an unknown lane type, a link to a missing road.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>

#include "emrm/opendrive/road_network.hpp"
#include "opendrive/xodr_text.hpp"

namespace emrm::opendrive {
namespace {

using testing::geometry;
using ::testing::HasSubstr;
using testing::road;
using testing::xodr;

InputError error_of(const std::string& text) {
  try {
    (void)parse_opendrive(text, "bad.xodr");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "read without error";
  return InputError({}, "");
}

/// Line and column of the first `needle` in `text`.
std::pair<int, int> position_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  const std::size_t line_start = text.rfind('\n', at) + 1;
  return {static_cast<int>(1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n')),
          static_cast<int>(at - line_start + 1)};
}

TEST(OpenDriveReader, UnsupportedGeometryNamesTheSupportedOnes) {
  // revMinor 5: no schema, so the reader's own check speaks.
  const std::string text = xodr(road("1", 10, geometry(0, 0, 0, 0, 10, "<clothoidSpline k=\"1\"/>")), 5);
  const InputError e = error_of(text);
  EXPECT_EQ(e.where().file, "bad.xodr");
  EXPECT_EQ(std::pair(e.where().line, e.where().column), position_of(text, "<clothoidSpline"));
  EXPECT_THAT(e.message(), HasSubstr("<clothoidSpline>"));
  EXPECT_THAT(e.message(), HasSubstr("line, arc, spiral, poly3, paramPoly3"));
  // In a 1.7 file the schema refuses it first, at the same element.
  const std::string v17 = xodr(road("1", 10, geometry(0, 0, 0, 0, 10, "<clothoidSpline k=\"1\"/>")), 7);
  const InputError schema = error_of(v17);
  EXPECT_EQ(std::pair(schema.where().line, schema.where().column), position_of(v17, "<clothoidSpline"));
}

TEST(OpenDriveReader, MissingAttributeSaysWhichAndWhere) {
  std::string text = xodr(road("1", 10, geometry(0, 0, 0, 0, 10, "<arc curvature=\"0.1\"/>")), 4);
  text.replace(text.find(" curvature=\"0.1\""), 16, "");
  const InputError e = error_of(text);
  EXPECT_EQ(std::pair(e.where().line, e.where().column), position_of(text, "<arc"));
  EXPECT_THAT(e.message(), HasSubstr("<arc> needs the attribute curvature"));
}

TEST(OpenDriveReader, BadNumbersAndLaneTypesAreRefused) {
  const std::string nan_length = xodr(road("1", 10, geometry(0, 0, 0, 0, 10, "<line/>")), 5);
  std::string text = nan_length;
  text.replace(text.find("length=\"10\">"), 11, "length=\"NaN\"");
  const InputError e = error_of(text);
  EXPECT_EQ(std::pair(e.where().line, e.where().column), position_of(text, "length=\"NaN\""));
  EXPECT_THAT(e.message(), HasSubstr("expected a number"));

  std::string negative = nan_length;
  negative.replace(negative.find("length=\"10\">"), 11, "length=\"-10\"");
  EXPECT_THAT(error_of(negative).message(), HasSubstr("expected a length > 0"));

  std::string lane_type = nan_length;
  lane_type.replace(lane_type.find("type=\"driving\""), 14, "type=\"motorway\"");
  const InputError type = error_of(lane_type);
  EXPECT_EQ(std::pair(type.where().line, type.where().column), position_of(lane_type, "type=\"motorway\""));
  EXPECT_THAT(type.message(), HasSubstr("connectingRamp"));
}

TEST(OpenDriveReader, WidthsMustNotGoNegative) {
  // 1 - 0.2 ds + 0.009 ds² is positive at both ends of [0, 30] and -0.11 at ds = 11.1.
  for (const std::string& bad : {testing::width(0, 3, -0.2), testing::width(0, 1, -0.2, 0.009)}) {
    const std::string text = xodr(
        road("1", 30, geometry(0, 0, 0, 0, 30, "<line/>"), testing::section(0, "", testing::lane(-1, "driving", bad))));
    const InputError e = error_of(text);
    EXPECT_EQ(std::pair(e.where().line, e.where().column),
              position_of(text, "a=\"" + bad.substr(bad.find("a=\"") + 3, 1)));
    EXPECT_THAT(e.message(), HasSubstr("expected a width >= 0"));
  }
  // Just touching 0 inside is a lane that narrows to nothing and widens again: accepted.
  EXPECT_NO_THROW((void)parse_opendrive(
      xodr(road("1", 30, geometry(0, 0, 0, 0, 30, "<line/>"),
                testing::section(0, "", testing::lane(-1, "driving", testing::width(0, 1, -0.2, 0.01))))),
      "ok.xodr"));
}

TEST(OpenDriveReader, LinkToAMissingRoadIsAnErrorAtTheLink) {
  const std::string text =
      xodr(road("1", 10, geometry(0, 0, 0, 0, 10, "<line/>"), testing::two_lanes(),
                "<link><successor elementType=\"road\" elementId=\"7\" contactPoint=\"start\"/></link>"));
  const InputError e = error_of(text);
  EXPECT_EQ(std::pair(e.where().line, e.where().column), position_of(text, "<successor"));
  EXPECT_THAT(e.message(), HasSubstr("\"7\""));
}

TEST(OpenDriveReader, GeometryMustJoinAndMatchTheRoadLength) {
  const std::string gap =
      xodr(road("1", 20, geometry(0, 0, 0, 0, 10, "<line/>") + geometry(11, 10, 0, 0, 9, "<line/>")));
  EXPECT_THAT(error_of(gap).message(), HasSubstr("where the previous one ends"));
  const std::string short_plan = xodr(road("1", 20, geometry(0, 0, 0, 0, 10, "<line/>")));
  EXPECT_THAT(error_of(short_plan).message(), HasSubstr("ends at s="));
}

TEST(OpenDriveReader, Reads14FilesWithWhatTheyAddIgnored) {
  // In the style of a 1.4 export: a geoReference, vendor userData in a lane, an object type that
  // 1.6's schema does not list, elevation: read, and what does not place lanes ignored.
  const std::string lanes = testing::section(
      0,
      testing::lane(1, "driving",
                    testing::width(0, 3.07) + "<userData code=\"viStyleDef\"><style laneStyle=\"x\"/></userData>"),
      testing::lane(-1, "driving", testing::width(0, 3.07)));
  std::string text = xodr(road("0", 100, geometry(0, 0, 0, 0, 100, "<line/>"), lanes), 4);
  text.replace(
      text.find("</planView>"), 11,
      "</planView><elevationProfile><elevation s=\"0\" a=\"1\" b=\"0.1\" c=\"0\" d=\"0\"/></elevationProfile>");
  text.replace(text.find("</lanes>"), 8,
               "</lanes><objects><object type=\"guide-post\" id=\"0\" s=\"0\" t=\"-3.7\"/></objects><signals/>");
  text.replace(text.find("version=\"1\"/>"), 13,
               "version=\"1\"><geoReference><![CDATA[+proj=tmerc]]></geoReference></header>");
  const RoadNetwork network = parse_opendrive(text, "v14.xodr");
  const Road& r = network.roads().front();
  EXPECT_NEAR(r.lane_center_t(1, 50), 3.07 / 2, 1e-12);
  EXPECT_NEAR(network.road_to_world(r, 50, 0).y, 0.0, 1e-12);  // elevation does not move it
}

TEST(OpenDriveReader, LoadReadsAFile) { EXPECT_THROW((void)load_opendrive("/nonexistent/emrm/none.xodr"), InputError); }

}  // namespace
}  // namespace emrm::opendrive
