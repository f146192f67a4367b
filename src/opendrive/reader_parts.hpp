#pragma once

// The OpenDRIVE reader's parts shared by reader.cpp (roads, links, junctions) and reader_lanes.cpp
// (lane offsets, sections and lanes). Not a public header.

#include <cmath>
#include <string>
#include <vector>

#include "emrm/opendrive/road_network.hpp"
#include "emrm/xml/document.hpp"

namespace emrm::opendrive::detail {

/// A whole number attribute (lane ids): InputError at the attribute otherwise.
inline int integer(const xml::Element& e, std::string_view name) {
  const double value = e.number(name);
  if (value != std::floor(value) || std::abs(value) > 1e6)
    e.fail(name, "<" + std::string(e.name()) + "> attribute " + std::string(name) + ": expected a whole number");
  return static_cast<int>(value);
}

/// A number attribute within [lo, hi]: InputError at the attribute otherwise.
inline double number_within(const xml::Element& e, std::string_view name, double lo, double hi) {
  const double value = e.number(name);
  if (value < lo || value > hi)
    e.fail(name, "<" + std::string(e.name()) + "> attribute " + std::string(name) + "=" + e.required(name) +
                     ": expected a value in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return value;
}

/// The lane offsets of a road of `length` (<laneOffset> under <lanes>).
std::vector<Cubic> read_lane_offsets(const xml::Element& lanes, double length);
/// The lane sections of a road of `length` (<laneSection> under <lanes>), each checked.
std::vector<LaneSection> read_lane_sections(const xml::Element& lanes, double length);

}  // namespace emrm::opendrive::detail
