#include "emrm/results/verify.hpp"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <set>

#include "emrm/campaign/adaptive.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/sim/certificate.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::results {
namespace {

using Polygon = std::array<core::Vec2, 4>;

// ---- geometry of the checks, written apart from the simulator's ------------------------------

// The ego's outline from its CG pose: the CG lies on the axis, cg_to_front behind the bumper.
Polygon ego_outline(const sim::VehicleParams& p, double x, double y, double yaw, double shrink_m) {
  const core::Vec2 along{std::cos(yaw), std::sin(yaw)};
  const core::Vec2 left{-along.y, along.x};
  const core::Vec2 cg{x, y};
  const double front = p.cg_to_front_m() - shrink_m;
  const double rear = p.cg_to_rear_m() - shrink_m;
  const double half = 0.5 * p.width_m - shrink_m;
  return {cg + along * front - left * half, cg + along * front + left * half, cg - along * rear + left * half,
          cg - along * rear - left * half};
}

Polygon actor_outline(const sim::Actor& actor, double t_s) {
  const auto box = actor.at(t_s).box;
  const core::Vec2 along{std::cos(box.heading_rad), std::sin(box.heading_rad)};
  const core::Vec2 left{-along.y, along.x};
  const core::Vec2 a = along * (0.5 * box.length_m);
  const core::Vec2 b = left * (0.5 * box.width_m);
  return {box.center + a - b, box.center + a + b, box.center - a + b, box.center - a - b};
}

// Convex quadrilaterals overlap unless an edge normal of either separates them.
bool overlap(const Polygon& a, const Polygon& b) {
  for (const Polygon* p : {&a, &b})
    for (std::size_t i = 0; i < 4; ++i) {
      const core::Vec2 edge = (*p)[(i + 1) % 4] - (*p)[i];
      const core::Vec2 normal{-edge.y, edge.x};
      double a_min = std::numeric_limits<double>::infinity(), a_max = -a_min, b_min = a_min, b_max = -a_min;
      for (const auto& v : a) a_min = std::min(a_min, v.dot(normal)), a_max = std::max(a_max, v.dot(normal));
      for (const auto& v : b) b_min = std::min(b_min, v.dot(normal)), b_max = std::max(b_max, v.dot(normal));
      if (a_max < b_min || b_max < a_min) return false;
    }
  return true;
}

double point_segment_distance(core::Vec2 p, core::Vec2 a, core::Vec2 b) {
  const core::Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.dot(ab), 0.0, 1.0);
  return (p - (a + ab * t)).norm();
}

// Distance between two disjoint convex polygons: the least vertex-to-edge distance either way.
double distance(const Polygon& a, const Polygon& b) {
  double d = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < 2; ++pass) {
    const Polygon& p = pass == 0 ? a : b;
    const Polygon& q = pass == 0 ? b : a;
    for (const auto& v : p)
      for (std::size_t i = 0; i < 4; ++i) d = std::min(d, point_segment_distance(v, q[i], q[(i + 1) % 4]));
  }
  return d;
}

// A pose between two recorded steps: cubic Hermite in position (world velocities) and yaw (rates).
struct Pose {
  double x, y, yaw;
};

core::Vec2 world_velocity(const sim::VehicleState& s) {
  return {s.vx_mps * std::cos(s.yaw_rad) - s.vy_mps * std::sin(s.yaw_rad),
          s.vx_mps * std::sin(s.yaw_rad) + s.vy_mps * std::cos(s.yaw_rad)};
}

Pose between(const sim::PathPoint& a, const sim::PathPoint& b, double t_s) {
  const double h = b.t_s - a.t_s;
  if (h <= 0.0) return {b.state.x_m, b.state.y_m, b.state.yaw_rad};
  const double u = (t_s - a.t_s) / h;
  const double h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u;
  const double h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  const core::Vec2 va = world_velocity(a.state) * h;
  const core::Vec2 vb = world_velocity(b.state) * h;
  return {h00 * a.state.x_m + h10 * va.x + h01 * b.state.x_m + h11 * vb.x,
          h00 * a.state.y_m + h10 * va.y + h01 * b.state.y_m + h11 * vb.y,
          h00 * a.state.yaw_rad + h10 * a.state.yaw_rate_radps * h + h01 * b.state.yaw_rad +
              h11 * b.state.yaw_rate_radps * h};
}

