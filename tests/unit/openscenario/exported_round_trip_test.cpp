// A cut-in exported by emrm (exchange::export_cell) imports again, and the player puts every actor
// where its exported timed polyline says at every sample.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "emrm/exchange/openscenario.hpp"
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

}  // namespace
}  // namespace emrm::openscenario
