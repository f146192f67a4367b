// The player's loop (player.hpp): esmini's ScenarioEngine::step at a fixed step. Each step: the
// triggers are evaluated on the states at its start time, the running actions stepped (they may
// move their entity), the time advanced, then every entity no action moved goes along its lane at
// its speed (esmini's default controller). docs/import.md, "The player's step".

#include "emrm/openscenario/player.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "emrm/openscenario/reader.hpp"
#include "runtime.hpp"

namespace emrm::openscenario {
namespace {

using detail::EntityState;
using detail::kSmall;
using detail::World;

// esmini's defaultController: s advances by speed * dt in the driving direction, keeping the lane
// and its offset, into the linked road past an end; without a lane, straight on.
void default_controller(const World& world, EntityState& e, double dt_s) {
  if (e.moved_longitudinally || std::fabs(e.speed_mps) < kSmall) return;
  const double step_m = e.speed_mps * dt_s;
  if (e.on_lane) {
    const LaneStep moved = world.roads->step_along(e.lane, s_step_for(*world.roads, e.lane, step_m) * e.direction);
    if (moved.direction_flipped) e.direction = -e.direction;
    e.lane = moved.to;
    if (moved.end_of_road) e.speed_mps = 0.0;
    if (!moved.end_of_road) {
      e.end_of_road_since_s.reset();
    } else if (!e.end_of_road_since_s) {
      e.end_of_road_since_s = world.time_s;  // the time after the step, as esmini stamps it
    }
    world.update_pose(e);
  } else {
    e.pose.x_m += step_m * std::cos(e.pose.heading_rad);
    e.pose.y_m += step_m * std::sin(e.pose.heading_rad);
  }
}

// esmini's state check after each step: an entity beyond its road's lanes (or on no road's lanes)
// is off road from the time after the step.
void check_off_road(const World& world, EntityState& e) {
  if (world.roads == nullptr) return;
  std::optional<LaneCoord> at =
      e.on_lane ? std::optional<LaneCoord>(e.lane) : world.roads->world_to_lane(e.pose.x_m, e.pose.y_m, &e.lane);
  const bool off =
      !at || world.roads->off_road(at->road_id, at->s_m,
                                   world.roads->lane_center_t(at->road_id, at->lane_id, at->s_m) + at->offset_m);
  if (!off) {
    e.off_road_since_s.reset();
  } else if (!e.off_road_since_s) {
    e.off_road_since_s = world.time_s;
  }
}

Sample sample_of(const EntityState& e, double t_s) {
  return {t_s, e.pose.x_m, e.pose.y_m, std::remainder(e.pose.heading_rad, 2.0 * std::numbers::pi), e.speed_mps};
}

Trajectories run(const Scenario& scenario, const PlayOptions& options) {
  if (!(options.dt_s > 0.0) || !(options.duration_s >= 0.0))
    throw InputError({}, "play: expected dt_s > 0 and duration_s >= 0");
  World world;
  world.scenario = &scenario;
  world.roads = scenario.roads.get();
  if (options.element_started) world.element_started = &options.element_started;
  for (const Parameter& p : scenario.parameters) world.parameters[p.name] = p.value;
  for (const Entity& entity : scenario.entities) {
    EntityState state;
    state.spec = &entity;
    world.entities.push_back(state);
  }
  detail::StoryboardRuntime storyboard(scenario, world);

  Trajectories out;
  StepStates states;
  const auto record = [&](double t_s) {
    for (const EntityState& e : world.entities) {
      const Sample s = sample_of(e, t_s);
      out[e.spec->name].push_back(s);
      states[e.spec->name] = s;
    }
  };
  // esmini's first frame has no duration: Init and the triggers at t = 0, nothing moves.
  storyboard.start();
  storyboard.step(0.0, 0.0);
  record(0.0);
  if (options.stop_at && options.stop_at(0.0, states)) return out;
  const auto steps = static_cast<long>(std::floor(options.duration_s / options.dt_s + 1e-9));
  for (long k = 0; k < steps; ++k) {
    const double t_s = static_cast<double>(k) * options.dt_s;
    for (EntityState& e : world.entities) e.moved_longitudinally = false;
    world.time_s = t_s;
    if (!storyboard.step(t_s, options.dt_s)) break;  // the StopTrigger ends the play (esmini quits)
    const double next_t = static_cast<double>(k + 1) * options.dt_s;
    world.time_s = next_t;
    for (EntityState& e : world.entities) default_controller(world, e, options.dt_s);
    for (EntityState& e : world.entities) check_off_road(world, e);
    record(next_t);
    if (options.stop_at && options.stop_at(next_t, states)) break;
  }
  return out;
}

}  // namespace

Trajectories play(const Scenario& scenario, const PlayOptions& options) {
  if (options.overrides.empty()) return run(scenario, options);
  ParameterOverrides merged = scenario.overrides;
  for (const auto& [name, value] : options.overrides) merged[name] = value;
  return run(load_openscenario(scenario.file, {.overrides = merged, .ego = scenario.ego}), options);
}

}  // namespace emrm::openscenario