// The pose at time t of a straight stop at constant deceleration from a (moving) to b (at rest):
// the deceleration is the one that stops a's speed within the distance from a to b.
Pose braking(const sim::PathPoint& a, const sim::PathPoint& b, double t_s) {
  const double distance = std::hypot(b.state.x_m - a.state.x_m, b.state.y_m - a.state.y_m);
  const double v = a.state.speed_mps();
  if (!(distance > 0.0) || !(v > 0.0)) return {b.state.x_m, b.state.y_m, b.state.yaw_rad};
  const double decel = v * v / (2.0 * distance);
  const double tau = std::min(t_s - a.t_s, v / decel);
  const double along = v * tau - 0.5 * decel * tau * tau;
  return {a.state.x_m + along * std::cos(a.state.yaw_rad), a.state.y_m + along * std::sin(a.state.yaw_rad),
          a.state.yaw_rad};
}

// ---- the checks -------------------------------------------------------------------------------

struct AvoidanceCheck {
  std::optional<std::string> failure;
  double clearance_m = std::numeric_limits<double>::infinity();
};

// Every check_step_s along the trajectory: no overlap with the truck deeper than the tolerance,
// inside the road to within it; at the end, a safe state.
AvoidanceCheck check_avoidance(const sim::Scene& scene, const std::vector<sim::PathPoint>& path,
                               const VerifyOptions& options) {
  const auto& config = scene.config();
  const double low = scene.road().min_y_m - options.tolerance_m;
  const double high = scene.road().max_y_m + options.tolerance_m;
  AvoidanceCheck out;
  // The truncation of a stop in closed form leaves a jump at the very end: a straight line on a
  // straight road, checked at its ends when every actor keeps its place along the road; where one
  // drives along it (a car cutting in), every check_step_s along the stop's own motion.
  const bool actor_drives = std::ranges::any_of(scene.actors(), [](const sim::Actor& actor) {
    return actor.motion().direction.x != 0.0 || actor.motion().track != nullptr;
  });
  for (std::size_t k = 0; k < path.size(); ++k) {
    const sim::PathPoint& b = path[k];
    const sim::PathPoint& a = k > 0 ? path[k - 1] : path[k];
    const bool closed_form_jump = b.t_s - a.t_s > 1.5 * config.simulation.dt_s;
    const int samples = k == 0 || (closed_form_jump && !actor_drives)
                            ? 1
                            : std::max(1, static_cast<int>(std::ceil((b.t_s - a.t_s) / options.check_step_s)));
    for (int i = 1; i <= samples; ++i) {
      const double t = a.t_s + (b.t_s - a.t_s) * i / samples;
      const Pose pose = k == 0 ? Pose{b.state.x_m, b.state.y_m, b.state.yaw_rad}
                        : closed_form_jump
                            ? (actor_drives ? braking(a, b, t) : Pose{b.state.x_m, b.state.y_m, b.state.yaw_rad})
                            : between(a, b, t);
      const Polygon ego = ego_outline(config.ego, pose.x, pose.y, pose.yaw, 0.0);
      // Every actor of the scene, the hazard first; the clearance is to the nearest of them.
      const Polygon shrunk = ego_outline(config.ego, pose.x, pose.y, pose.yaw, options.tolerance_m);
      for (const sim::Actor& actor : scene.actors()) {
        const Polygon other = actor_outline(actor, t);
        if (overlap(shrunk, other)) {
          out.failure = fmt::format("overlaps the {} at t = {:.3f} s", actor.body().name, t);
          return out;
        }
        if (!overlap(ego, other)) out.clearance_m = std::min(out.clearance_m, distance(ego, other));
      }
      for (const auto& corner : ego)
        if (corner.y < low || corner.y > high) {
          out.failure = fmt::format("leaves the road at t = {:.3f} s (corner at y = {:.4f} m)", t, corner.y);
          return out;
        }
    }
  }
  // The end: at rest, and no actor that moves on meets the standing car (every check_step_s over the
  // scene's horizon after the end, or until every actor rests); or stable with room to stop on the road.
  const sim::VehicleState& s = path.back().state;
  if (s.speed_mps() < 0.05) {
    const double end_s = path.back().t_s;
    const Polygon standing = ego_outline(config.ego, s.x_m, s.y_m, s.yaw_rad, options.tolerance_m);
    const double look_s = config.simulation.horizon_s;
    for (double t = end_s; t <= end_s + look_s; t += options.check_step_s) {
      bool moving = false;
      for (const sim::Actor& actor : scene.actors()) {
        if (t > actor.motion().rest_time_s() + options.check_step_s) continue;
        moving = true;
        if (overlap(standing, actor_outline(actor, t))) {
          out.failure =
              fmt::format("stands in the way of the {}, which meets it at t = {:.3f} s", actor.body().name, t);
          return out;
        }
      }
      if (!moving) break;
    }
    return out;
  }
  const auto& bounds = config.safe_state;
  const double heading = std::remainder(s.yaw_rad, 2.0 * std::numbers::pi);
  if (std::abs(s.yaw_rate_radps) > bounds.max_yaw_rate_radps ||
      std::abs(s.slip_angle_rad()) > bounds.max_slip_angle_rad || std::abs(heading) > bounds.max_heading_error_rad ||
      std::abs(s.steer_rad) > bounds.max_steer_rad) {
    out.failure = fmt::format("ends unstable (yaw rate {:.3f} rad/s, slip {:.3f} rad, heading {:.3f} rad)",
                              s.yaw_rate_radps, s.slip_angle_rad(), heading);
    return out;
  }
  const double stop_m = s.speed_mps() * s.speed_mps() / (2.0 * scene.friction() * sim::kGravity_mps2);
  const Polygon at_rest = ego_outline(config.ego, s.x_m + stop_m * std::cos(s.yaw_rad),
                                      s.y_m + stop_m * std::sin(s.yaw_rad), s.yaw_rad, 0.0);
  for (const auto& corner : at_rest)
    if (corner.y < low || corner.y > high) {
      out.failure = "ends without room to stop on the road";
      return out;
    }
  return out;
}

