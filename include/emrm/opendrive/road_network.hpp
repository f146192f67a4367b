#pragma once

// An OpenDRIVE road network (ASAM OpenDRIVE 1.4-1.7) as the simulation needs it: planar roads with
// their reference lines, lane offsets, lane sections and lanes, the links between roads, and
// junctions; coordinate transforms road <-> world and the lane an actor follows across road ends.
// What the reader supports, ignores and refuses: docs/import.md, "OpenDRIVE".
//
// Conventions (ASAM OpenDRIVE 1.7 §5, §9):
// - s along the reference line from 0 to the road's length; t to its left (the reference line's
//   normal rotated +90°). Elevation, superelevation and shape are ignored: the world is planar.
// - Lanes: positive ids left of the centre lane (0), negative right; the centre lane runs along
//   the reference line shifted by the lane offset and has no width.
// - Direction of travel: with right-hand traffic (the default, <road rule="RHT">) the right lanes
//   (negative ids) are driven along s and the left lanes against s; left-hand traffic swaps them.
//   default_travel() says which; the poses here always head along s (the caller adds pi).

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/opendrive/geometry.hpp"

namespace emrm::opendrive {

/// The lane types of OpenDRIVE 1.4-1.7 (e_laneType; 1.4's and 1.5's are a subset of 1.6's).
enum class LaneType {
  kDriving,
  kShoulder,
  kBorder,
  kMedian,
  kSidewalk,
  kBiking,
  kRestricted,
  kNone,
  kParking,
  kStop,
  kEntry,
  kExit,
  kOnRamp,
  kOffRamp,
  kConnectingRamp,
  kBidirectional,
  kCurb,
  kSpecial1,
  kSpecial2,
  kSpecial3,
  kRoadWorks,
  kTram,
  kRail,
  kBus,
  kTaxi,
  kHov,
  kMwyEntry,
  kMwyExit
};

/// What a car may do on a lane of a type.
enum class Drivability {
  kDrivable,       // a lane for cars in normal driving
  kEmergencyOnly,  // paved and passable by a car, used only to avoid harm (a shoulder, road works)
  kNotDrivable     // not for cars: kerb, verge, pavement, tracks, a median, or nothing at all
};

/// A lane type's entry in the roadside table (lane_type_table(), the one owner of these facts).
struct LaneTypeInfo {
  LaneType type = LaneType::kNone;
  std::string_view name;                                // as the file writes it ("onRamp")
  Drivability drivability = Drivability::kNotDrivable;  // for a car
  std::string_view roadside;                            // what lies there, for messages and docs
};

/// Every lane type, in enum order.
[[nodiscard]] const std::vector<LaneTypeInfo>& lane_type_table();
[[nodiscard]] const LaneTypeInfo& info(LaneType type);
/// The type a file names; std::nullopt for a name not in the table.
[[nodiscard]] std::optional<LaneType> lane_type_named(std::string_view name);
/// "driving, shoulder, ..." for messages.
[[nodiscard]] std::string lane_type_names();

/// a + b ds + c ds² + d ds³ with ds = s - s_start (s_start absolute along the road).
struct Cubic {
  double s_start = 0.0;
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
  [[nodiscard]] double at(double s) const;
  [[nodiscard]] double derivative(double s) const;
};
/// The value at s of the last record starting at or before s; 0 before the first and without records.
/// Records are in increasing s_start.
[[nodiscard]] double evaluate(const std::vector<Cubic>& records, double s);

enum class TrafficRule { kRightHand, kLeftHand };
enum class Travel { kAlongS, kAgainstS };
enum class ContactPoint { kStart, kEnd };
enum class ElementType { kRoad, kJunction };

struct Lane {
  int id = 0;
  LaneType type = LaneType::kNone;
  /// <width> records (ASAM OpenDRIVE 1.7 §9.5.1), s_start absolute (section s + sOffset).
  std::vector<Cubic> widths;
  /// <border> records (§9.5.2), used only when there is no <width>: the outer border's distance from
  /// the centre lane (positive outwards, as a width), s_start absolute.
  std::vector<Cubic> borders;
  std::vector<int> predecessors;  // lane ids in the previous section or road (§9.4)
  std::vector<int> successors;
  SourceLocation where;
};

struct LaneSection {
  double s = 0.0;  // where it starts along the road
  bool single_sided = false;
  std::vector<Lane> left;   // ids 1, 2, ... (inner to outer)
  std::vector<Lane> right;  // ids -1, -2, ... (inner to outer)
  Lane center;              // id 0
  [[nodiscard]] const Lane* find(int lane_id) const;
};

/// A road's <predecessor> or <successor> (§8.2).
struct RoadLink {
  ElementType type = ElementType::kRoad;
  std::string id;
  std::optional<ContactPoint> contact_point;  // required for a road; absent for a junction
  SourceLocation where;
};

struct Road {
  std::string id;
  std::string name;
  double length = 0.0;
  std::string junction;  // the junction it belongs to; empty for "-1" (none)
  TrafficRule rule = TrafficRule::kRightHand;
  ReferenceLine plan_view;
  std::vector<Cubic> lane_offsets;         // <laneOffset> (§9.3), t of the centre lane
  std::vector<LaneSection> lane_sections;  // increasing s, the first at 0
  std::optional<RoadLink> predecessor;
  std::optional<RoadLink> successor;
  SourceLocation where;

