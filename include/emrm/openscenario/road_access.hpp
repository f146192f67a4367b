#pragma once

// What the player asks of a road network: lane coordinates to the world frame and back, and a step
// along a lane that crosses road ends through their links. The OpenDRIVE network answers it
// (road_network_access.hpp); a test may answer it with a road of its own.

#include <memory>
#include <optional>
#include <string>

#include "emrm/opendrive/road_network.hpp"

namespace emrm::openscenario {

/// A point in lane coordinates: a road, a lane of it, the road's s and the lateral offset from the
/// lane's centre, positive to the left of the road's reference direction (t), as esmini counts it.
struct LaneCoord {
  std::string road_id;
  int lane_id = 0;
  double s_m = 0.0;
  double offset_m = 0.0;
};

/// A pose in the world (OpenDRIVE inertial) frame.
struct WorldPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_rad = 0.0;
};

/// Where a step along a lane ended, and whether the road's s direction there is opposite to the
/// one the step started on (a link into a road's end flips it).
struct LaneStep {
  LaneCoord to;
  bool direction_flipped = false;
  bool end_of_road = false;  ///< the lane ended without a successor: `to` is its last point
};

class RoadAccess {
 public:
  virtual ~RoadAccess() = default;
  [[nodiscard]] virtual bool has_road(const std::string& road_id) const = 0;
  /// Whether the road has lane `lane_id` at `s_m`.
  [[nodiscard]] virtual bool has_lane(const std::string& road_id, int lane_id, double s_m) const = 0;
  /// The world pose of the point (s, t) of a road; heading: the road's reference direction there.
  [[nodiscard]] virtual WorldPose road_to_world(const std::string& road_id, double s_m, double t_m) const = 0;
  /// Whether a lane is driven along s by its road's traffic rule (right-hand: the right lanes).
  [[nodiscard]] virtual bool driven_along_s(const std::string& road_id, int lane_id) const = 0;
  /// The curvature of the road's reference line at s (1/m, positive to the left).
  [[nodiscard]] virtual double curvature(const std::string& road_id, double s_m) const = 0;
  /// The t of a lane's centre at s.
  [[nodiscard]] virtual double lane_center_t(const std::string& road_id, int lane_id, double s_m) const = 0;
  /// The lane coordinates of a world point, preferring the road of `hint` (may be nullptr);
  /// std::nullopt off every road's lanes.
  [[nodiscard]] virtual std::optional<LaneCoord> world_to_lane(double x_m, double y_m, const LaneCoord* hint) const = 0;
  /// Whether (s, t) lies beyond the road's lanes on its side of the centre lane, lanes of type none
  /// left out (esmini's Position::IsOffRoad).
  [[nodiscard]] virtual bool off_road(const std::string& road_id, double s_m, double t_m) const = 0;
  /// `from` moved by `ds_m` along s (negative: towards s = 0) keeping its lane and offset, into the
  /// linked road and lane past either end of the road.
  [[nodiscard]] virtual LaneStep step_along(const LaneCoord& from, double ds_m) const = 0;
};

/// The OpenDRIVE network as the player asks it: lanes follow their links and junction connections
/// (the first connection that takes the lane), a lane that ends within a road continues in the lane
/// that holds its t. Shares ownership of `network`.
[[nodiscard]] std::shared_ptr<const RoadAccess> road_access(std::shared_ptr<const opendrive::RoadNetwork> network);

/// The step along the road's s that covers `distance_m` along the lane at `at`'s offset (esmini's
/// DistanceToDS): distance / (1 - curvature t), the curvature and t taken where the step starts.
[[nodiscard]] double s_step_for(const RoadAccess& roads, const LaneCoord& at, double distance_m);

/// The world pose of a lane point: the road's pose at the lane centre's t plus the offset.
[[nodiscard]] WorldPose lane_to_world(const RoadAccess& roads, const LaneCoord& at);

}  // namespace emrm::openscenario
