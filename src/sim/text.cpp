// The printed form of a simulated cell (`emrm simulate` without --json).

#include "emrm/sim/text.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::sim {
namespace {

std::string yes_no(bool b) { return b ? "yes" : "no"; }

// A row's note: whose outcome a strategy adopted; what the controller read and chose (the events of
// its loss-evaluation trace, its own predictions); which outcome the oracle took in hindsight.
std::string note_of(const StrategyOutcome& o) {
  if (o.chosen_strategy.empty()) return o.adopted_from;
  if (o.chosen_strategy == "none") return "no risk";
  if (o.loss_evaluation_trace.empty()) return "best in hindsight: " + o.chosen_strategy;
  std::vector<std::string> read;
  for (std::size_t i = 1; i < o.loss_evaluation_trace.size(); i += 2) read.push_back(o.loss_evaluation_trace[i]);
  return fmt::format("chose {} (predicted {}), its own plan", o.chosen_strategy, core::join(read, " "));
}

}  // namespace

std::string to_text(const CellResult& r, const SceneConfig& config, std::uint64_t seed) {
  std::string out;
  out += fmt::format("Cell: {} (seed {})\n", cell_text(scenario_factors(config), r.input), seed);
  const Scene scene(config, r.input);
  const double v = scene.initial_speed_mps();
  if (stop_boundary_applies(config)) {
    // Through the scene's actuators, as the map's boundary: the latency and dead time, the ramp, a cap.
    const double alone_s = v / (2.0 * scene.friction() * kGravity_mps2);
    const double needed_s = stop_boundary_ttc_s(v * 3.6, scene.friction(), config.actuation);
    const std::string how =
        std::abs(needed_s - alone_s) < 1e-12
            ? std::string("v/(2 mu g)")
            : fmt::format("stopping through the actuation: {:.3f} s more than v/(2 mu g) = {:.3f} s",
                          needed_s - alone_s, alone_s);
    out += fmt::format("Initial distance {:.2f} m; braking alone needs TTC >= {:.3f} s ({})\n",
                       scene.initial_distance_m(), needed_s, how);
  } else
    out += fmt::format("Initial gap {:.2f} m\n", scene.initial_distance_m());
  if (!r.feasible) {
    out += fmt::format("Infeasible: {}\n", scene.infeasible_reason());
    return out;
  }
  const auto& u = r.unmitigated;
  out += fmt::format("Region: {}\n", region_name(r.region));
  if (!r.no_certificate.empty()) out += fmt::format("Evidence: {} ({})\n", evidence_name(r.evidence), r.no_certificate);
  out += fmt::format("Unmitigated: impact {:.1f} km/h, delta-v {:.1f} km/h, P(MAIS3+) {:.3f}, P(fatal) {:.3f}, L{}\n\n",
                     u.impact_speed_mps * 3.6, u.delta_v_mps * 3.6, u.p_mais3, u.p_fatal, u.loss_level);
  std::vector<core::Row> rows;
  for (const auto& o : r.strategies)
    rows.push_back({o.strategy, yes_no(o.avoided), fmt::format("{:.1f}", o.impact.impact_speed_mps * 3.6),
                    fmt::format("{:.1f}", o.impact.delta_v_mps * 3.6), fmt::format("{:.3f}", o.impact.p_mais3),
                    fmt::format("{:.3f}", o.impact.p_fatal), fmt::format("L{}", o.impact.loss_level),
                    std::to_string(o.delta_loss), fmt::format("{:.3f}", o.min_ttc_s), std::to_string(o.planner.nodes),
                    note_of(o)});
  out += core::markdown_table({"strategy", "avoided", "impact_kph", "delta_v_kph", "p_mais3", "p_fatal", "loss",
                               "delta_loss", "min_ttc_s", "nodes", "note"},
                              rows);
  const StrategyTable strategies = registered_strategies();
  for (const auto& o : r.strategies)
    if (const StrategyInfo* info = strategies.info(o.strategy);
        info != nullptr && info->role == StrategyRole::kChooser && !info->hindsight) {
      out += "\nEMRM FSM trace: " + core::join(o.fsm_trace, " ") + "\n";
      if (!o.loss_evaluation_trace.empty())
        out += "Loss-evaluation FSM trace: " + core::join(o.loss_evaluation_trace, " ") + "\n";
    }
  return out;
}

}  // namespace emrm::sim