bool same(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a)); }

// G when the baseline avoided; Y when another strategy that counts did; O when the best level is
// below the reference's; R otherwise (docs/simulate.md).
sim::Region region_from(const sim::StrategyTable& table, const campaign::CellRecord& r) {
  const sim::StrategyInfo* baseline = table.first_of(sim::StrategyRole::kBaseline);
  int best = r.unmitigated_loss_level;
  bool any = false;
  for (const auto& o : r.outcomes) {
    const sim::StrategyInfo* info = table.info(o.strategy);
    if (info == nullptr || info->role == sim::StrategyRole::kChooser) continue;
    if (o.avoided && baseline != nullptr && o.strategy == baseline->name) return sim::Region::kG;
    any = any || o.avoided;
    best = std::min(best, o.loss_level);
  }
  if (any) return sim::Region::kY;
  return best < r.unmitigated_loss_level ? sim::Region::kO : sim::Region::kR;
}

// The strategy whose limits a stored maneuver obeys: the one that found an adopted outcome; for the
// controller's own maneuver (adopted from nobody), the strategy it committed to; for an outcome the
// oracle took from the controller, the controller's.
std::string limits_source(const sim::StrategyTable& table, const campaign::CellRecord& r,
                          const campaign::OutcomeRecord& o) {
  const campaign::OutcomeRecord* at = &o;
  if (!at->adopted_from.empty()) {
    const sim::StrategyInfo* from = table.info(at->adopted_from);
    const campaign::OutcomeRecord* next = r.outcome(at->adopted_from);
    if (from == nullptr || from->role != sim::StrategyRole::kChooser || next == nullptr || next == at)
      return at->adopted_from;
    at = next;
  }
  if (at->adopted_from.empty() && table.info(at->chosen_strategy) != nullptr) return at->chosen_strategy;
  return at->adopted_from.empty() ? at->strategy : at->adopted_from;
}

// Cells checked side by side at a time: enough to keep every core busy, few enough to hold.
constexpr std::size_t kVerifyBatch = 256;

