#pragma once

// The road of a scene (docs/families.md, "The road"): the drivable area, a straight band along x in
// the road frame (x along the road, the ego driving +x; y to the left), and what lies beyond each of
// its edges.

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "emrm/core/enum_names.hpp"

namespace emrm::sim {

/// What lies beyond an edge of the drivable area (docs/physics.md, "Road departure").
enum class Roadside : std::uint8_t {
  kBarrier,  ///< a rigid wall or guardrail: a departure is an impact against an immovable body
  kOpen,     ///< clear, traversable ground: a departure hits nothing (Δv 0) and scores L4
  /// a slope down from the edge: traversable when no steeper than the critical slope, else the car
  /// rolls over (the roadside's slope: Road::right_slope_h, left_slope_h)
  kEmbankment,
};

/// The drivable area y ∈ [min_y_m, max_y_m] and the roadside beyond each edge.
struct Road {
  double min_y_m = 0.0;  ///< the right edge
  double max_y_m = 0.0;  ///< the left edge
  Roadside right = Roadside::kBarrier;
  Roadside left = Roadside::kBarrier;
  /// An embankment's slope beyond each edge: its horizontal run per unit of drop (1V:2H is 2).
  double right_slope_h = 0.0;
  double left_slope_h = 0.0;

  [[nodiscard]] double width_m() const noexcept { return max_y_m - min_y_m; }
  /// The roadside beyond the right edge (`right_edge`) or the left one.
  [[nodiscard]] Roadside beyond(bool right_edge) const noexcept { return right_edge ? right : left; }
  /// The slope beyond that edge (an embankment's).
  [[nodiscard]] double slope_h(bool right_edge) const noexcept { return right_edge ? right_slope_h : left_slope_h; }
};

}  // namespace emrm::sim

template <>
struct emrm::core::EnumNames<emrm::sim::Roadside> {
  static constexpr std::array<std::pair<emrm::sim::Roadside, std::string_view>, 3> kNames{{
      {emrm::sim::Roadside::kBarrier, "barrier"},
      {emrm::sim::Roadside::kOpen, "open"},
      {emrm::sim::Roadside::kEmbankment, "embankment"},
  }};
};
