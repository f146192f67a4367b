#include "emrm/campaign/sensitivity.hpp"

#include <fmt/format.h>

#include <cmath>

#include "emrm/campaign/aggregate.hpp"

namespace emrm::campaign {
namespace {

// The share (%) of `grid`'s feasible cells where the emergency stop avoids under `a`: the closed
// form (docs/actuation.md), exact to one integration step.
double green_pct(const std::vector<CellRecord>& records, std::string_view grid, const sim::ActuationConfig& a) {
  std::size_t feasible = 0, green = 0;
  for (const auto& r : records) {
    if (r.grid != grid || !r.feasible) continue;
    ++feasible;
    green += analytically_stoppable(r.speed_kph, r.ttc_s, r.mu, a) ? 1u : 0u;
  }
  return feasible == 0 ? NAN : 100.0 * static_cast<double>(green) / static_cast<double>(feasible);
}

}  // namespace

core::Table brake_sensitivity_table(const std::vector<CellRecord>& records, const PaperReference& paper,
                                    std::string_view grid, const sim::ActuationConfig& base) {
  core::Table t;
  t.title = fmt::format("G (emergency stop avoids) on grid '{}' against the brakes' dead time and peak deceleration",
                        grid);
  t.header = {"brakes", "G (%)", "change (points)", "paper G (%)"};
  const double paper_g = paper.fine_grid.grid == grid ? paper.fine_grid.regions_pct.g : NAN;
  const std::string paper_text = std::isnan(paper_g) ? std::string(core::kNoValue) : core::format_number(paper_g, 1);
  const double at_base = green_pct(records, grid, base);
  const auto row = [&](const std::string& label, const sim::ActuationConfig& a) {
    const double g = green_pct(records, grid, a);
    t.rows.push_back({label, core::format_number(g, 1), core::format_number(g - at_base, 1), paper_text});
  };
  row(fmt::format("this scene (dead time {:g} s, ramp {:g} s, cap {})", base.brake_dead_time_s, base.brake_ramp_s,
                  base.max_decel_mps2 > 0.0 ? fmt::format("{:g} m/s²", base.max_decel_mps2) : std::string("none")),
      base);
  for (int k = 0; k <= 6; ++k) {
    sim::ActuationConfig a = base;
    a.brake_dead_time_s = 0.1 * k;
    row(fmt::format("dead time {:.1f} s", a.brake_dead_time_s), a);
  }
  for (const double cap : {10.0, 9.0, 8.0, 7.0, 6.0, 5.0, 4.0}) {
    sim::ActuationConfig a = base;
    a.max_decel_mps2 = cap;
    row(fmt::format("peak deceleration {:g} m/s²", cap), a);
  }
  t.notes.push_back(
      "Computed, not swept: G is where the emergency stop avoids, and it avoids exactly when v·TTC is at least its "
      "stopping distance through the actuators (perception latency, brake dead time, ramp, cap; docs/actuation.md), "
      "tested to one time step. Each row changes one parameter of this scene's actuation and keeps the others. Y, O "
      "and R need the planners and are not in this table.");
  return t;
}

}  // namespace emrm::campaign
