#include "emrm/sim/json.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "emrm/core/error.hpp"

namespace emrm::sim {
namespace {

nlohmann::json impact_json(const ImpactAssessment& a) {
  return {{"impact_speed_kph", a.impact_speed_mps * kKphPerMps},
          {"delta_v_kph", a.delta_v_mps * kKphPerMps},
          {"p_mais3", a.p_mais3},
          {"p_fatal", a.p_fatal},
          {"loss_level", a.loss_level}};
}

nlohmann::json control_json(const Control& u) {
  return {{"steer_rate_radps", u.steer_rate_radps}, {"brake", u.brake}, {"rear_lock", u.rear_lock}};
}

nlohmann::json point_json(const std::optional<core::Vec2>& p) {
  return p ? nlohmann::json::array({p->x, p->y}) : nlohmann::json(nullptr);
}

// Readers that name what is wrong and where.
const nlohmann::json& member(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw InputError(SourceLocation{}, fmt::format("{}: expected an object with '{}'", where, key));
  return j.at(key);
}

double number(const nlohmann::json& j, const char* key, const std::string& where) {
  const auto& v = member(j, key, where);
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw InputError(SourceLocation{}, fmt::format("{}: '{}' must be a finite number", where, key));
  return v.get<double>();
}

bool boolean(const nlohmann::json& j, const char* key, const std::string& where) {
  const auto& v = member(j, key, where);
  if (!v.is_boolean()) throw InputError(SourceLocation{}, fmt::format("{}: '{}' must be true or false", where, key));
  return v.get<bool>();
}

Control control_from(const nlohmann::json& j, const std::string& where) {
  return {number(j, "steer_rate_radps", where), number(j, "brake", where), boolean(j, "rear_lock", where)};
}

std::optional<core::Vec2> point_from(const nlohmann::json& j, const char* key, const std::string& where) {
  const auto& v = member(j, key, where);
  if (v.is_null()) return std::nullopt;
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number() || !std::isfinite(v[0].get<double>()) ||
      !std::isfinite(v[1].get<double>()))
    throw InputError(SourceLocation{}, fmt::format("{}: '{}' must be null or [x, y] in metres", where, key));
  return core::Vec2{v[0].get<double>(), v[1].get<double>()};
}

nlohmann::json trajectory_json(const std::vector<PathPoint>& path) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : path)
    out.push_back(
        {{"t", p.t_s}, {"x", p.state.x_m}, {"y", p.state.y_m}, {"psi", p.state.yaw_rad}, {"v", p.state.speed_mps()}});
  return out;
}

nlohmann::json truck_trajectory_json(const Scene& scene, const std::vector<PathPoint>& path) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : path) {
    const ActorState truck = scene.hazard_at(p.t_s);
    out.push_back({{"t", p.t_s}, {"x", truck.box.center.x}, {"y", truck.box.center.y}, {"psi", truck.box.heading_rad}});
  }
  return out;
}

// Every actor's body and, with trajectories, its motion at every simulation step from t = 0 to the
// end of the longest strategy's trajectory: enough to re-check a witness without emrm.
nlohmann::json actors_json(const Scene& scene, const CellResult& result, bool trajectories) {
  double end_s = 0.0;
  for (const auto& o : result.strategies)
    if (!o.path.empty()) end_s = std::max(end_s, o.path.back().t_s);
  const double dt_s = scene.config().simulation.dt_s;
  const auto steps = static_cast<long long>(std::ceil(end_s / dt_s - 1e-9));
  nlohmann::json out = nlohmann::json::array();
  for (const Actor& actor : scene.actors()) {
    const ActorBody& body = actor.body();
    nlohmann::json a{{"name", body.name},
                     {"kind", core::enum_name(body.kind)},
                     {"length_m", body.length_m},
                     {"width_m", body.width_m},
                     {"mass_kg", body.mass_kg}};
    if (trajectories) {
      nlohmann::json trajectory = nlohmann::json::array();
      for (long long k = 0; k <= steps; ++k) {
        const double t = std::min(static_cast<double>(k) * dt_s, end_s);
        const ActorState s = actor.at(t);
        trajectory.push_back({{"t", t}, {"x", s.box.center.x}, {"y", s.box.center.y}, {"psi", s.box.heading_rad}});
      }
      a["trajectory"] = std::move(trajectory);
    }
    out.push_back(std::move(a));
  }
  return out;
}

