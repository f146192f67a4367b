// emrm's own OpenDRIVE export (exchange::opendrive_xml, 1.6) read back by the reader: the main
// road's drivable edges and the ego's lane are the scene's, and its lanes lead through the junction.

#include <gtest/gtest.h>

#include "emrm/exchange/opendrive.hpp"
#include "emrm/opendrive/road_network.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::opendrive {
namespace {

TEST(OpenDriveReader, ReadsEmrmsOwnExportAsTheScene) {
  sim::SceneConfig wide;
  wide.road.lanes = 3;
  wide.road.lane_width_m = 3.25;
  wide.road.shoulder_m = 2.0;
  wide.road.ego_lane_center_m = -3.25;
  for (const sim::SceneConfig& config : {sim::SceneConfig{}, wide}) {
    const RoadNetwork network =
        parse_opendrive(exchange::opendrive_xml(config, sim::TJunctionCell{50, 1.2, 0.8, 3.0, 10}), "tjunction.xodr");
    const Road* main = network.find_road("1");
    ASSERT_NE(main, nullptr);
    const double s = 0.5 * main->length;
    const auto ids = main->lane_ids(s);
    const double top = network.road_to_world(*main, s, main->lane_borders(ids.front(), s).second).y;
    const double bottom = network.road_to_world(*main, s, main->lane_borders(ids.back(), s).second).y;
    EXPECT_NEAR(top, config.road.drivable_max_y_m(), 1e-9);
    EXPECT_NEAR(bottom, config.road.drivable_min_y_m(), 1e-9);

    const Pose on_ego_lane = network.road_to_world(*main, s, 0.0);
    const auto ego = network.world_to_road(on_ego_lane.x, config.road.ego_lane_center_m);
    ASSERT_TRUE(ego.has_value());
    EXPECT_EQ(ego->road, main);
    EXPECT_EQ(main->lane_type(ego->lane_id, ego->s), LaneType::kDriving);
    EXPECT_NEAR(network.lane_to_world(*main, ego->lane_id, s, 0.0).y, config.road.ego_lane_center_m, 1e-9);

    // The ego's lane, driven on, leads into the junction's connecting road.
    const auto next = network.next_lanes(*main, ego->lane_id, main->default_travel(ego->lane_id));
    ASSERT_FALSE(next.empty());
    EXPECT_FALSE(next.front().road->junction.empty());
  }
}

}  // namespace
}  // namespace emrm::opendrive
