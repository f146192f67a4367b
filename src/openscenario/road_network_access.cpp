// The OpenDRIVE road network as the player asks it (road_access.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "emrm/openscenario/road_access.hpp"

namespace emrm::openscenario {
namespace {

class NetworkAccess final : public RoadAccess {
 public:
  explicit NetworkAccess(std::shared_ptr<const opendrive::RoadNetwork> network) : network_(std::move(network)) {}

  bool has_road(const std::string& road_id) const override { return network_->find_road(road_id) != nullptr; }

  bool has_lane(const std::string& road_id, int lane_id, double s_m) const override {
    const opendrive::Road* road = network_->find_road(road_id);
    return road != nullptr && lane_id != 0 && road->section_at(s_m).find(lane_id) != nullptr;
  }

  WorldPose road_to_world(const std::string& road_id, double s_m, double t_m) const override {
    const opendrive::Pose p = network_->road_to_world(road(road_id), s_m, t_m);
    return {p.x, p.y, p.heading};
  }

  double curvature(const std::string& road_id, double s_m) const override {
    return road(road_id).plan_view.curvature(s_m);
  }

  bool driven_along_s(const std::string& road_id, int lane_id) const override {
    return road(road_id).default_travel(lane_id) == opendrive::Travel::kAlongS;
  }

  double lane_center_t(const std::string& road_id, int lane_id, double s_m) const override {
    const opendrive::Road& r = road(road_id);
    if (r.section_at(s_m).find(lane_id) == nullptr) return r.lane_offset(s_m);
    return r.lane_center_t(lane_id, s_m);
  }

  std::optional<LaneCoord> world_to_lane(double x_m, double y_m, const LaneCoord* hint) const override {
    const opendrive::Road* hint_road = hint != nullptr ? network_->find_road(hint->road_id) : nullptr;
    const auto found = network_->world_to_road(x_m, y_m, hint_road);
    if (!found || found->road == nullptr) return std::nullopt;
    const opendrive::Road& r = *found->road;
    return LaneCoord{r.id, found->lane_id, found->s, found->t - r.lane_center_t(found->lane_id, found->s)};
  }

  bool off_road(const std::string& road_id, double s_m, double t_m) const override {
    const opendrive::Road& r = road(road_id);
    const double from_centre = t_m - r.lane_offset(s_m);
    double width = 0.0;
    for (const int id : r.lane_ids(s_m))
      if (id != 0 && (id > 0) == (from_centre > 0.0) && r.lane_type(id, s_m) != opendrive::LaneType::kNone)
        width += r.lane_width(id, s_m);
    return std::fabs(from_centre) > width;
  }

  LaneStep step_along(const LaneCoord& from, double ds_m) const override {
    LaneStep step;
    step.to = from;
    const opendrive::Road* r = &road(from.road_id);
    double s = from.s_m + ds_m;
    bool along = ds_m >= 0.0;  // the direction of the step in the current road's s
    // Past an end: into the lane it leads to, as often as the step is long.
    for (int hops = 0; hops < 64 && (s > r->length || s < 0.0); ++hops) {
      const double beyond = along ? s - r->length : -s;
      const auto next =
          network_->next_lanes(*r, step.to.lane_id, along ? opendrive::Travel::kAlongS : opendrive::Travel::kAgainstS);
      if (next.empty()) {
        step.to.s_m = along ? r->length : 0.0;
        step.end_of_road = true;
        return step;
      }
      const opendrive::LaneContinuation& c = next.front();
      const bool next_along = c.travel == opendrive::Travel::kAlongS;
      if (next_along != along) {
        step.direction_flipped = !step.direction_flipped;
        step.to.offset_m = -step.to.offset_m;  // the same side of the lane when its t turns round
      }
      along = next_along;
      r = c.road;
      step.to.road_id = r->id;
      step.to.lane_id = c.lane_id;
      s = along ? c.s + beyond : c.s - beyond;
    }
    step.to.s_m = std::clamp(s, 0.0, r->length);
    // A lane that ends within the road (a new lane section): the lane that holds its t there.
    if (r->section_at(step.to.s_m).find(step.to.lane_id) == nullptr) {
      const double t = lane_center_t(from.road_id, from.lane_id, from.s_m);
      if (const auto lane = r->lane_at(step.to.s_m, t)) step.to.lane_id = *lane;
    }
    return step;
  }

 private:
  const opendrive::Road& road(const std::string& id) const {
    const opendrive::Road* r = network_->find_road(id);
    if (r == nullptr) throw InputError({network_->file(), 0, 0}, fmt::format("road '{}' does not exist", id));
    return *r;
  }

  std::shared_ptr<const opendrive::RoadNetwork> network_;
};

}  // namespace

std::shared_ptr<const RoadAccess> road_access(std::shared_ptr<const opendrive::RoadNetwork> network) {
  return std::make_shared<NetworkAccess>(std::move(network));
}

}  // namespace emrm::openscenario
