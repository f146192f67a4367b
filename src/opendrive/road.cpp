// A road's lanes across its width (ASAM OpenDRIVE 1.7 §9.3 lane offset, §9.5.1 lane width, §9.5.2
// lane borders) and its road coordinates in the world (§5.3.3: t to the left of the reference line).

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "emrm/opendrive/road_network.hpp"

namespace emrm::opendrive {

double Cubic::at(double s) const {
  const double ds = s - s_start;
  return a + ds * (b + ds * (c + ds * d));
}

double Cubic::derivative(double s) const {
  const double ds = s - s_start;
  return b + ds * (2.0 * c + ds * 3.0 * d);
}

double evaluate(const std::vector<Cubic>& records, double s) {
  const auto after = std::upper_bound(records.begin(), records.end(), s,
                                      [](double value, const Cubic& record) { return value < record.s_start; });
  return after == records.begin() ? 0.0 : std::prev(after)->at(s);
}

const Lane* LaneSection::find(int lane_id) const {
  if (lane_id == 0) return &center;
  const auto& side = lane_id > 0 ? left : right;
  const auto index = static_cast<std::size_t>(std::abs(lane_id)) - 1;
  return index < side.size() ? &side[index] : nullptr;
}

double Road::lane_offset(double s) const { return evaluate(lane_offsets, s); }

const LaneSection& Road::section_at(double s) const {
  if (lane_sections.empty()) throw std::logic_error("road " + id + " has no lane section");
  const auto after = std::upper_bound(lane_sections.begin(), lane_sections.end(), std::clamp(s, 0.0, length),
                                      [](double value, const LaneSection& section) { return value < section.s; });
  return after == lane_sections.begin() ? lane_sections.front() : *std::prev(after);
}

std::vector<int> Road::lane_ids(double s) const {
  const LaneSection& section = section_at(s);
  std::vector<int> ids;
  for (std::size_t i = section.left.size(); i-- > 0;) ids.push_back(section.left[i].id);  // outer to inner
  ids.push_back(0);
  for (const Lane& lane : section.right) ids.push_back(lane.id);
  return ids;
}

namespace {

/// The distance of each lane's outer border from the centre lane on one side, inner to outer:
/// a lane's width added to its inner neighbour's, or its <border> record where it has no width.
std::vector<double> outer_distances(const std::vector<Lane>& side, double s) {
  std::vector<double> distances;
  double inner = 0.0;
  for (const Lane& lane : side) {
    inner = lane.widths.empty() ? evaluate(lane.borders, s) : inner + evaluate(lane.widths, s);
    distances.push_back(inner);
  }
  return distances;
}

}  // namespace

std::pair<double, double> Road::lane_borders(int lane_id, double s) const {
  const LaneSection& section = section_at(s);
  if (section.find(lane_id) == nullptr)
    throw std::out_of_range("road " + id + " has no lane " + std::to_string(lane_id) + " at s = " + std::to_string(s));
  const double offset = lane_offset(s);
  if (lane_id == 0) return {offset, offset};
  const double sign = lane_id > 0 ? 1.0 : -1.0;
  const auto distances = outer_distances(lane_id > 0 ? section.left : section.right, s);
  const auto index = static_cast<std::size_t>(std::abs(lane_id)) - 1;
  const double inner = index == 0 ? 0.0 : distances[index - 1];
  return {offset + sign * inner, offset + sign * distances[index]};
}

double Road::lane_center_t(int lane_id, double s) const {
  const auto [inner, outer] = lane_borders(lane_id, s);
  return 0.5 * (inner + outer);
}

double Road::lane_width(int lane_id, double s) const {
  const auto [inner, outer] = lane_borders(lane_id, s);
  return std::abs(outer - inner);
}

LaneType Road::lane_type(int lane_id, double s) const {
  const Lane* lane = section_at(s).find(lane_id);
  if (lane == nullptr)
    throw std::out_of_range("road " + id + " has no lane " + std::to_string(lane_id) + " at s = " + std::to_string(s));
  return lane->type;
}

std::optional<int> Road::lane_at(double s, double t) const {
  const LaneSection& section = section_at(s);
  const double offset = lane_offset(s);
  const auto search = [&](const std::vector<Lane>& side, double sign) -> std::optional<int> {
    const double d = sign * (t - offset);  // distance outwards from the centre lane
    double inner = 0.0;
    const auto distances = outer_distances(side, s);
    for (std::size_t i = 0; i < side.size(); ++i) {
      if (d >= std::min(inner, distances[i]) && d <= std::max(inner, distances[i]) && distances[i] != inner)
        return side[i].id;
      inner = distances[i];
    }
    return std::nullopt;
  };
  if (t >= offset) {
    if (auto lane = search(section.left, 1.0)) return lane;
    if (t == offset) return search(section.right, -1.0);
    return std::nullopt;
  }
  return search(section.right, -1.0);
}

std::optional<int> Road::lane_in_next_section(int lane_id, double s, Travel travel) const {
  const LaneSection& here = section_at(s);
  const auto index = static_cast<std::size_t>(&here - lane_sections.data());
  const bool forward = travel == Travel::kAlongS;
  if (forward ? index + 1 >= lane_sections.size() : index == 0) return std::nullopt;
  const LaneSection& next = lane_sections[forward ? index + 1 : index - 1];
  const Lane* lane = here.find(lane_id);
  if (lane == nullptr) return std::nullopt;
  const std::vector<int>& linked = forward ? lane->successors : lane->predecessors;
  for (const int next_id : linked)
    if (next.find(next_id) != nullptr) return next_id;
  if (linked.empty() && next.find(lane_id) != nullptr) return lane_id;
  return std::nullopt;
}

Travel Road::default_travel(int lane_id) const {
  const bool left = lane_id > 0;
  const bool against = rule == TrafficRule::kRightHand ? left : !left && lane_id != 0;
  return against ? Travel::kAgainstS : Travel::kAlongS;
}

Pose Road::to_world(double s, double t) const {
  const Pose p = plan_view.at(s);
  return {p.x - t * std::sin(p.heading), p.y + t * std::cos(p.heading), p.heading};
}

}  // namespace emrm::opendrive
