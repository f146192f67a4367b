// Bad input never crashes the OpenDRIVE reader: every truncation and many one-character damages
// of a file that uses every supported element are read or refused with an InputError, nothing else.

#include <gtest/gtest.h>

#include <cmath>

#include "emrm/opendrive/road_network.hpp"
#include "opendrive/xodr_text.hpp"

namespace emrm::opendrive {
namespace {

using testing::geometry;
using testing::lane;
using testing::road;
using testing::section;
using testing::width;
using testing::xodr;

std::string every_element(int rev_minor) {
  const Pose b = clothoid({0, 0, 0}, 0, 0.001, 10);
  const std::string geometries = geometry(0, 0, 0, 0, 10, "<spiral curvStart=\"0\" curvEnd=\"0.01\"/>") +
                                 geometry(10, b.x, b.y, b.heading, 10, "<poly3 a=\"0\" b=\"0\" c=\"0.001\" d=\"0\"/>") +
                                 geometry(20, 10, 5, 0.2, 10,
                                          "<paramPoly3 aU=\"0\" bU=\"10\" cU=\"0\" dU=\"0\" aV=\"0\" bV=\"0\" cV=\"1\" "
                                          "dV=\"0\" pRange=\"normalized\"/>");
  const std::string lanes =
      "<laneOffset s=\"0\" a=\"0.1\" b=\"0\" c=\"0\" d=\"0\"/>\n" +
      section(0, lane(1, "driving", width(0, 3)),
              lane(-1, "driving", "<link><successor id=\"-1\"/></link>" + width(0, 3))) +
      section(15, "", lane(-1, "shoulder", "<border sOffset=\"0\" a=\"2\" b=\"0\" c=\"0\" d=\"0\"/>"));
  return xodr(road("1", 30, geometries, lanes, "<link><successor elementType=\"junction\" elementId=\"9\"/></link>") +
                  road("2", 10, geometry(0, 40, 0, 0, 10, "<line/>"), testing::two_lanes(),
                       "<link><predecessor elementType=\"road\" elementId=\"1\" contactPoint=\"end\"/></link>", "9") +
                  "  <junction id=\"9\" name=\"j\">\n"
                  "    <connection id=\"0\" incomingRoad=\"1\" connectingRoad=\"2\" contactPoint=\"start\">"
                  "<laneLink from=\"-1\" to=\"-1\"/></connection>\n"
                  "  </junction>\n",
              rev_minor);
}

/// Reads `text`; fails the test on any exception but an InputError, and on a position-less one.
void read_or_refuse(const std::string& text) {
  try {
    const RoadNetwork network = parse_opendrive(text, "damaged.xodr");
    for (const Road& r : network.roads()) {
      const Pose p = network.lane_to_world(r, r.lane_ids(0).back(), 0.5 * r.length, 0.0);
      (void)network.world_to_road(p.x, p.y);
      for (const int id : r.lane_ids(r.length)) (void)network.next_lanes(r, id, Travel::kAlongS);
    }
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "damaged.xodr") << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what() << "\n" << text;
  }
}

TEST(OpenDriveReader, DamagedFilesAreReadOrRefusedNeverCrash) {
  for (const int minor : {5, 7}) {
    const std::string text = every_element(minor);
    EXPECT_NO_THROW((void)parse_opendrive(text, "whole.xodr")) << minor;
    for (std::size_t n = 0; n < text.size(); n += 7) read_or_refuse(text.substr(0, n));
    for (std::size_t i = 0; i < text.size(); i += 4) {
      for (const char c : {'-', '9', 'x', '"', '<', 'e'}) {
        std::string damaged = text;
        damaged[i] = c;
        read_or_refuse(damaged);
      }
    }
  }
}

}  // namespace
}  // namespace emrm::opendrive
