// Reading a road's <lanes>: lane offsets (ASAM OpenDRIVE 1.7 §9.3), lane sections (§9.2) and their
// lanes with types, widths, borders (§9.5) and lane links (§9.4). What is ignored: docs/import.md.

#include <algorithm>
#include <cmath>
#include <limits>

#include "reader_parts.hpp"

namespace emrm::opendrive::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// How far a record may start past its section's end (m): rounding in the files that write it.
constexpr double kStartTolerance_m = 1e-3;
// How far below 0 a width may dip (m): the rounding of a lane that narrows to nothing.
constexpr double kNegativeWidthTolerance_m = 1e-3;

/// A cubic record of `e` with its start at `base` + the attribute `start_name` (s or sOffset).
Cubic read_cubic(const xml::Element& e, std::string_view start_name, double base, double max_start) {
  return {base + number_within(e, start_name, 0.0, max_start), e.number("a"), e.number("b"), e.number("c"),
          e.number("d")};
}

/// Records in the order of their starts (a record out of order is an error at it).
std::vector<Cubic> read_records(const std::vector<xml::Element>& elements, std::string_view start_name, double base,
                                double max_start) {
  std::vector<Cubic> records;
  for (const xml::Element& e : elements) {
    records.push_back(read_cubic(e, start_name, base, max_start));
    if (records.size() > 1 && records.back().s_start < records[records.size() - 2].s_start)
      e.fail(start_name, "<" + std::string(e.name()) + "> records must be in increasing " + std::string(start_name));
  }
  return records;
}

/// The least value of a record over [from, to]: at the ends or where its derivative vanishes.
double least_value(const Cubic& record, double from, double to) {
  double least = std::min(record.at(from), record.at(to));
  // b + 2c x + 3d x² = 0 for x = ds
  const double qa = 3.0 * record.d;
  const double qb = 2.0 * record.c;
  const double qc = record.b;
  std::vector<double> roots;
  if (qa == 0.0) {
    if (qb != 0.0) roots.push_back(-qc / qb);
  } else if (const double disc = qb * qb - 4.0 * qa * qc; disc >= 0.0) {
    roots.push_back((-qb + std::sqrt(disc)) / (2.0 * qa));
    roots.push_back((-qb - std::sqrt(disc)) / (2.0 * qa));
  }
  for (const double ds : roots)
    if (record.s_start + ds > from && record.s_start + ds < to) least = std::min(least, record.at(record.s_start + ds));
  return least;
}

/// Widths must not go negative over their range (up to the next record or the section's end).
void check_widths(const std::vector<xml::Element>& elements, const std::vector<Cubic>& widths, double section_end) {
  for (std::size_t i = 0; i < widths.size(); ++i) {
    const double to = i + 1 < widths.size() ? widths[i + 1].s_start : section_end;
    if (!std::isfinite(to) || to < widths[i].s_start) continue;
    if (const double least = least_value(widths[i], widths[i].s_start, to); least < -kNegativeWidthTolerance_m)
      elements[i].fail("a", "<width> makes the lane's width negative (" + std::to_string(least) +
                                " m) before s=" + std::to_string(to) + ": expected a width >= 0");
  }
}

std::vector<int> linked_ids(const xml::Element& lane, std::string_view which) {
  std::vector<int> ids;
  if (const auto link = lane.child("link"))
    for (const xml::Element& e : link->children(which)) ids.push_back(integer(e, "id"));
  return ids;
}

Lane read_lane(const xml::Element& e, double section_s, double section_length) {
  const double max_start = section_length + kStartTolerance_m;
  Lane lane;
  lane.where = e.where();
  lane.id = integer(e, "id");
  const std::string type = e.required("type");
  const auto known = lane_type_named(type);
  if (!known) e.fail("type", "<lane> type \"" + type + "\" is not a lane type; expected one of " + lane_type_names());
  lane.type = *known;
  const auto widths = e.children("width");
  lane.widths = read_records(widths, "sOffset", section_s, max_start);
  check_widths(widths, lane.widths, section_s + section_length);
  lane.borders = read_records(e.children("border"), "sOffset", section_s, max_start);
  lane.predecessors = linked_ids(e, "predecessor");
  lane.successors = linked_ids(e, "successor");
  return lane;
}

/// The lanes of one side, checked to be numbered 1, 2, ... (or -1, -2, ...) outwards, each with a width.
std::vector<Lane> read_side(const xml::Element& section, std::string_view side_name, int sign, double section_s,
                            double section_length) {
  std::vector<Lane> lanes;
  const auto side = section.child(side_name);
  if (!side) return lanes;
  const auto elements = side->children("lane");
  for (const xml::Element& e : elements) {
    lanes.push_back(read_lane(e, section_s, section_length));
    const Lane& lane = lanes.back();
    if (lane.id * sign <= 0)
      e.fail("id",
             "a lane in <" + std::string(side_name) + "> needs a " + (sign > 0 ? "positive" : "negative") + " id");
    if (lane.widths.empty() && lane.borders.empty()) e.fail("<lane> needs a <width> or a <border> record");
  }
  std::sort(lanes.begin(), lanes.end(), [](const Lane& a, const Lane& b) { return std::abs(a.id) < std::abs(b.id); });
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    if (std::abs(lanes[i].id) != static_cast<int>(i) + 1)
      throw InputError(lanes[i].where, "the lanes of <" + std::string(side_name) + "> must be numbered " +
                                           (sign > 0 ? "1, 2, ..." : "-1, -2, ...") + " without gaps or repeats; " +
                                           "lane " + std::to_string(lanes[i].id) + " is out of place");
  }
  return lanes;
}

}  // namespace

std::vector<Cubic> read_lane_offsets(const xml::Element& lanes, double length) {
  return read_records(lanes.children("laneOffset"), "s", 0.0, length);
}

std::vector<LaneSection> read_lane_sections(const xml::Element& lanes, double length) {
  std::vector<LaneSection> sections;
  const auto elements = lanes.children("laneSection");
  if (elements.empty()) lanes.fail("<lanes> needs a <laneSection>");
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const xml::Element& e = elements[i];
    LaneSection section;
    section.s = number_within(e, "s", 0.0, length);
    if (i == 0 && section.s != 0.0) e.fail("s", "the first <laneSection> must start at s=\"0\"");
    if (i > 0 && section.s < sections.back().s) e.fail("s", "<laneSection> records must be in increasing s");
    section.single_sided = e.attribute("singleSided").value_or("false") == "true";
    const double end = i + 1 < elements.size() ? elements[i + 1].optional_number("s").value_or(length) : length;
    const double section_length = std::max(0.0, end - section.s);
    section.left = read_side(e, "left", 1, section.s, section_length);
    section.right = read_side(e, "right", -1, section.s, section_length);
    const auto center = e.required_child("center");
    const auto center_lanes = center.children("lane");
    if (center_lanes.size() != 1) center.fail("<center> needs exactly one <lane id=\"0\">");
    section.center = read_lane(center_lanes.front(), section.s, kInfinity);
    if (section.center.id != 0) center_lanes.front().fail("id", "the centre lane's id must be 0");
    section.center.widths.clear();  // the centre lane has no width (§9.5.1)
    section.center.borders.clear();
    sections.push_back(std::move(section));
  }
  return sections;
}

}  // namespace emrm::opendrive::detail
