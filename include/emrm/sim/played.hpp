#pragma once

// A scenario played open loop — an imported OpenSCENARIO storyboard (docs/import.md) — laid out as
// one cell's scene: every road user's path in the world frame, sampled from the scenario's t = 0;
// the moment the threat appears (the ego's time to collision with another road user first falls to
// the cell's TTC); and from then on the other road users as actors on tracks (Track) in the road
// frame of a straight road, the ego's front bumper at x = 0.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/actor.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/road.hpp"

namespace emrm::sim {

/// One road user's path: its body and its box's centre, heading and speed at every step.
struct PlayedUser {
  ActorBody body;
  std::vector<Track::Sample> path;
};

/// Every road user's path, sampled every dt_s from the scenario's t = 0 (all paths equally long).
struct PlayedScenario {
  double dt_s = 0.01;
  PlayedUser ego;
  std::vector<PlayedUser> others;
};

/// A straight road in the world frame: its reference line through `origin` along `heading_rad`, and
/// the drivable band across it (`band`'s y is the offset from the line, positive to the left).
struct StraightRoad {
  core::Vec2 origin;
  double heading_rad = 0.0;
  Road band;
};

/// The most the ego's heading may differ from the road's at the threat onset: the scene starts it
/// along the road (Scene::ego_initial).
inline constexpr double kMaxOnsetHeading_rad = 0.02;

/// When the threat appears: the step at which the ego's time to collision with another road user
/// (both keeping their velocities, the boxes' swept overlap: core::time_to_overlap) first falls to
/// the cell's TTC, that road user (the hazard) and its TTC then.
struct Onset {
  std::size_t step = 0;
  std::size_t hazard = 0;  ///< in PlayedScenario::others
  double ttc_s = 0.0;
};

/// The first step at which the ego's time to collision with any other road user is at most `ttc_s`
/// (the nearest one is the hazard); none when it never is. The ego's box is `ego_length_m` ×
/// `ego_width_m` about its path.
[[nodiscard]] std::optional<Onset> threat_onset(const PlayedScenario& played, double ttc_s, double ego_length_m,
                                                double ego_width_m);

/// The hand-over at a given step (a storyboard element's start): the hazard is the road user with
/// the least TTC then, else (none on a collision course, ttc_s infinite) the nearest one.
[[nodiscard]] Onset onset_at(const PlayedScenario& played, std::size_t step, double ego_length_m, double ego_width_m);

/// The cell's layout from the onset on, in the road frame of `road` shifted along it so that the
/// ego's front bumper is at x = 0 at the onset: the hazard first, then the others in their order, on
/// tracks; the ego in its place across the road at its speed then. `ego_cg_to_front_m` places the
/// bumper. Without an onset (none given) the layout is infeasible, saying why (`why`).
[[nodiscard]] SceneLayout layout_from_onset(const PlayedScenario& played, const StraightRoad& road,
                                            const std::optional<Onset>& onset, double ego_length_m,
                                            const std::string& why = {});

}  // namespace emrm::sim
