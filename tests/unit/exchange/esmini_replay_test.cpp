// The export replayed the way esmini replays it, and judged by `emrm assess --format esmini`
// (docs/openscenario.md, "esmini"): emrm's tests do not run esmini (CI cannot fetch it), so this
// file replays an exported scenario as esmini 3.6 does, from its source, and checks that assess
// gives the simulated outcome of every strategy. What the replay reproduces, each of which once
// changed outcomes:
//
// - frames on the fixed time step from t = 0, the first frame logged twice; the storyboard stops
//   at the first frame at or after its StopTrigger's time (esmini's time rules have 1e-6 s slack);
// - an entity on a timed trajectory is put where the polyline is at each frame's time, with the
//   speed of its reference point (the rear axle) over the step just taken (a backward difference),
//   except on the frame that passes the trajectory's last vertex: that frame keeps the previous
//   speed and moves on by it along the last vertex's heading (FollowTrajectoryAction::Move, Step);
// - the heading interpolated linearly along each segment when the entity has the property
//   plineInterpolation=segment, else (followingMode "position") blended from the previous vertex:
//   half a step late, snapping to the last vertex's heading at the end;
// - a truck braked by a SpeedAction at a rate moved by semi-implicit Euler (the new speed times the
//   step), one on a timed trajectory put on it;
// - `wheel_angle` esmini's kinematic estimate atan(wheelbase · heading rate / speed);
// - headings in [0, 2π), tilted by 1e-7 rad as any measured heading is, and dat2csv's decimals.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "emrm/exchange/assess.hpp"
#include "emrm/exchange/openscenario.hpp"
#include "emrm/sim/simulate.hpp"
#include "exchange/xml_support.hpp"
#include "test_scale.hpp"

namespace emrm::exchange {
namespace esmini_replay_test {

using testing::Document;

constexpr double kKphPerMps = 3.6;
constexpr double kEsminiSlack_s = 1e-6;  // esmini's SMALL_NUMBER in its time comparisons

struct Vertex {
  double t_s = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double h_rad = 0.0;
};

// A timed polyline as esmini evaluates it: position linear in time along each segment.
struct Polyline {
  std::vector<Vertex> vertices;

  [[nodiscard]] std::size_t segment(double t) const {
    std::size_t i = 0;
    while (i + 2 < vertices.size() && t > vertices[i + 1].t_s) ++i;
    return i;
  }
  [[nodiscard]] Vertex at(double t) const {
    const double end = vertices.back().t_s;
    t = std::clamp(t, vertices.front().t_s, end);
    const std::size_t i = segment(t);
    const Vertex& a = vertices[i];
    const Vertex& b = vertices[i + 1];
    const double u = b.t_s > a.t_s ? (t - a.t_s) / (b.t_s - a.t_s) : 1.0;
    return {t, a.x_m + u * (b.x_m - a.x_m), a.y_m + u * (b.y_m - a.y_m), a.h_rad + u * (b.h_rad - a.h_rad)};
  }
  // The distance along the polyline to its point at time t.
  [[nodiscard]] double s_at(double t) const {
    t = std::clamp(t, vertices.front().t_s, vertices.back().t_s);
    const std::size_t i = segment(t);
    double s = 0.0;
    for (std::size_t k = 0; k < i; ++k)
      s += std::hypot(vertices[k + 1].x_m - vertices[k].x_m, vertices[k + 1].y_m - vertices[k].y_m);
    const Vertex p = at(t);
    return s + std::hypot(p.x_m - vertices[i].x_m, p.y_m - vertices[i].y_m);
  }
};

std::string of_entity(const std::string& entity) {
  return "//ManeuverGroup[Actors/EntityRef/@entityRef='" + entity + "']";
}

Polyline polyline_of(const Document& doc, const std::string& entity) {
  const std::string v = of_entity(entity) + "//Polyline/Vertex";
  const auto ts = doc.all(v + "/@time");
  const auto xs = doc.all(v + "/Position/WorldPosition/@x");
  const auto ys = doc.all(v + "/Position/WorldPosition/@y");
  const auto hs = doc.all(v + "/Position/WorldPosition/@h");
  Polyline p;
  for (std::size_t k = 0; k < ts.size(); ++k)
    p.vertices.push_back({std::stod(ts[k]), std::stod(xs[k]), std::stod(ys[k]), std::stod(hs[k])});
  return p;
}

// One entity's motion, frame by frame.
class Mover {
 public:
  Mover(const Document& doc, const std::string& entity, double dt_s) : dt_s_(dt_s) {
    const std::string init = "/OpenSCENARIO/Storyboard/Init/Actions/Private[@entityRef='" + entity + "']/PrivateAction";
    pose_ = {0.0, doc.number(init + "/TeleportAction/Position/WorldPosition/@x"),
             doc.number(init + "/TeleportAction/Position/WorldPosition/@y"),
             doc.number(init + "/TeleportAction/Position/WorldPosition/@h")};
    speed_ = doc.number(init + "/LongitudinalAction/SpeedAction/SpeedActionTarget/AbsoluteTargetSpeed/@value");
    path_ = polyline_of(doc, entity);
    segment_headings_ =
        !doc.all("//ScenarioObject[@name='" + entity + "']//Property[@name='plineInterpolation'][@value='segment']")
             .empty();
    const auto rate = doc.all(of_entity(entity) + "//SpeedActionDynamics[@dynamicsDimension='rate']/@value");
    if (!rate.empty()) brake_mps2_ = std::stod(rate.front());
  }