// Adds one part of the report (a cell's) to the whole.
void merge_into(VerifyReport& whole, VerifyReport&& part) {
  whole.cells += part.cells;
  whole.witnesses += part.witnesses;
  whole.avoidances += part.avoidances;
  whole.certificates += part.certificates;
  whole.undecided += part.undecided;
  whole.inferred += part.inferred;
  for (const auto& [region, counts] : part.by_region)
    for (const auto& [evidence, n] : counts) whole.by_region[region][evidence] += n;
  whole.least_clearance_m = std::min(whole.least_clearance_m, part.least_clearance_m);
  whole.failures.insert(whole.failures.end(), std::make_move_iterator(part.failures.begin()),
                        std::make_move_iterator(part.failures.end()));
}

}  // namespace

VerifyReport verify_results(const std::filesystem::path& results_sqlite, const VerifyOptions& options) {
  const campaign::ResultStore store = campaign::ResultStore::open_for_reading(results_sqlite);
  const sim::SceneConfig config =
      sim::parse_stored_scene_config(store.meta().scene_yaml, results_sqlite.string() + " (scene)");
  const sim::FactorTable factors = sim::scenario_factors(config);
  const auto model = sim::make_vehicle_model(config.simulation.vehicle_model, config.ego);
  const sim::StrategyTable table = sim::registered_strategies();
  bool every_strategy_stored = true;
  for (const auto& entry : table.entries())
    if (entry.info.role != sim::StrategyRole::kChooser &&
        std::find(store.meta().strategies.begin(), store.meta().strategies.end(), entry.info.name) ==
            store.meta().strategies.end())
      every_strategy_stored = false;

  // The simulated cells by grid: the grounds an inferred cell may name.
  std::map<std::string, std::set<std::int64_t>> simulated;
  store.for_each_key([&](std::size_t g, std::int64_t i) {
    if (g < store.meta().grids.size()) simulated[store.meta().grids[g]].insert(i);
  });

  // One cell's checks, counted into `report` (a part of the whole, merged in store order).
  const auto check_cell = [&](const campaign::CellRecord& r, VerifyReport& report) {
    if (!r.feasible) return;
    ++report.cells;
    ++report.by_region[core::enum_text(r.region)][core::enum_text(r.evidence)];
    const auto fail = [&](const std::string& strategy, std::string what) {
      report.failures.push_back({r.grid, r.index, strategy, std::move(what)});
    };
    if (r.factors.size() != factors.size()) {
      fail("", fmt::format("{} factor values for the scene's {} factors", r.factors.size(), factors.size()));
      return;
    }
    const sim::Scene scene(config, r.factors);
    // An adaptive sweep's inferred cell: its grounds must stand (docs/adaptive.md).
    if (r.method == campaign::CellMethod::kInferred) {
      ++report.inferred;
      if (r.evidence != campaign::CellEvidence::kInferred)
        fail("", fmt::format("inferred cell with evidence '{}'", core::enum_name(r.evidence)));
      if (r.inferred_from.empty() &&
          (r.region != sim::Region::kG || sim::stop_call(config, scene.cell()) != sim::StopCall::kStops))
        fail("", fmt::format("region {} inferred without grounds, and the stop boundary does not prove G",
                             core::enum_name(r.region)));
      const auto grid_cells = simulated.find(r.grid);  // read only: the cells are checked side by side
      for (const std::int64_t from : r.inferred_from)
        if (grid_cells == simulated.end() || grid_cells->second.count(from) == 0)
          fail("", fmt::format("inferred from cell {}#{}, which is not a simulated cell", r.grid, from));
      return;
    }

    if (every_strategy_stored) {
      const sim::Region derived = region_from(table, r);
      if (derived != r.region)
        fail("", fmt::format("region {} stored, the outcomes give {}", core::enum_name(r.region),
                             core::enum_name(derived)));
    }
    const bool avoidable = r.region == sim::Region::kG || r.region == sim::Region::kY;
    if (avoidable && r.evidence != campaign::CellEvidence::kWitness)
      fail("", fmt::format("region {} without a witness", core::enum_name(r.region)));
    if (!avoidable && r.evidence != campaign::CellEvidence::kCertificate &&
        r.evidence != campaign::CellEvidence::kUndecided)
      fail("", fmt::format("region {} with evidence '{}'", core::enum_name(r.region), core::enum_name(r.evidence)));
    if (r.evidence == campaign::CellEvidence::kUndecided) ++report.undecided;
    if (r.evidence == campaign::CellEvidence::kCertificate && r.certificate.empty())
      fail("", "evidence 'certificate' without one");
    // "Nothing below the reference's L4" is a proof only when no avoidance exists either.
    if (r.mitigation_evidence == sim::MitigationEvidence::kProof && r.evidence != campaign::CellEvidence::kCertificate)
      fail("", "mitigation evidence 'proof' without a certificate that nothing avoids");
    if (!r.certificate.empty()) {
      const std::string where = fmt::format("{}: cell {}#{} certificate", results_sqlite.string(), r.grid, r.index);
      nlohmann::json json;
      try {
        json = nlohmann::json::parse(r.certificate);
      } catch (const nlohmann::json::exception& e) {
        throw InputError(SourceLocation{results_sqlite.string()},
                         fmt::format("cell {}#{}: the stored certificate is not JSON: {}", r.grid, r.index, e.what()));
      }
      ++report.certificates;
      if (!sim::check_certificate(scene, sim::certificate_from_json(json, factors, where)))
        fail("", "the certificate does not hold");
      if (avoidable)
        fail("", fmt::format("region {} although a certificate says nothing avoids", core::enum_name(r.region)));
    }

    // The oracle is never worse than an option it had: a strategy EMRM may choose, or the
    // controller's executed maneuver (the controller, which commits before it knows the outcomes,
    // may be worse than a strategy).
    for (const auto& chooser : r.outcomes) {
      const sim::StrategyInfo* info = table.info(chooser.strategy);
      if (info == nullptr || info->role != sim::StrategyRole::kChooser || !info->hindsight) continue;
      for (const auto& option : r.outcomes) {
        const sim::StrategyInfo* other = table.info(option.strategy);
        const bool controller = other != nullptr && other->role == sim::StrategyRole::kChooser && !other->hindsight;
        if (other != nullptr && (other->emrm_may_choose || controller) && better_record(option, chooser))
          fail(chooser.strategy, fmt::format("worse than {}, which it may choose", option.strategy));
      }
    }

    for (const auto& o : r.outcomes) {
      const std::string source = limits_source(table, r, o);
      const sim::StrategyInfo* info = table.info(source);
      if (info == nullptr) {
        fail(o.strategy, fmt::format("unknown strategy '{}'", source));
        continue;
      }
      if (o.maneuver.empty()) {
        fail(o.strategy, "no maneuver stored: nothing to replay");
        continue;
      }
      nlohmann::json json;
      try {
        json = nlohmann::json::parse(o.maneuver);
      } catch (const nlohmann::json::exception& e) {
        throw InputError(
            SourceLocation{results_sqlite.string()},
            fmt::format("cell {}#{} {}: the stored maneuver is not JSON: {}", r.grid, r.index, o.strategy, e.what()));
      }
      const sim::Maneuver maneuver = sim::maneuver_from_json(
          json, fmt::format("{}: cell {}#{} {}", results_sqlite.string(), r.grid, r.index, o.strategy));
      const sim::RolloutResult again = sim::replay(scene, *model, info->limits, maneuver);
      ++report.witnesses;
      const bool contact = again.termination == sim::Termination::kContact;
      const bool departure = again.termination == sim::Termination::kRoadDeparture;
      if (again.avoided() != o.avoided || contact != o.contact || departure != o.road_departure)
        fail(o.strategy, fmt::format("replay {} what is stored ({} stored)",
                                     again.avoided() ? "avoids, unlike" : "does not avoid, unlike",
                                     o.avoided ? "avoided" : "not avoided"));
      else if (!o.avoided &&
               (again.impact.loss_level != o.loss_level || !same(again.impact.delta_v_mps * 3.6, o.delta_v_kph)))
        fail(o.strategy,
             fmt::format("replay gives L{} at {:.3f} km/h, stored L{} at {:.3f} km/h", again.impact.loss_level,
                         again.impact.delta_v_mps * 3.6, o.loss_level, o.delta_v_kph));
      if (o.avoided && o.evidence != sim::Evidence::kWitness) fail(o.strategy, "an avoidance without a witness");
      if (!again.avoided()) continue;
      ++report.avoidances;
      const AvoidanceCheck check = check_avoidance(scene, again.path, options);
      if (check.failure) fail(o.strategy, *check.failure);
      report.least_clearance_m = std::min(report.least_clearance_m, check.clearance_m);
    }
  };

  // The cells are checked side by side in batches and merged in store order, so the report (and
  // the first error thrown, if a stored maneuver cannot be read) is the same for any thread count.
  std::optional<tbb::global_control> limit;
  if (options.threads > 0)
    limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(options.threads));
  VerifyReport report;
  report.least_clearance_m = std::numeric_limits<double>::infinity();
  std::vector<campaign::CellRecord> batch;
  const auto check_batch = [&] {
    std::vector<VerifyReport> parts(batch.size());
    std::vector<std::exception_ptr> errors(batch.size());
    tbb::parallel_for(std::size_t{0}, batch.size(), [&](std::size_t k) {
      parts[k].least_clearance_m = std::numeric_limits<double>::infinity();
      try {
        check_cell(batch[k], parts[k]);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
    for (std::size_t k = 0; k < batch.size(); ++k) {
      if (errors[k]) std::rethrow_exception(errors[k]);
      merge_into(report, std::move(parts[k]));
    }
    batch.clear();
  };
  store.for_each_cell([&](const campaign::CellRecord& r) {
    batch.push_back(r);
    if (batch.size() >= kVerifyBatch) check_batch();
  });
  check_batch();
  if (!std::isfinite(report.least_clearance_m)) report.least_clearance_m = 0.0;
  return report;
}

std::string to_text(const VerifyReport& report) {
  std::string out = fmt::format(
      "Verified {} feasible cells: {} maneuvers replayed, {} avoidances re-checked every millisecond "
      "(least clearance to an actor {:.4g} m), {} certificates re-derived, {} undecided cells\n",
      report.cells, report.witnesses, report.avoidances, report.least_clearance_m, report.certificates,
      report.undecided);
  if (report.inferred > 0)
    out += fmt::format(
        "{} cells were inferred by an adaptive sweep: their grounds (simulated cells, or the analytic "
        "stop boundary) checked, nothing replayed\n",
        report.inferred);
  out += fmt::format("| region | witness | certificate | undecided |{}\n| --- | --- | --- | --- |{}\n",
                     report.inferred > 0 ? " inferred |" : "", report.inferred > 0 ? " --- |" : "");
  for (const char* region : {"G", "Y", "O", "R"}) {
    const auto it = report.by_region.find(region);
    const auto count = [&](const char* evidence) -> std::int64_t {
      if (it == report.by_region.end()) return 0;
      const auto e = it->second.find(evidence);
      return e == it->second.end() ? 0 : e->second;
    };
    out += fmt::format("| {} | {} | {} | {} |{}\n", region, count("witness"), count("certificate"), count("undecided"),
                       report.inferred > 0 ? fmt::format(" {} |", count("inferred")) : "");
  }
  if (report.ok()) return out + "All claims hold.\n";
  out += fmt::format("{} claims do not hold:\n", report.failures.size());
  for (const auto& f : report.failures)
    out += fmt::format("  {}#{}{}: {}\n", f.grid, f.index, f.strategy.empty() ? "" : " " + f.strategy, f.what);
  return out;
}

nlohmann::ordered_json to_json(const VerifyReport& report) {
  nlohmann::ordered_json j{{"ok", report.ok()},
                           {"cells", report.cells},
                           {"witnesses", report.witnesses},
                           {"avoidances", report.avoidances},
                           {"certificates", report.certificates},
                           {"undecided", report.undecided},
                           {"inferred", report.inferred},
                           {"least_clearance_m", report.least_clearance_m}};
  auto& regions = j["by_region"] = nlohmann::ordered_json::object();
  for (const auto& [region, counts] : report.by_region)
    for (const auto& [evidence, n] : counts) regions[region][evidence] = n;
  auto& failures = j["failures"] = nlohmann::ordered_json::array();
  for (const auto& f : report.failures)
    failures.push_back({{"grid", f.grid}, {"index", f.index}, {"strategy", f.strategy}, {"what", f.what}});
  return j;
}

void write_verify_report(const std::filesystem::path& dir, const VerifyReport& report) {
  core::write_file(ResultsDir(dir).verify_json(), to_json(report).dump(2) + "\n");
}

}  // namespace emrm::results