// The drivable area as one polygon (counter-clockwise, road frame) over the x the cell spans, and
// what lies beyond each edge.
nlohmann::json road_json(const Scene& scene, const CellResult& result) {
  const Road& road = scene.road();
  double x_lo = scene.ego_initial().x_m - scene.config().ego.length_m;
  double x_hi = scene.passed_x_m() + scene.config().ego.length_m;
  for (const auto& o : result.strategies)
    for (const auto& p : o.path) x_hi = std::max(x_hi, p.state.x_m + scene.config().ego.length_m);
  const nlohmann::json polygon =
      nlohmann::json::array({{x_lo, road.min_y_m}, {x_hi, road.min_y_m}, {x_hi, road.max_y_m}, {x_lo, road.max_y_m}});
  nlohmann::json roadside = {{"right", core::enum_name(road.right)}, {"left", core::enum_name(road.left)}};
  // An embankment's slope (run per unit of drop) beside its kind.
  if (road.right == Roadside::kEmbankment) roadside["right_slope_h"] = road.right_slope_h;
  if (road.left == Roadside::kEmbankment) roadside["left_slope_h"] = road.left_slope_h;
  return {{"drivable", nlohmann::json::array({polygon})}, {"roadside", std::move(roadside)}};
}

std::string text(const nlohmann::json& j, const char* key, const std::string& where) {
  const auto& v = member(j, key, where);
  if (!v.is_string()) throw InputError(SourceLocation{}, fmt::format("{}: '{}' must be a string", where, key));
  return v.get<std::string>();
}

}  // namespace

nlohmann::json to_json(const ImpactAssessment& impact) { return impact_json(impact); }

nlohmann::json to_json(const CellInput& cell, const FactorTable& factors) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < factors.size() && i < cell.size(); ++i) j[factors[i].key] = cell[i];
  return j;
}

nlohmann::json to_json(const FactorTable& factors) {
  nlohmann::json out = nlohmann::json::array();
  for (const Factor& f : factors) {
    const FactorLimits& l = f.limits;
    out.push_back({{"key", f.key},
                   {"unit", f.unit},
                   {"what", f.what},
                   {"role", core::enum_name(f.role)},
                   {"default", f.default_value},
                   {"low", l.low},
                   {"low_inclusive", l.low_inclusive},
                   {"high", std::isinf(l.high) ? nlohmann::json(nullptr) : nlohmann::json(l.high)}});
    if (f.categorical()) out.back()["levels"] = f.levels;  // a cell holds a level's index
  }
  return out;
}

nlohmann::json to_json(const Certificate& c, const FactorTable& factors) {
  return {{"method", c.method},
          {"margin_m", c.margin_m},
          {"witness", c.witness},
          {"crossing_x_m", c.crossing_x_m},
          {"heading_cap_rad", c.heading_cap_rad},
          {"window_start_s", c.window_start_s},
          {"window_end_s", c.window_end_s},
          {"stop_reach_x_m", c.stop_reach_x_m},
          {"step_s", c.step_s},
          {"cell", to_json(c.cell, factors)},
          {"latency_s", c.latency_s},
          {"actuation", to_json(c.actuation)}};
}

Certificate certificate_from_json(const nlohmann::json& j, const FactorTable& factors, const std::string& where) {
  Certificate c;
  c.method = text(j, "method", where);
  c.margin_m = number(j, "margin_m", where);
  c.witness = text(j, "witness", where);
  c.crossing_x_m = number(j, "crossing_x_m", where);
  c.heading_cap_rad = number(j, "heading_cap_rad", where);
  c.window_start_s = number(j, "window_start_s", where);
  c.window_end_s = number(j, "window_end_s", where);
  c.stop_reach_x_m = number(j, "stop_reach_x_m", where);
  c.step_s = number(j, "step_s", where);
  const auto& cell = member(j, "cell", where);
  const std::string at = where + ": cell";
  std::vector<double> values;
  for (const Factor& f : factors) values.push_back(number(cell, f.key.c_str(), at));
  c.cell = CellInput(std::span<const double>(values));
  c.latency_s = number(j, "latency_s", where);
  // Certificates written before actuators existed were made for instant actuation.
  c.actuation.perception_latency_s = c.latency_s;
  if (j.contains("actuation")) c.actuation = actuation_from_json(member(j, "actuation", where), where + ": actuation");
  return c;
}

nlohmann::json to_json(const ActuationConfig& a) {
  return {{"perception_latency_s", a.perception_latency_s},
          {"brake_dead_time_s", a.brake_dead_time_s},
          {"brake_ramp_s", a.brake_ramp_s},
          {"max_decel_mps2", a.max_decel_mps2},
          {"steer_dead_time_s", a.steer_dead_time_s},
          {"steer_time_constant_s", a.steer_time_constant_s}};
}

ActuationConfig actuation_from_json(const nlohmann::json& a, const std::string& where) {
  return {number(a, "perception_latency_s", where), number(a, "brake_dead_time_s", where),
          number(a, "brake_ramp_s", where),         number(a, "max_decel_mps2", where),
          number(a, "steer_dead_time_s", where),    number(a, "steer_time_constant_s", where)};
}

