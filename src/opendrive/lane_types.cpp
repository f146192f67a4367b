// The roadside table: what each OpenDRIVE lane type (e_laneType, ASAM OpenDRIVE 1.7 §9.5.3) means
// for a car that must leave its lane. The one owner of these facts (docs/import.md repeats it).

#include <algorithm>
#include <stdexcept>

#include "emrm/opendrive/road_network.hpp"

namespace emrm::opendrive {

const std::vector<LaneTypeInfo>& lane_type_table() {
  using enum LaneType;
  using enum Drivability;
  static const std::vector<LaneTypeInfo> table{
      {kDriving, "driving", kDrivable, "a normal lane for traffic"},
      {kShoulder, "shoulder", kEmergencyOnly, "a paved hard shoulder: passable in an emergency"},
      {kBorder, "border", kNotDrivable, "a hard border at the road's edge (same height as the lane)"},
      {kMedian, "median", kNotDrivable, "a median between the carriageways: barriers, grass, kerbs"},
      {kSidewalk, "sidewalk", kNotDrivable, "a pavement: pedestrians"},
      {kBiking, "biking", kNotDrivable, "a cycle lane: cyclists"},
      {kRestricted, "restricted", kNotDrivable, "a lane cars must not use (hatched area, verge)"},
      {kNone, "none", kNotDrivable, "nothing drivable (the world's edge, the centre lane)"},
      {kParking, "parking", kEmergencyOnly, "parking spaces: paved, may hold parked cars"},
      {kStop, "stop", kEmergencyOnly, "an emergency stopping lane (1.4's hard shoulder)"},
      {kEntry, "entry", kDrivable, "an acceleration lane onto a motorway"},
      {kExit, "exit", kDrivable, "a deceleration lane off a motorway"},
      {kOnRamp, "onRamp", kDrivable, "a ramp onto a motorway"},
      {kOffRamp, "offRamp", kDrivable, "a ramp off a motorway"},
      {kConnectingRamp, "connectingRamp", kDrivable, "a ramp between two motorways"},
      {kBidirectional, "bidirectional", kDrivable, "a lane driven in both directions"},
      {kCurb, "curb", kNotDrivable, "a kerb: a raised edge between road and pavement"},
      {kSpecial1, "special1", kNotDrivable, "user-defined (unknown): treated as not drivable"},
      {kSpecial2, "special2", kNotDrivable, "user-defined (unknown): treated as not drivable"},
      {kSpecial3, "special3", kNotDrivable, "user-defined (unknown): treated as not drivable"},
      {kRoadWorks, "roadWorks", kEmergencyOnly, "road works: paved, may hold workers and machines"},
      {kTram, "tram", kNotDrivable, "tram tracks"},
      {kRail, "rail", kNotDrivable, "railway tracks"},
      {kBus, "bus", kDrivable, "a bus lane: paved, for buses"},
      {kTaxi, "taxi", kDrivable, "a taxi lane: paved, for taxis"},
      {kHov, "HOV", kDrivable, "a lane for high-occupancy vehicles"},
      {kMwyEntry, "mwyEntry", kDrivable, "a motorway entry lane (1.5, deprecated)"},
      {kMwyExit, "mwyExit", kDrivable, "a motorway exit lane (1.5, deprecated)"},
  };
  return table;
}

const LaneTypeInfo& info(LaneType type) {
  const auto& table = lane_type_table();
  const auto i = static_cast<std::size_t>(type);
  if (i >= table.size() || table[i].type != type) throw std::logic_error("lane_type_table is out of enum order");
  return table[i];
}

std::optional<LaneType> lane_type_named(std::string_view name) {
  const auto& table = lane_type_table();
  const auto found = std::find_if(table.begin(), table.end(), [&](const LaneTypeInfo& t) { return t.name == name; });
  if (found == table.end()) return std::nullopt;
  return found->type;
}

std::string lane_type_names() {
  std::string names;
  for (const auto& entry : lane_type_table()) names += (names.empty() ? "" : ", ") + std::string(entry.name);
  return names;
}

}  // namespace emrm::opendrive