  [[nodiscard]] const Vertex& pose() const { return pose_; }
  [[nodiscard]] double speed() const { return speed_; }

  // From the frame at t − dt to the frame at t.
  void step(double t) {
    const double previous_h = pose_.h_rad;
    if (!path_.vertices.empty() && !ended_) {
      const double end = path_.vertices.back().t_s;
      if (t < end + kEsminiSlack_s) {
        const Vertex p = path_.at(t);
        speed_ = std::abs(path_.s_at(t) - path_.s_at(t - dt_s_)) / dt_s_;
        double h = p.h_rad;
        if (!segment_headings_ && t < end - kEsminiSlack_s) h = 0.5 * (path_.at(t - dt_s_).h_rad + p.h_rad);
        pose_ = {t, p.x_m, p.y_m, h};
      } else {
        // Past the last vertex: there, then on by the remaining time at the previous frame's speed
        // along the last heading; the speed is not updated.
        const Vertex last = path_.vertices.back();
        const double on = (t - end) * speed_;
        pose_ = {t, last.x_m + on * std::cos(last.h_rad), last.y_m + on * std::sin(last.h_rad), last.h_rad};
      }
      if (t > end - kEsminiSlack_s) ended_ = true;
    } else {
      // A SpeedAction at a rate, or the speed kept: the new speed times the step.
      if (brake_mps2_ > 0.0) speed_ = std::max(speed_ - brake_mps2_ * dt_s_, 0.0);
      pose_ = {t, pose_.x_m + speed_ * dt_s_ * std::cos(pose_.h_rad),
               pose_.y_m + speed_ * dt_s_ * std::sin(pose_.h_rad), pose_.h_rad};
    }
    heading_rate_ = (pose_.h_rad - previous_h) / dt_s_;
  }
  [[nodiscard]] double heading_rate() const { return heading_rate_; }

