#include "emrm/results/sensitivity.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "emrm/results/aggregate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::results {
namespace {

// The share (%) of `grid`'s feasible cells where the emergency stop avoids under `a`: the closed
// form (docs/actuation.md), exact to one integration step.
double green_pct(const std::vector<campaign::CellRecord>& records, std::string_view grid,
                 const sim::ActuationConfig& a) {
  std::size_t feasible = 0, green = 0;
  for (const auto& r : records) {
    if (r.grid != grid || !r.feasible) continue;
    ++feasible;
    green += sim::analytically_stoppable(r.factors, a) ? 1u : 0u;
  }
  return feasible == 0 ? NAN : 100.0 * static_cast<double>(green) / static_cast<double>(feasible);
}

}  // namespace

BrakeSensitivity brake_sensitivity(const std::vector<campaign::CellRecord>& records, std::string_view grid,
                                   const sim::ActuationConfig& base) {
  BrakeSensitivity out;
  out.base_g_pct = green_pct(records, grid, base);
  for (int k = 0; k <= 6; ++k) {
    sim::ActuationConfig a = base;
    a.brake_dead_time_s = 0.1 * k;
    out.dead_times_s.push_back(a.brake_dead_time_s);
    out.dead_time_g_pct.push_back(green_pct(records, grid, a));
  }
  // The caps that bite: from the grid's friction limit, rounded up to a whole m/s², down to 40 % of
  // it (10, 9, …, 4 where μ reaches 1; 5, 4.5, …, 2 on a wet grid whose μ is 0.5).
  double mu_max = 0.0;
  for (const auto& r : records)
    if (r.grid == grid && r.feasible) mu_max = std::max(mu_max, r.factors.friction());
  const double top = std::max(1.0, std::ceil(mu_max * sim::kGravity_mps2 - 1e-9));
  for (int k = 0; k <= 6; ++k) {
    const double cap = top * (1.0 - 0.1 * k);
    sim::ActuationConfig a = base;
    a.max_decel_mps2 = cap;
    out.peak_decels_mps2.push_back(cap);
    out.peak_decel_g_pct.push_back(green_pct(records, grid, a));
  }
  return out;
}

core::Table brake_sensitivity_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                                    std::string_view grid, const sim::ActuationConfig& base) {
  const BrakeSensitivity s = brake_sensitivity(records, grid, base);
  core::Table t;
  t.title =
      fmt::format("G (emergency stop avoids) on grid '{}' against the brakes' dead time and peak deceleration", grid);
  t.header = {"brakes", "G (%)", "change (points)"};
  if (!paper.empty()) t.header.emplace_back("paper G (%)");
  const double paper_g = paper.fine_grid.grid == grid ? paper.fine_grid.regions_pct.g : NAN;
  const std::string paper_text = std::isnan(paper_g) ? std::string(core::kNoValue) : core::format_number(paper_g, 1);
  const auto row = [&](const std::string& label, double g) {
    t.rows.push_back({label, core::format_number(g, 1), core::format_number(g - s.base_g_pct, 1)});
    if (!paper.empty()) t.rows.back().push_back(paper_text);
  };
  row(fmt::format("this scene (dead time {:g} s, ramp {:g} s, cap {})", base.brake_dead_time_s, base.brake_ramp_s,
                  base.max_decel_mps2 > 0.0 ? fmt::format("{:g} m/s²", base.max_decel_mps2) : std::string("none")),
      s.base_g_pct);
  for (std::size_t k = 0; k < s.dead_times_s.size(); ++k)
    row(fmt::format("dead time {:.1f} s", s.dead_times_s[k]), s.dead_time_g_pct[k]);
  for (std::size_t k = 0; k < s.peak_decels_mps2.size(); ++k)
    row(fmt::format("peak deceleration {:g} m/s²", s.peak_decels_mps2[k]), s.peak_decel_g_pct[k]);
  t.notes.push_back(
      "Computed, not swept: G is where the emergency stop avoids, and it avoids exactly when v·TTC is at least its "
      "stopping distance through the actuators (perception latency, brake dead time, ramp, cap; docs/actuation.md), "
      "tested to one time step. Each row changes one parameter of this scene's actuation and keeps the others. Y, O "
      "and R need the planners and are not in this table.");
  return t;
}

}  // namespace emrm::results