nlohmann::json to_json(const Maneuver& maneuver) {
  nlohmann::json plan = nlohmann::json::array();
  for (const auto& s : maneuver.plan)
    plan.push_back({{"control", control_json(s.control)},
                    {"duration_s", s.duration_s},
                    {"pursue", point_json(s.pursue)},
                    {"friction_circle_brake", s.friction_circle_brake},
                    {"pursuit_grip", s.pursuit_grip}});
  nlohmann::json tail(nullptr);
  if (maneuver.tail)
    tail = {{"control", control_json(maneuver.tail->control)},
            {"straighten", maneuver.tail->straighten},
            {"friction_circle_brake", maneuver.tail->friction_circle_brake},
            {"pursue", point_json(maneuver.tail->pursue)}};
  return {{"plan", std::move(plan)}, {"tail", std::move(tail)}};
}

Maneuver maneuver_from_json(const nlohmann::json& j, const std::string& where) {
  Maneuver m;
  const auto& plan = member(j, "plan", where);
  if (!plan.is_array())
    throw InputError(SourceLocation{}, fmt::format("{}: 'plan' must be an array of segments", where));
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const std::string at = fmt::format("{}: plan[{}]", where, i);
    ControlSegment s;
    s.control = control_from(member(plan[i], "control", at), at + ".control");
    s.duration_s = number(plan[i], "duration_s", at);
    if (s.duration_s < 0.0) throw InputError(SourceLocation{}, fmt::format("{}: 'duration_s' must be >= 0", at));
    s.pursue = point_from(plan[i], "pursue", at);
    s.friction_circle_brake = boolean(plan[i], "friction_circle_brake", at);
    s.pursuit_grip = number(plan[i], "pursuit_grip", at);
    m.plan.push_back(s);
  }
  const auto& tail = member(j, "tail", where);
  if (!tail.is_null()) {
    const std::string at = where + ": tail";
    Tail t;
    t.control = control_from(member(tail, "control", at), at + ".control");
    t.straighten = boolean(tail, "straighten", at);
    t.friction_circle_brake = boolean(tail, "friction_circle_brake", at);
    t.pursue = point_from(tail, "pursue", at);
    m.tail = t;
  }
  return m;
}

nlohmann::json to_json(const CellResult& result, const Scene& scene, std::uint64_t seed, const JsonOptions& options) {
  nlohmann::json j;
  const FactorTable factors = scenario_factors(scene.config());
  j["input"] = to_json(result.input, factors);
  j["input"]["seed"] = seed;
  j["feasible"] = result.feasible;
  j["region"] = std::string(region_name(result.region));
  if (result.feasible) {
    j["evidence"] = std::string(evidence_name(result.evidence));
    if (result.mitigation_evidence != MitigationEvidence::kNone)
      j["mitigation_evidence"] = std::string(core::enum_name(result.mitigation_evidence));
    j["strengthened"] = result.strengthened;
    j["harm_reduction"] = {{"p_mais3", result.p_mais3_reduction}, {"p_fatal", result.p_fatal_reduction}};
    if (result.certificate) j["certificate"] = to_json(*result.certificate, factors);
    if (!result.no_certificate.empty()) j["no_certificate"] = result.no_certificate;
  }
  j["unmitigated"] = impact_json(result.unmitigated);
  nlohmann::json strategies = nlohmann::json::object();
  for (const auto& o : result.strategies) {
    nlohmann::json s = impact_json(o.impact);
    s["avoided"] = o.avoided;
    s["contact"] = o.contact;
    s["road_departure"] = o.road_departure;
    s["departure_speed_kph"] = o.road_departure ? o.impact.impact_speed_mps * kKphPerMps : 0.0;
    s["evidence"] = std::string(evidence_name(o.evidence));
    s["delta_loss"] = o.delta_loss;
    s["min_ttc_s"] = o.min_ttc_s;
    s["fsm_trace"] = o.fsm_trace;
    if (!o.loss_evaluation_trace.empty()) s["loss_evaluation_trace"] = o.loss_evaluation_trace;
    if (!o.chosen_strategy.empty()) s["chosen_strategy"] = o.chosen_strategy;
    if (!o.adopted_from.empty()) s["adopted_from"] = o.adopted_from;
    s["planner"] = {{"nodes", o.planner.nodes}, {"rollouts", o.planner.rollouts}};
    if (options.timing) {
      s["planner"]["time_ms"] = o.planner.time_ms;
      s["planner"]["time_limited"] = o.planner.time_limited;
    }
    if (options.trajectories) {
      s["trajectory"] = trajectory_json(o.path);
      s["truck_trajectory"] = truck_trajectory_json(scene, o.path);
    }
    s["maneuver"] = to_json(o.maneuver);
    strategies[o.strategy] = std::move(s);
  }
  j["strategies"] = std::move(strategies);
  j["family"] = scene.config().family;
  j["actors"] = actors_json(scene, result, options.trajectories);
  j["road"] = road_json(scene, result);
  return j;
}

}  // namespace emrm::sim
