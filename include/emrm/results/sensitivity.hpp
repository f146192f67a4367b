#pragma once

// How the brakes move the map (docs/actuation.md, "Sensitivity"): the G share of a grid against
// the brake dead time and the peak deceleration, from the stop's closed form (no sweep).

#include <string_view>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/table.hpp"
#include "emrm/results/paper_reference.hpp"
#include "emrm/sim/actuation.hpp"

namespace emrm::results {

/// G (%) of `grid`'s feasible cells under `base`, and with one brake parameter changed at a time.
struct BrakeSensitivity {
  double base_g_pct = 0.0;
  std::vector<double> dead_times_s;  ///< 0, 0.1, …, 0.6
  std::vector<double> dead_time_g_pct;
  std::vector<double> peak_decels_mps2;  ///< ⌈μ_max g⌉ down to 40 % of it in 7 steps (10, 9, …, 4 at μ 1)
  std::vector<double> peak_decel_g_pct;
};
[[nodiscard]] BrakeSensitivity brake_sensitivity(const std::vector<campaign::CellRecord>& records,
                                                 std::string_view grid, const sim::ActuationConfig& base);

/// Rows: the scene's own brakes, then brake dead time 0–0.6 s in 0.1 s steps, then peak
/// deceleration from the grid's friction limit (the largest μ of its feasible cells times g,
/// rounded up to a whole m/s²) down to 40 % of it (each row changes one parameter of `base`); columns: G %, the change
/// from the scene's, and the paper's G where `grid` is the paper's fine grid.
[[nodiscard]] core::Table brake_sensitivity_table(const std::vector<campaign::CellRecord>& records,
                                                  const PaperReference& paper, std::string_view grid,
                                                  const sim::ActuationConfig& base);

}  // namespace emrm::results
