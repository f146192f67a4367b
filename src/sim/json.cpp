#include "emrm/sim/json.hpp"

namespace emrm::sim {
namespace {

constexpr double kKphPerMps = 3.6;

nlohmann::json impact_json(const ImpactAssessment& a) {
  return {{"impact_speed_kph", a.impact_speed_mps * kKphPerMps},
          {"delta_v_kph", a.delta_v_mps * kKphPerMps},
          {"p_mais3", a.p_mais3},
          {"p_fatal", a.p_fatal},
          {"loss_level", a.loss_level}};
}

}  // namespace

nlohmann::json to_json(const CellResult& result, std::uint64_t seed, const JsonOptions& options) {
  nlohmann::json j;
  j["input"] = {{"speed_kph", result.input.speed_kph},
                {"ttc_s", result.input.ttc_s},
                {"mu", result.input.mu},
                {"passage_m", result.input.passage_m},
                {"truck_speed_kph", result.input.truck_speed_kph},
                {"seed", seed}};
  j["feasible"] = result.feasible;
  j["region"] = std::string(region_name(result.region));
  j["unmitigated"] = impact_json(result.unmitigated);
  nlohmann::json strategies = nlohmann::json::object();
  for (const auto& o : result.strategies) {
    nlohmann::json s = impact_json(o.impact);
    s["avoided"] = o.avoided;
    s["contact"] = o.contact;
    s["road_departure"] = o.road_departure;
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
    if (options.paths) {
      nlohmann::json path = nlohmann::json::array();
      for (const auto& p : o.path)
        path.push_back({p.t_s, p.state.x_m, p.state.y_m, p.state.yaw_rad, p.state.speed_mps()});
      s["path"] = {{"columns", {"t_s", "x_m", "y_m", "yaw_rad", "speed_mps"}}, {"points", std::move(path)}};
    }
    strategies[o.strategy] = std::move(s);
  }
  j["strategies"] = std::move(strategies);
  return j;
}

}  // namespace emrm::sim