  /// t of the centre lane at s.
  [[nodiscard]] double lane_offset(double s) const;
  /// The section that holds s (the later one at a boundary; s clamped to [0, length]).
  [[nodiscard]] const LaneSection& section_at(double s) const;
  /// The lane ids at s, from the leftmost to the rightmost, 0 included.
  [[nodiscard]] std::vector<int> lane_ids(double s) const;
  /// t of the lane's inner and outer borders at s (equal for lane 0: the lane offset).
  /// Throws std::out_of_range when the section at s has no such lane.
  [[nodiscard]] std::pair<double, double> lane_borders(int lane_id, double s) const;
  [[nodiscard]] double lane_center_t(int lane_id, double s) const;
  [[nodiscard]] double lane_width(int lane_id, double s) const;
  [[nodiscard]] LaneType lane_type(int lane_id, double s) const;
  /// The lane whose borders hold t at s (lane 0 is never returned: a t on the centre lane belongs
  /// to the first lane on the side it leans to); std::nullopt outside every lane.
  [[nodiscard]] std::optional<int> lane_at(double s, double t) const;
  /// The lane that `lane_id` of the section holding s continues as in the next section in `travel`
  /// (inside this road; past its ends see RoadNetwork::next_lanes): its successor link for kAlongS,
  /// predecessor for kAgainstS; without such a link, the same id if that section has it (files often
  /// leave unchanged lanes unlinked). std::nullopt in the road's last section in `travel`, or when
  /// the lane ends there.
  [[nodiscard]] std::optional<int> lane_in_next_section(int lane_id, double s, Travel travel) const;
  /// The direction a lane is driven in by the road's rule (the sign of its id).
  [[nodiscard]] Travel default_travel(int lane_id) const;
  /// The pose at (s, t): t from the reference line (not from the centre lane), heading along s;
  /// s clamped to [0, length] (past an end: next_lanes).
  [[nodiscard]] Pose to_world(double s, double t) const;
};

/// A junction's <connection> (§10): from the incoming road into the connecting road.
struct Connection {
  std::string id;
  std::string incoming_road;
  std::string connecting_road;
  ContactPoint contact_point = ContactPoint::kStart;  // where the connecting road is entered
  std::vector<std::pair<int, int>> lane_links;        // (from on incoming, to on connecting)
  SourceLocation where;
};

struct Junction {
  std::string id;
  std::string name;
  std::vector<Connection> connections;
  SourceLocation where;
};

/// A world point in road coordinates.
struct RoadCoordinates {
  const Road* road = nullptr;
  double s = 0.0;
  double t = 0.0;  // from the reference line
  int lane_id = 0;
  double heading = 0.0;  // of the reference line at s
};

/// Where a lane leads past its road's end: the road and lane entered, the s where they are entered
/// (0 or the road's length, by the contact point) and the direction to drive on in.
struct LaneContinuation {
  const Road* road = nullptr;
  int lane_id = 0;
  double s = 0.0;
  Travel travel = Travel::kAlongS;
};

/// The roads and junctions of a file. The Road pointers it hands out (find_road, RoadCoordinates,
/// LaneContinuation) point into it: valid while it lives, also after it is moved (not into a copy).
class RoadNetwork {
 public:
  RoadNetwork() = default;
  /// Takes roads and junctions the reader has checked (every link refers to something present).
  RoadNetwork(std::string file, std::vector<Road> roads, std::vector<Junction> junctions);

  /// The file it was read from (for messages).
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] const std::vector<Road>& roads() const { return roads_; }
  [[nodiscard]] const std::vector<Junction>& junctions() const { return junctions_; }
  /// nullptr when there is none: a user file naming a missing road is the caller's InputError.
  [[nodiscard]] const Road* find_road(std::string_view id) const;
  [[nodiscard]] const Junction* find_junction(std::string_view id) const;

  /// road.to_world(s, t).
  [[nodiscard]] Pose road_to_world(const Road& road, double s, double t) const;
  /// The pose `offset` to the left of the lane's centre at s, heading along the reference line.
  [[nodiscard]] Pose lane_to_world(const Road& road, int lane_id, double s, double offset) const;
  /// The point in road coordinates on the road whose lanes hold it (the hint first, then the one
  /// nearest its reference line); std::nullopt when no road's lanes hold it.
  [[nodiscard]] std::optional<RoadCoordinates> world_to_road(double x, double y, const Road* hint = nullptr) const;

  /// Where `lane_id` of `road`, driven in `travel`, leads past the road's end (its successor for
  /// kAlongS, predecessor for kAgainstS): through a road link and the lane's link, or through the
  /// junction's connections from this road and their lane links. Empty at a dead end. Several in
  /// a junction (one per connection that takes the lane).
  [[nodiscard]] std::vector<LaneContinuation> next_lanes(const Road& road, int lane_id, Travel travel) const;

 private:
  std::string file_;
  std::vector<Road> roads_;
  std::vector<Junction> junctions_;
  std::unordered_map<std::string, std::size_t> road_index_;
  std::unordered_map<std::string, std::size_t> junction_index_;
  struct Box {  // a road's lanes lie inside (world x, y)
    double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  };
  std::vector<Box> boxes_;  // one per road
};

/// Reads an OpenDRIVE file: validates it against the embedded XSD when its version has one
/// (xml::validate), then reads it, checking every number (finite, lengths > 0, records in order) and
/// every reference (a missing road or junction is an InputError at the referring element).
/// Throws InputError with file:line:column.
[[nodiscard]] RoadNetwork load_opendrive(const std::filesystem::path& file);
[[nodiscard]] RoadNetwork parse_opendrive(const std::string& text, const std::string& file_name);

}  // namespace emrm::opendrive
