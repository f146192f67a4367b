// Lanes across a road (ASAM OpenDRIVE 1.7 §9): borders as sums of width polynomials shifted by the
// lane offset, borders given as <border> records; road <-> world round trips on straight, arc and
// spiral roads; where a lane leads through road links and a junction.

#include "emrm/opendrive/road_network.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "opendrive/xodr_text.hpp"

namespace emrm::opendrive {
namespace {

using testing::geometry;
using testing::lane;
using testing::num;
using testing::road;
using testing::section;
using testing::width;
using testing::xodr;

// Lane offset 0.2 + 0.01 ds; left: 1 (3 + 0.02 ds), 2 (sidewalk 2); right: -1 (3.5), -2 (shoulder
// 1 + 0.001 ds²); a second section at s = 60 whose widths restart at its own start (+ sOffset 10).
std::string lanes_text() {
  return "<laneOffset s=\"0\" a=\"0.2\" b=\"0.01\" c=\"0\" d=\"0\"/>\n" +
         section(0, lane(2, "sidewalk", width(0, 2)) + lane(1, "driving", width(0, 3, 0.02)),
                 lane(-1, "driving", width(0, 3.5)) + lane(-2, "shoulder", width(0, 1, 0, 0.001))) +
         section(60, lane(1, "driving", width(0, 3) + width(10, 4)), lane(-1, "driving", width(0, 3.5)));
}

TEST(OpenDriveLanes, BordersAreSumsOfWidthsShiftedByTheLaneOffset) {
  const RoadNetwork network =
      parse_opendrive(xodr(road("1", 100, geometry(0, 0, 0, 0, 100, "<line/>"), lanes_text())), "l.xodr");
  const Road& r = network.roads().front();
  for (const double s : {0.0, 25.0, 59.9}) {
    const double offset = 0.2 + 0.01 * s;
    const double w1 = 3 + 0.02 * s;
    const double w2 = 2;
    const double wm1 = 3.5;
    const double wm2 = 1 + 0.001 * s * s;
    EXPECT_DOUBLE_EQ(r.lane_offset(s), offset);
    EXPECT_EQ(r.lane_ids(s), (std::vector<int>{2, 1, 0, -1, -2}));
    EXPECT_NEAR(r.lane_borders(0, s).first, offset, 1e-12);
    EXPECT_NEAR(r.lane_borders(0, s).second, offset, 1e-12);
    EXPECT_NEAR(r.lane_borders(1, s).first, offset, 1e-12);
    EXPECT_NEAR(r.lane_borders(2, s).second, offset + w1 + w2, 1e-12);
    EXPECT_NEAR(r.lane_borders(-2, s).second, offset - wm1 - wm2, 1e-12);
    EXPECT_NEAR(r.lane_width(-2, s), wm2, 1e-12);
    EXPECT_NEAR(r.lane_center_t(1, s), offset + w1 / 2, 1e-12);
    EXPECT_NEAR(r.lane_center_t(-1, s), offset - wm1 / 2, 1e-12);
    EXPECT_EQ(r.lane_type(2, s), LaneType::kSidewalk);
    EXPECT_EQ(r.lane_type(-2, s), LaneType::kShoulder);
    // Each lane holds its own centre, and nothing lies beyond the outermost border.
    for (const int id : r.lane_ids(s))
      if (id != 0) {
        EXPECT_EQ(r.lane_at(s, r.lane_center_t(id, s)), id);
      }
    EXPECT_FALSE(r.lane_at(s, offset + w1 + w2 + 0.01).has_value());
  }
  // The second section: its widths count from its start, the later record from sOffset 10.
  EXPECT_EQ(r.lane_ids(70), (std::vector<int>{1, 0, -1}));
  EXPECT_NEAR(r.lane_width(1, 65), 3, 1e-12);
  EXPECT_NEAR(r.lane_width(1, 75), 4, 1e-12);
  EXPECT_THROW((void)r.lane_borders(-2, 70), std::out_of_range);
}

TEST(OpenDriveLanes, LanesContinueIntoTheNextSection) {
  const RoadNetwork network =
      parse_opendrive(xodr(road("1", 100, geometry(0, 0, 0, 0, 100, "<line/>"), lanes_text())), "n.xodr");
  const Road& r = network.roads().front();
  // Unlinked lanes continue by their id where the next section has it; lane -2 ends at s = 60.
  EXPECT_EQ(r.lane_in_next_section(1, 10, Travel::kAlongS), 1);
  EXPECT_EQ(r.lane_in_next_section(-1, 59.9, Travel::kAlongS), -1);
  EXPECT_FALSE(r.lane_in_next_section(-2, 10, Travel::kAlongS).has_value());
  EXPECT_FALSE(r.lane_in_next_section(1, 70, Travel::kAlongS).has_value());  // the last section
  EXPECT_EQ(r.lane_in_next_section(1, 70, Travel::kAgainstS), 1);
  EXPECT_FALSE(r.lane_in_next_section(1, 10, Travel::kAgainstS).has_value());
  // A link wins over the id: lane -1 of the first section continues as -2 of the second.
  const std::string linked = section(0, "", lane(-1, "driving", "<link><successor id=\"-2\"/></link>" + width(0, 3))) +
                             section(50, "", lane(-1, "shoulder", width(0, 1)) + lane(-2, "driving", width(0, 3)));
  const RoadNetwork second =
      parse_opendrive(xodr(road("1", 100, geometry(0, 0, 0, 0, 100, "<line/>"), linked)), "k.xodr");
  EXPECT_EQ(second.roads().front().lane_in_next_section(-1, 0, Travel::kAlongS), -2);
}

TEST(OpenDriveLanes, BorderRecordsGiveTheSameLanesAsWidths) {
  // Lane 1: width 3 + 0.02 ds; lane 2 by its outer border 5 + 0.02 ds (its width 2).
  const std::string lanes = section(0,
                                    lane(2, "border", "<border sOffset=\"0\" a=\"5\" b=\"0.02\" c=\"0\" d=\"0\"/>") +
                                        lane(1, "driving", width(0, 3, 0.02)),
                                    lane(-1, "driving", width(0, 3.5)));
  const RoadNetwork network =
      parse_opendrive(xodr(road("1", 50, geometry(0, 0, 0, 0, 50, "<line/>"), lanes)), "b.xodr");
  const Road& r = network.roads().front();
  for (const double s : {0.0, 30.0}) {
    EXPECT_NEAR(r.lane_borders(2, s).second, 5 + 0.02 * s, 1e-12);
    EXPECT_NEAR(r.lane_width(2, s), 2, 1e-12);
  }
}

TEST(OpenDriveLanes, TravelFollowsTheTrafficRule) {
  const RoadNetwork network = parse_opendrive(xodr(road("1", 50, geometry(0, 0, 0, 0, 50, "<line/>"))), "t.xodr");
  const Road& r = network.roads().front();
  EXPECT_EQ(r.default_travel(-1), Travel::kAlongS);
  EXPECT_EQ(r.default_travel(1), Travel::kAgainstS);
  std::string text = xodr(road("1", 50, geometry(0, 0, 0, 0, 50, "<line/>")));
  text.replace(text.find("junction=\"-1\""), 13, "junction=\"-1\" rule=\"LHT\"");
  const RoadNetwork left_network = parse_opendrive(text, "lht.xodr");
  const Road& left = left_network.roads().front();
  EXPECT_EQ(left.rule, TrafficRule::kLeftHand);
  EXPECT_EQ(left.default_travel(1), Travel::kAlongS);
  EXPECT_EQ(left.default_travel(-1), Travel::kAgainstS);
  for (const auto& entry : lane_type_table()) EXPECT_EQ(info(entry.type).name, entry.name);
  EXPECT_EQ(info(LaneType::kDriving).drivability, Drivability::kDrivable);
  EXPECT_EQ(info(LaneType::kShoulder).drivability, Drivability::kEmergencyOnly);
  EXPECT_EQ(info(LaneType::kCurb).drivability, Drivability::kNotDrivable);
}

void expect_round_trip(const RoadNetwork& network) {
  const Road& r = network.roads().front();
  for (double s = 0; s <= r.length; s += r.length / 37) {
    for (const int id : r.lane_ids(s)) {
      if (id == 0) continue;
      for (const double fraction : {-0.8, 0.0, 0.9}) {  // of the way from the centre to a border
        const double offset = fraction * r.lane_width(id, s) / 2;
        const double t = r.lane_center_t(id, s) + offset;
        const Pose p = network.lane_to_world(r, id, s, offset);
        const Pose q = network.road_to_world(r, s, t);
        EXPECT_NEAR(p.x, q.x, 1e-12);
        const auto back = network.world_to_road(p.x, p.y);
        ASSERT_TRUE(back.has_value()) << s << " " << t;
        EXPECT_EQ(back->road, &r);
        EXPECT_NEAR(back->s, s, 1e-7) << t;
        EXPECT_NEAR(back->t, t, 1e-7) << s;
        EXPECT_EQ(back->lane_id, id);
        EXPECT_NEAR(std::remainder(back->heading - p.heading, 2 * std::numbers::pi), 0.0, 1e-7);
      }
    }
  }
}

TEST(OpenDriveNetwork, WorldToRoadInvertsRoadToWorld) {
  const std::string lanes = lanes_text();
  // Straight, arc (radius 40, lanes on the inside reach 33 m from its centre) and a spiral.
  expect_round_trip(parse_opendrive(xodr(road("1", 100, geometry(0, 1, 2, 0.5, 100, "<line/>"), lanes)), "s.xodr"));
  expect_round_trip(parse_opendrive(
      xodr(road("1", 100, geometry(0, 1, 2, 0.5, 100, "<arc curvature=\"0.025\"/>"), lanes)), "a.xodr"));
  expect_round_trip(parse_opendrive(
      xodr(road("1", 100, geometry(0, 1, 2, 0.5, 100, "<spiral curvStart=\"-0.01\" curvEnd=\"0.02\"/>"), lanes)),
      "c.xodr"));
  // A line into an arc: the joint at s = 50.
  const Pose joint = clothoid({0, 0, 0}, 0, 0, 50);
  expect_round_trip(
      parse_opendrive(xodr(road("1", 100,
                                geometry(0, 0, 0, 0, 50, "<line/>") +
                                    geometry(50, joint.x, joint.y, joint.heading, 50, "<arc curvature=\"-0.02\"/>"),
                                lanes)),
                      "j.xodr"));
}

TEST(OpenDriveNetwork, WorldToRoadFindsNothingOffTheRoads) {
  const RoadNetwork network = parse_opendrive(xodr(road("1", 100, geometry(0, 0, 0, 0, 100, "<line/>"))), "o.xodr");
  EXPECT_FALSE(network.world_to_road(50, 3.6).has_value());  // beyond the 3.5 m lane
  EXPECT_FALSE(network.world_to_road(-1, 0.5).has_value());  // before the start
  EXPECT_FALSE(network.world_to_road(100.5, 0.5).has_value());
  EXPECT_EQ(network.world_to_road(50, 3.4)->lane_id, 1);
  EXPECT_EQ(network.world_to_road(50, -3.4)->lane_id, -1);
}

std::string link(const std::string& predecessor, const std::string& successor) {
  return "<link>" + predecessor + successor + "</link>";
}

std::string lanes_linked(const std::string& left_link, const std::string& right_link) {
  return section(0, lane(1, "driving", "<link>" + left_link + "</link>" + width(0, 3.5)),
                 lane(-1, "driving", "<link>" + right_link + "</link>" + width(0, 3.5)));
}

TEST(OpenDriveNetwork, LanesLeadThroughRoadLinksAndJunctions) {
  // Road 1 -> road 2 (met at its start); road 2 ends in junction 9, whose connecting road 3 runs
  // from road 2 into road 4, met at 4's end (so road 4's lane 1 continues it, driven against s).
  const std::string body = road("1", 30, geometry(0, 0, 0, 0, 30, "<line/>"),
                                lanes_linked("<predecessor id=\"1\"/>", "<successor id=\"-1\"/>"),
                                link("", "<successor elementType=\"road\" elementId=\"2\" contactPoint=\"start\"/>")) +
                           road("2", 20, geometry(0, 30, 0, 0, 20, "<line/>"),
                                lanes_linked("<predecessor id=\"1\"/>", "<predecessor id=\"-1\"/>"),
                                link("<predecessor elementType=\"road\" elementId=\"1\" contactPoint=\"end\"/>",
                                     "<successor elementType=\"junction\" elementId=\"9\"/>")) +
                           road("3", 10, geometry(0, 50, 0, 0, 10, "<line/>"), testing::two_lanes(),
                                link("<predecessor elementType=\"road\" elementId=\"2\" contactPoint=\"end\"/>",
                                     "<successor elementType=\"road\" elementId=\"4\" contactPoint=\"end\"/>"),
                                "9") +
                           road("4", 40, geometry(0, 100, 0, std::numbers::pi, 40, "<line/>"), testing::two_lanes(),
                                link("", "<successor elementType=\"junction\" elementId=\"9\"/>")) +
                           "  <junction id=\"9\" name=\"j\">\n"
                           "    <connection id=\"0\" incomingRoad=\"2\" connectingRoad=\"3\" contactPoint=\"start\">\n"
                           "      <laneLink from=\"-1\" to=\"-1\"/>\n"
                           "    </connection>\n"
                           "  </junction>\n";
  const RoadNetwork network = parse_opendrive(xodr(body), "links.xodr");
  const Road& r1 = *network.find_road("1");
  const Road& r2 = *network.find_road("2");
  EXPECT_EQ(network.find_road("5"), nullptr);
  ASSERT_NE(network.find_junction("9"), nullptr);

  const auto after_1 = network.next_lanes(r1, -1, Travel::kAlongS);
  ASSERT_EQ(after_1.size(), 1U);
  EXPECT_EQ(after_1[0].road, &r2);
  EXPECT_EQ(after_1[0].lane_id, -1);
  EXPECT_EQ(after_1[0].s, 0.0);
  EXPECT_EQ(after_1[0].travel, Travel::kAlongS);
  // The left lane of road 2 driven against s comes back into road 1 at its end.
  const auto before_2 = network.next_lanes(r2, 1, Travel::kAgainstS);
  ASSERT_EQ(before_2.size(), 1U);
  EXPECT_EQ(before_2[0].road, &r1);
  EXPECT_EQ(before_2[0].lane_id, 1);
  EXPECT_EQ(before_2[0].s, r1.length);
  EXPECT_EQ(before_2[0].travel, Travel::kAgainstS);
  // Through the junction.
  const auto into_junction = network.next_lanes(r2, -1, Travel::kAlongS);
  ASSERT_EQ(into_junction.size(), 1U);
  EXPECT_EQ(into_junction[0].road->id, "3");
  EXPECT_EQ(into_junction[0].lane_id, -1);
  EXPECT_EQ(into_junction[0].s, 0.0);
  // Nothing is linked past road 1's start for its right lane, nor for a lane the junction does not take.
  EXPECT_TRUE(network.next_lanes(r1, -1, Travel::kAgainstS).empty());
  EXPECT_TRUE(network.next_lanes(r2, 1, Travel::kAlongS).empty());
}

}  // namespace
}  // namespace emrm::opendrive
