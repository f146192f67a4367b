// A cut-in exported by emrm (exchange::export_cell) imports again, and the player puts every actor
// where its exported timed polyline says at every sample.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "emrm/exchange/openscenario.hpp"
#include "emrm/openscenario/family.hpp"
#include "emrm/openscenario/player.hpp"
#include "emrm/openscenario/reader.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "scratch.hpp"

namespace emrm::openscenario {
namespace {

// The polyline's position at time t, by linear interpolation of its vertices (their closed form).
std::pair<double, double> at_time(const std::vector<PolylineVertex>& vertices, double t) {
  for (std::size_t k = 0; k + 1 < vertices.size(); ++k) {
    const double t0 = *vertices[k].time_s, t1 = *vertices[k + 1].time_s;
    if (t > t1 && k + 2 < vertices.size()) continue;
    const auto& a = std::get<WorldPosition>(vertices[k].position.kind);
    const auto& b = std::get<WorldPosition>(vertices[k + 1].position.kind);
    const double u = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
    return {a.x_m + u * (b.x_m - a.x_m), a.y_m + u * (b.y_m - a.y_m)};
  }
  const auto& only = std::get<WorldPosition>(vertices.front().position.kind);
  return {only.x_m, only.y_m};
}

TEST(ExportedScenario, ACutInExportedByEmrmPlaysItsOwnTrajectoriesBack) {
  const sim::SceneConfig config = sim::load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/cut_in/scene.yaml");
  sim::CellInput cell = sim::scenario_factors(config).defaults();
  cell[sim::kEgoSpeedFactor] = 100.0;
  cell[sim::kTtcFactor] = 1.5;
  const sim::CellResult result = sim::simulate_cell(config, cell, {});
  const exchange::EgoTrajectory trajectory{result.strategies.back().strategy, result.strategies.back().path};
  const auto dir = emrm::test::scratch_dir("openscenario", "exported_cut_in");
  const auto files = exchange::export_cell(dir, config, cell, &trajectory, {});
  const auto xosc = *std::find_if(files.begin(), files.end(), [](const auto& f) { return f.extension() == ".xosc"; });

  const Scenario scenario = load_openscenario(xosc);
  const Trajectories played = play(scenario, {.dt_s = 0.01, .duration_s = 20.0});
  int followed = 0;
  for (const Story& story : scenario.storyboard.stories)
    for (const Act& act : story.acts)
      for (const ManeuverGroup& group : act.groups)
        for (const Maneuver& maneuver : group.maneuvers)
          for (const Event& event : maneuver.events)
            for (const Action& action : event.actions) {
              const auto* follow = std::get_if<FollowTrajectoryAction>(&action.kind);
              if (follow == nullptr) continue;
              const auto& vertices = std::get<std::vector<PolylineVertex>>(follow->trajectory.shape);
              const std::string& actor = group.actors.front();
              ++followed;
              for (const Sample& s : played.at(actor)) {
                if (s.t_s < *vertices.front().time_s || s.t_s > *vertices.back().time_s) continue;
                const auto [x, y] = at_time(vertices, s.t_s);
                EXPECT_NEAR(s.x_m, x, 1e-6) << actor << " at " << s.t_s;
                EXPECT_NEAR(s.y_m, y, 1e-6) << actor << " at " << s.t_s;
              }
            }
  EXPECT_GE(followed, 2);  // the ego and the cutting car
}

// A cell exported with `emrm export` and imported again, in a scene with the same car, simulation
// and road edges, handed over where the export starts (its story's start, t = 0), gives the same
// outcome: the same initial gap, hazard mass, region and braking.
TEST(ExportedScenario, ACellExportedAndImportedAgainHasTheSameOutcome) {
  const Registration registration;
  const sim::SceneConfig original =
      sim::load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/highway_obstacle/scene.yaml");
  const sim::FactorTable factors = sim::scenario_factors(original);
  for (const auto& [speed_kph, ttc_s, obstacle] : {std::tuple{100.0, 1.2, "truck"}, std::tuple{80.0, 2.0, "deer"}}) {
    sim::CellInput cell = factors.defaults();
    cell[sim::kEgoSpeedFactor] = speed_kph;
    cell[sim::kTtcFactor] = ttc_s;
    cell[*factors.find("obstacle")] = factors[*factors.find("obstacle")].parse(obstacle);
    const auto dir = emrm::test::scratch_dir("openscenario", std::string("round_trip_") + obstacle);
    const auto files = exchange::export_cell(dir, original, cell, nullptr, {});
    const auto xosc = *std::find_if(files.begin(), files.end(), [](const auto& f) { return f.extension() == ".xosc"; });

    sim::SceneConfig imported = scene_of(xosc);
    EXPECT_TRUE(imported.openscenario.factors.empty());  // the export's parameters are only informational
    EXPECT_EQ(imported.ego.mass_kg, original.ego.mass_kg);
    imported.ego = original.ego;
    imported.simulation = original.simulation;
    imported.actuation = original.actuation;
    imported.severity = original.severity;
    imported.planner = original.planner;
    imported.safe_state = original.safe_state;
    imported.max_initial_distance_m = original.max_initial_distance_m;
    // The export starts at the hand-over: its story starts at t = 0.
    imported.openscenario.handover = load_openscenario(xosc).element_names().front();
    sim::CellInput again = sim::scenario_factors(imported).defaults();
    again[sim::kEgoSpeedFactor] = speed_kph;
    again[sim::kTtcFactor] = 10.0;
    again[sim::kFrictionFactor] = cell[sim::kFrictionFactor];

    const sim::Scene before(original, cell);
    const sim::Scene after(imported, again);
    ASSERT_TRUE(after.feasible()) << after.infeasible_reason();
    EXPECT_NEAR(after.initial_distance_m(), before.initial_distance_m(), 0.01) << obstacle;
    EXPECT_NEAR(after.hazard().body().mass_kg, before.hazard().body().mass_kg, 1e-9) << obstacle;
    const sim::CellResult a = sim::simulate_cell(original, cell, {});
    const sim::CellResult b = sim::simulate_cell(imported, again, {});
    EXPECT_EQ(b.region, a.region) << obstacle;
    ASSERT_EQ(a.strategies.front().strategy, "emergency_stop");
    ASSERT_EQ(b.strategies.front().strategy, "emergency_stop");
    EXPECT_EQ(b.strategies.front().avoided, a.strategies.front().avoided) << obstacle;
    EXPECT_NEAR(b.strategies.front().impact.impact_speed_mps, a.strategies.front().impact.impact_speed_mps, 0.3)
        << obstacle;
  }
}

}  // namespace
}  // namespace emrm::openscenario
