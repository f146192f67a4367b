// Reading an OpenDRIVE file (docs/import.md, "OpenDRIVE"): validated against the embedded XSD where
// its version has one, then read with every number and reference checked; roads (§8), their plan
// view (§7), links (§8.2) and junctions (§10). Lanes: reader_lanes.cpp.

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "reader_parts.hpp"

namespace emrm::opendrive {
namespace {

using detail::number_within;

constexpr double kHuge_m = 1e7;              // no coordinate is further out (m)
constexpr double kLongestRoad_m = 1e5;       // no road is longer (m): the network samples each metre
constexpr double kMaxCurvature_per_m = 1e3;  // a turn radius of 1 mm
/// How far a spiral may turn (rad): a point on it costs a Gauss-Legendre panel per radian.
constexpr double kMostSpiralTurn_rad = 1e3;
/// How far the plan view's end may miss the road's length, and a geometry's start its predecessor's
/// end (m): the rounding of the files that write them.
constexpr double kJoinTolerance_m = 1e-2;

constexpr std::string_view kGeometryKinds = "line, arc, spiral, poly3, paramPoly3";

Shape read_shape(const xml::Element& geometry) {
  std::vector<xml::Element> kinds;
  for (const xml::Element& child : geometry.children())  // without the additional data any element may hold
    if (child.name() != "userData" && child.name() != "include" && child.name() != "dataQuality")
      kinds.push_back(child);
  if (kinds.size() != 1) geometry.fail("<geometry> needs exactly one of " + std::string(kGeometryKinds) + " inside");
  const xml::Element& k = kinds.front();
  const std::string_view name = k.name();
  const auto curvature = [&](std::string_view attribute) {
    return number_within(k, attribute, -kMaxCurvature_per_m, kMaxCurvature_per_m);
  };
  if (name == "line") return Line{};
  if (name == "arc") return Arc{curvature("curvature")};
  if (name == "spiral") {
    const Spiral spiral{curvature("curvStart"), curvature("curvEnd")};
    const double length = geometry.number("length");
    if (std::max(std::abs(spiral.curvature_start), std::abs(spiral.curvature_end)) * length > kMostSpiralTurn_rad)
      k.fail("<spiral> turns by more than " + std::to_string(kMostSpiralTurn_rad) + " rad over its length");
    return spiral;
  }
  if (name == "poly3") return Poly3{k.number("a"), k.number("b"), k.number("c"), k.number("d")};
  if (name == "paramPoly3") {
    const std::string range = k.attribute("pRange").value_or("normalized");
    if (range != "normalized" && range != "arcLength")
      k.fail("pRange", "<paramPoly3> pRange=\"" + range + "\": expected arcLength or normalized");
    return ParamPoly3{
        k.number("aU"), k.number("bU"), k.number("cU"),
        k.number("dU"), k.number("aV"), k.number("bV"),
        k.number("cV"), k.number("dV"), range == "arcLength" ? ParamRange::kArcLength : ParamRange::kNormalized};
  }
  k.fail("<" + std::string(name) + "> is not a supported geometry; expected one of " + std::string(kGeometryKinds));
}

ReferenceLine read_plan_view(const xml::Element& road, double length) {
  const auto plan_view = road.required_child("planView");
  const auto geometries = plan_view.children("geometry");
  if (geometries.empty()) plan_view.fail("<planView> needs a <geometry>");
  std::vector<Segment> segments;
  for (const xml::Element& g : geometries) {
    Segment segment{number_within(g, "s", 0.0, kLongestRoad_m),
                    number_within(g, "x", -kHuge_m, kHuge_m),
                    number_within(g, "y", -kHuge_m, kHuge_m),
                    g.number("hdg"),
                    g.number("length"),
                    read_shape(g)};
    if (!(segment.length > 0.0) || segment.length > kLongestRoad_m)
      g.fail("length", "<geometry> length=" + g.required("length") + ": expected a length > 0 and at most " +
                           std::to_string(kLongestRoad_m) + " m");
    const double expected_s = segments.empty() ? 0.0 : segments.back().s + segments.back().length;
    if (std::abs(segment.s - expected_s) > kJoinTolerance_m)
      g.fail("s", "<geometry> s=" + g.required("s") +
                      ": expected it to start where the previous one ends, at s=" + std::to_string(expected_s));
    segments.push_back(segment);
  }
  const double end = segments.back().s + segments.back().length;
  if (std::abs(end - length) > std::max(kJoinTolerance_m, 1e-6 * length))
    road.fail("length",
              "<road> length=" + road.required("length") + " but its <planView> ends at s=" + std::to_string(end));
  return ReferenceLine(std::move(segments));
}

ContactPoint read_contact_point(const xml::Element& e) {
  const std::string text = e.required("contactPoint");
  if (text == "start") return ContactPoint::kStart;
  if (text == "end") return ContactPoint::kEnd;
  e.fail("contactPoint", "<" + std::string(e.name()) + "> contactPoint=\"" + text + "\": expected start or end");
}

std::optional<RoadLink> read_road_link(const xml::Element& road, std::string_view which) {
  const auto link = road.child("link");
  if (!link) return std::nullopt;
  const auto e = link->child(which);
  if (!e) return std::nullopt;
  RoadLink result;
  result.where = e->where();
  const std::string type = e->required("elementType");
  if (type == "road") {
    result.type = ElementType::kRoad;
    result.contact_point = read_contact_point(*e);
  } else if (type == "junction") {
    result.type = ElementType::kJunction;
  } else {
    e->fail("elementType", "<" + std::string(which) + "> elementType=\"" + type + "\": expected road or junction");
  }
  result.id = e->required("elementId");
  return result;
}

TrafficRule read_rule(const xml::Element& road) {
  const std::string rule = road.attribute("rule").value_or("RHT");
  if (rule == "RHT") return TrafficRule::kRightHand;
  if (rule == "LHT") return TrafficRule::kLeftHand;
  road.fail("rule", "<road> rule=\"" + rule + "\": expected RHT or LHT");
}

Road read_road(const xml::Element& e) {
  Road road;
  road.where = e.where();
  road.id = e.required("id");
  road.name = e.attribute("name").value_or("");
  road.length = e.number("length");
  if (!(road.length > 0.0) || road.length > kLongestRoad_m)
    e.fail("length", "<road> length=" + e.required("length") + ": expected a length > 0 and at most " +
                         std::to_string(kLongestRoad_m) + " m");
  const std::string junction = e.required("junction");
  road.junction = junction == "-1" ? "" : junction;
  road.rule = read_rule(e);
  road.plan_view = read_plan_view(e, road.length);
  const auto lanes = e.required_child("lanes");
  road.lane_offsets = detail::read_lane_offsets(lanes, road.length);
  road.lane_sections = detail::read_lane_sections(lanes, road.length);
  road.predecessor = read_road_link(e, "predecessor");
  road.successor = read_road_link(e, "successor");
  return road;
}

Junction read_junction(const xml::Element& e) {
  Junction junction;
  junction.where = e.where();
  junction.id = e.required("id");
  junction.name = e.attribute("name").value_or("");
  for (const xml::Element& c : e.children("connection")) {
    Connection connection;
    connection.where = c.where();
    connection.id = c.required("id");
    connection.incoming_road = c.required("incomingRoad");
    // A direct junction (1.7) names the road it leads to linkedRoad.
    const auto connecting = c.attribute("connectingRoad");
    connection.connecting_road = connecting ? *connecting : c.attribute("linkedRoad").value_or("");
    if (connection.connecting_road.empty()) c.fail("<connection> needs the attribute connectingRoad");
    connection.contact_point = read_contact_point(c);
    for (const xml::Element& link : c.children("laneLink"))
      connection.lane_links.emplace_back(detail::integer(link, "from"), detail::integer(link, "to"));
    junction.connections.push_back(std::move(connection));
  }
  return junction;
}

/// Every id a road or junction names exists (an InputError at the element that names it).
void check_references(const RoadNetwork& network, const xml::Element& root) {
  const auto roads = root.children("road");
  for (std::size_t i = 0; i < network.roads().size(); ++i) {
    const Road& road = network.roads()[i];
    if (!road.junction.empty() && network.find_junction(road.junction) == nullptr)
      roads[i].fail("junction", "<road id=\"" + road.id + "\"> is in junction \"" + road.junction +
                                    "\", which the file does not have");
    for (const auto* link : {&road.predecessor, &road.successor}) {
      if (!*link) continue;
      const bool found = (*link)->type == ElementType::kRoad ? network.find_road((*link)->id) != nullptr
                                                             : network.find_junction((*link)->id) != nullptr;
      if (!found)
        throw InputError((*link)->where, std::string("the link names the ") +
                                             ((*link)->type == ElementType::kRoad ? "road" : "junction") + " \"" +
                                             (*link)->id + "\", which the file does not have");
    }
  }
  for (const Junction& junction : network.junctions())
    for (const Connection& c : junction.connections)
      for (const std::string* id : {&c.incoming_road, &c.connecting_road})
        if (network.find_road(*id) == nullptr)
          throw InputError(
              c.where, "<connection id=\"" + c.id + "\"> names the road \"" + *id + "\", which the file does not have");
}

RoadNetwork read(const xml::Document& document) {
  xml::validate(document, xml::Schema::kOpenDrive);
  const xml::Element root = document.root();
  if (root.name() != "OpenDRIVE") root.fail("expected <OpenDRIVE> as the root element");
  std::vector<Road> roads;
  std::unordered_set<std::string> road_ids;
  for (const xml::Element& e : root.children("road")) {
    roads.push_back(read_road(e));
    if (!road_ids.insert(roads.back().id).second) e.fail("id", "a second road with the id \"" + roads.back().id + "\"");
  }
  if (roads.empty()) root.fail("<OpenDRIVE> needs a <road>");
  std::vector<Junction> junctions;
  std::unordered_set<std::string> junction_ids;
  for (const xml::Element& e : root.children("junction")) {
    junctions.push_back(read_junction(e));
    if (!junction_ids.insert(junctions.back().id).second)
      e.fail("id", "a second junction with the id \"" + junctions.back().id + "\"");
  }
  RoadNetwork network(document.file(), std::move(roads), std::move(junctions));
  check_references(network, root);
  return network;
}

}  // namespace

RoadNetwork load_opendrive(const std::filesystem::path& file) { return read(xml::Document::load(file)); }

RoadNetwork parse_opendrive(const std::string& text, const std::string& file_name) {
  return read(xml::Document::parse(text, file_name));
}

}  // namespace emrm::opendrive
