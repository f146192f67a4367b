#pragma once

// OpenDRIVE 1.6 road network of a scenario cell (docs/openscenario.md): the T-junction — the main
// road before and after it, the side road the truck comes down, and the junction's connecting
// roads. Coordinates are emrm's road frame (x along the main road, y to the left, the ego's front
// bumper at x = 0 when the hazard appears).

#include <string>

#include "emrm/sim/scene.hpp"

namespace emrm::exchange {

/// The road network of one cell; everything in metres in the road frame. The side road joins from
/// the left (y > 0) with its centre line at `side_road_x_m`; the truck drives down its left lane.
struct JunctionLayout {
  double main_start_x_m = 0.0;    ///< start of road 1 (incoming main road)
  double junction_min_x_m = 0.0;  ///< road 1 ends, the junction begins
  double junction_max_x_m = 0.0;  ///< the junction ends, road 2 begins
  double main_end_x_m = 0.0;      ///< end of road 2
  double side_road_x_m = 0.0;     ///< the side road's reference line
  double side_road_start_y_m = 0.0;
  double side_road_length_m = 0.0;
  double reference_line_y_m = 0.0;  ///< the main road's reference line (the centre lane)
  int left_lanes = 0;               ///< driving lanes left of the reference line (ids 1…)
  int right_lanes = 0;              ///< driving lanes right of it (ids −1…), then the shoulder
};
[[nodiscard]] JunctionLayout junction_layout(const sim::SceneConfig& config, const sim::CellInput& cell);

/// The T-junction of a cell as an OpenDRIVE 1.6 document.
[[nodiscard]] std::string opendrive_xml(const sim::SceneConfig& config, const sim::CellInput& cell);

/// The straight road of a cell of any other family as an OpenDRIVE 1.6 document: one road along x
/// from before the ego's start to well past the hazard, its lanes the family's (sim::RoadLane), the
/// reference line between the ego's direction (right of it) and the oncoming lanes.
[[nodiscard]] std::string straight_road_xml(const sim::SceneConfig& config, const sim::CellInput& cell);

}  // namespace emrm::exchange
