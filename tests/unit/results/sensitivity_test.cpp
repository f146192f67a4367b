// The brakes' sensitivity table: the G share from the stop's closed form, one parameter at a time.

#include "emrm/results/sensitivity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "emrm/results/aggregate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::results {
namespace sensitivity_test {

std::vector<campaign::CellRecord> fine_grid(double mu = 1.0) {
  std::vector<campaign::CellRecord> out;
  for (double speed = 30.0; speed <= 72.0; speed += 3.0)
    for (double ttc = 0.25; ttc <= 2.95; ttc += 0.06) {
      campaign::CellRecord r;
      r.grid = "fine";
      r.factors = sim::CellInput{speed, ttc, mu, 0.0, 0.0};
      r.feasible = speed / 3.6 * ttc <= 24.5;
      out.push_back(r);
    }
  return out;
}

double g_of(const core::Row& row) { return std::stod(row[1]); }

TEST(BrakeSensitivity, GFallsWithEveryDeadTimeStepAndEveryLowerCap) {
  sim::ActuationConfig base;
  base.perception_latency_s = 0.1;
  PaperReference paper;
  paper.fine_grid.grid = "fine";
  paper.fine_grid.regions_pct.g = 44.5;
  const auto records = fine_grid();
  const core::Table t = brake_sensitivity_table(records, paper, "fine", base);
  ASSERT_EQ(t.rows.size(), 1u + 7u + 7u);
  EXPECT_EQ(t.rows[0][3], "44.5");
  // The scene's own brakes (dead time 0) are the first dead-time row.
  EXPECT_EQ(t.rows[0][1], t.rows[1][1]);
  EXPECT_EQ(t.rows[0][2], "0.0");
  for (std::size_t k = 2; k <= 7; ++k) EXPECT_LT(g_of(t.rows[k]), g_of(t.rows[k - 1])) << t.rows[k][0];
  // A 10 m/s² cap is above mu g: no change; lower caps cut G.
  EXPECT_EQ(t.rows[8][1], t.rows[0][1]);
  for (std::size_t k = 10; k < t.rows.size(); ++k) EXPECT_LT(g_of(t.rows[k]), g_of(t.rows[k - 1])) << t.rows[k][0];
  // The first row counts the closed form directly.
  std::size_t feasible = 0, green = 0;
  for (const auto& r : records)
    if (r.feasible) ++feasible, green += sim::analytically_stoppable(r.factors, base) ? 1u : 0u;
  EXPECT_NEAR(g_of(t.rows[0]), 100.0 * static_cast<double>(green) / static_cast<double>(feasible), 0.05);
}

// Issue 40, 7: the caps were 10 to 4 m/s² whatever the grid, flat above 4.9 m/s² at μ 0.5. They
// now run from the grid's friction limit (rounded up to a whole m/s²) down to 40 % of it: the top
// cap changes nothing, and every lower one cuts G.
TEST(BrakeSensitivity, TheCapsSpanTheGridsFrictionLimit) {
  for (const double mu : {1.0, 0.5, 0.3}) {
    const auto s = brake_sensitivity(fine_grid(mu), "fine", sim::ActuationConfig{});
    ASSERT_EQ(s.peak_decels_mps2.size(), 7u);
    const double top = std::ceil(mu * sim::kGravity_mps2);
    EXPECT_DOUBLE_EQ(s.peak_decels_mps2.front(), top) << "mu " << mu;
    EXPECT_NEAR(s.peak_decels_mps2.back(), 0.4 * top, 1e-9) << "mu " << mu;
    EXPECT_GE(s.peak_decels_mps2.front(), mu * sim::kGravity_mps2);
    EXPECT_EQ(s.peak_decel_g_pct.front(), s.base_g_pct) << "a cap above mu g changes nothing, mu " << mu;
    for (std::size_t k = 2; k < s.peak_decel_g_pct.size(); ++k)
      EXPECT_LT(s.peak_decel_g_pct[k], s.peak_decel_g_pct[k - 1]) << "mu " << mu << ", cap " << s.peak_decels_mps2[k];
  }
}

}  // namespace sensitivity_test
}  // namespace emrm::results