 private:
  double dt_s_;
  Vertex pose_;
  double speed_ = 0.0;
  Polyline path_;
  bool segment_headings_ = false;
  bool ended_ = false;
  double brake_mps2_ = 0.0;
  double heading_rate_ = 0.0;
};

struct Recording {
  int decimals = 9;
  double heading_tilt_rad = 1e-7;
};

// esmini --headless --fixed_timestep dt --osc xosc --record sim.dat, then dat2csv sim.dat.
std::string replay(const std::string& xosc, const sim::SceneConfig& config, const Recording& how) {
  const Document doc(xosc);
  const double dt = config.simulation.dt_s;
  const double stop = doc.number("/OpenSCENARIO/Storyboard/StopTrigger//SimulationTimeCondition/@value");
  Mover ego(doc, kEgoEntity, dt);
  Mover truck(doc, kTruckEntity, dt);
  std::string out =
      "Version: 3, OpenDRIVE: tjunction.xodr, 3DModel: \n"
      "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n";
  const int p = how.decimals;
  const auto row = [&](int id, const char* name, const Mover& m, double tilt, double wheel) {
    const double h = std::fmod(m.pose().h_rad + tilt + 4.0 * std::numbers::pi, 2.0 * std::numbers::pi);
    out += fmt::format(
        "{:.{}f}, {}, {}, {:.{}f}, {:.{}f}, {:.{}f}, {:.{}f}, {:.{}f}, {:.{}f}, {:.{}f}, {:.{}f}, {:.{}f}\n",
        m.pose().t_s, p, id, name, m.pose().x_m, p, m.pose().y_m, p, 0.0, p, h, p, 0.0, p, 0.0, p, m.speed(), p, wheel,
        p, 0.0, p);
  };
  const auto frame = [&] {
    const double wheel = std::atan2(ego.heading_rate() * config.ego.wheelbase_m(), std::max(ego.speed(), 1e-9));
    row(0, kEgoEntity, ego, how.heading_tilt_rad, wheel);
    row(1, kTruckEntity, truck, -how.heading_tilt_rad, 0.0);
  };
  frame();
  frame();
  for (int k = 1; static_cast<double>(k - 1) * dt < stop - kEsminiSlack_s; ++k) {
    const double t = static_cast<double>(k) * dt;
    ego.step(t);
    truck.step(t);
    frame();
  }
  return out;
}

struct Expected {
  bool avoided = false;
  bool contact = false;
  bool road_departure = false;
  sim::ImpactAssessment impact;
};

// Whether assess gives the simulated outcome; a message saying how it differs otherwise.
std::string mismatch(const Expected& e, const Assessment& a) {
  const double dv = std::abs(a.impact.delta_v_mps - e.impact.delta_v_mps) * kKphPerMps;
  const double speed = std::abs(a.impact.impact_speed_mps - e.impact.impact_speed_mps) * kKphPerMps;
  if (a.avoided == e.avoided && a.contact == e.contact && a.road_departure == e.road_departure &&
      a.impact.loss_level == e.impact.loss_level && dv <= 0.1 && speed <= 0.1)
    return "";
  return fmt::format(
      "simulated avoided {} contact {} departure {} L{} Δv {:.2f} impact {:.2f}; assessed avoided {} "
      "contact {} departure {} L{} Δv {:.2f} impact {:.2f} ({})",
      e.avoided, e.contact, e.road_departure, e.impact.loss_level, e.impact.delta_v_mps * kKphPerMps,
      e.impact.impact_speed_mps * kKphPerMps, a.avoided, a.contact, a.road_departure, a.impact.loss_level,
      a.impact.delta_v_mps * kKphPerMps, a.impact.impact_speed_mps * kKphPerMps, safe_state_name(a.safe_state));
}

// Every strategy's executed trajectory, and the no-action run, of `cell` exported, replayed and
// judged; the number of runs and the messages of those that differ.
struct Tally {
  int runs = 0;
  int contacts = 0;
  int avoided = 0;
  std::vector<std::string> mismatches;
};

void replay_cell(const sim::SceneConfig& config, const sim::TJunctionCell& cell, const Recording& how, Tally& tally) {
  const sim::CellResult result = sim::simulate_cell(config, cell, {});
  const std::string where = fmt::format("cell {} km/h, TTC {} s, mu {}, passage {} m, truck {} km/h", cell.speed_kph,
                                        cell.ttc_s, cell.mu, cell.passage_m, cell.truck_speed_kph);
  const auto judge = [&](const std::string& xosc, const Expected& e, const std::string& what) {
    const auto recorded = parse_trajectory_csv(replay(xosc, config, how), "sim.csv", TrajectoryFormat::kEsmini, config);
    EXPECT_TRUE(recorded.has_truck) << what;
    const std::string m = mismatch(e, assess(config, cell, recorded));
    if (!m.empty()) tally.mismatches.push_back(where + ", " + what + ": " + m);
    ++tally.runs;
    tally.contacts += e.contact ? 1 : 0;
    tally.avoided += e.avoided ? 1 : 0;
  };
  for (const auto& o : result.strategies) {
    if (o.path.size() < 2) continue;
    const EgoTrajectory trajectory{o.strategy, o.path};
    judge(openscenario_xml(config, cell, &trajectory, {}), {o.avoided, o.contact, o.road_departure, o.impact},
          o.strategy);
  }
  const bool hit = result.unmitigated.impact_speed_mps > 0.0;
  judge(openscenario_xml(config, cell, nullptr, {}), {!hit, hit, false, result.unmitigated}, "no action");
}

std::string report(const Tally& t) {
  std::string out = fmt::format("{} of {} runs differ:\n", t.mismatches.size(), t.runs);
  for (const auto& m : t.mismatches) out += "  " + m + "\n";
  return out;
}

// Cells over every outcome the simulator gives: stops short of the truck, dodges past it and
// stabilised, contacts straight into its side (faces parallel) and at a corner, grazing contacts
// within centimetres of a miss, road departures, drifts, and a no-action run that passes.
std::vector<sim::TJunctionCell> outcome_cells() {
  return {{30, 0.4, 0.3, 2.0, 0},  {30, 2.0, 1.0, 3.5, 20}, {40, 0.8, 0.3, 3.5, 20}, {50, 1.2, 0.8, 3.0, 10},
          {50, 0.8, 0.6, 2.0, 0},  {60, 1.2, 0.6, 2.0, 0},  {65, 1.0, 0.5, 2.0, 20}, {72, 0.8, 0.6, 2.5, 20},
          {72, 0.4, 0.6, 3.5, 20}, {72, 0.4, 0.3, 3.0, 10}, {35, 2.0, 0.4, 2.8, 8},  {45, 1.6, 0.3, 2.5, 5}};
}

TEST(EsminiReplay, EveryStrategyAndTheNoActionRunGiveTheSimulatedOutcome) {
  const sim::SceneConfig config;
  const auto cells = outcome_cells();
  Tally tally;
  for (std::size_t k = 0; k < test::sample(cells.size(), std::size_t{4}); ++k)
    replay_cell(config, cells[k], Recording{}, tally);
  EXPECT_TRUE(tally.mismatches.empty()) << report(tally);
  EXPECT_GT(tally.contacts, 0);
  EXPECT_GT(tally.avoided, 0);
}

// dat2csv --precision 6, what docs/openscenario.md prescribes: positions to a micrometre, headings
// to a microradian.
TEST(EsminiReplay, SixDecimalsGiveTheSimulatedOutcome) {
  const sim::SceneConfig config;
  const auto cells = outcome_cells();
  Tally tally;
  for (std::size_t k = 0; k < test::sample(cells.size(), std::size_t{3}); ++k)
    replay_cell(config, cells[k], Recording{6, 0.0}, tally);
  EXPECT_TRUE(tally.mismatches.empty()) << report(tally);
}

// Random cells over the ODD's ranges.
TEST(EsminiReplay, RandomCellsGiveTheSimulatedOutcome) {
  const sim::SceneConfig config;
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> speed(25, 70), mu(0.3, 1.0), passage(1.5, 4.0), truck(5, 15);
  Tally tally;
  for (int k = 0; k < test::sample(8, 2); ++k) {
    const double v = speed(rng);
    const double ttc = std::uniform_real_distribution<double>(0.3, config.max_initial_distance_m / (v / 3.6))(rng);
    replay_cell(config, {v, ttc, mu(rng), passage(rng), truck(rng)}, Recording{}, tally);
  }
  EXPECT_TRUE(tally.mismatches.empty()) << report(tally);
}

}  // namespace esmini_replay_test
}  // namespace emrm::exchange
