// The figures tests' shared parts: a synthetic campaign, the checks of a drawn figure, the fixtures.

#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/report/plan_figures.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "tjunction.hpp"

namespace emrm::report {
namespace figures_test {

namespace fs = std::filesystem;
using campaign::CellRecord;
using campaign::OutcomeRecord;

const std::vector<std::string> kStrategies{"emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident", "emrm"};

// --- a synthetic campaign ---------------------------------------------------------------------
// Regions by a simple rule: infeasible beyond 45 m of initial distance; G when the analytic stop
// boundary says the stop avoids; Y when there is still time and grip to steer; O at lower speeds;
// R otherwise. Each strategy avoids in a subset of the cells, so every rate lies strictly between
// 0 and 100 and differs between strategies.
inline OutcomeRecord outcome(const std::string& strategy, bool avoided, double impact_kph, int level, int unmitigated) {
  OutcomeRecord o;
  o.strategy = strategy;
  o.avoided = avoided;
  o.contact = !avoided;
  o.impact_speed_kph = avoided ? 0.0 : impact_kph;
  o.loss_level = avoided ? 0 : level;
  o.delta_loss = unmitigated - o.loss_level;
  o.min_ttc_s = avoided ? 0.5 : 0.0;
  return o;
}

inline CellRecord synthetic_cell(const std::string& grid, std::int64_t index, double speed, double ttc, double mu) {
  CellRecord c;
  c.grid = grid;
  c.index = index;
  c.factors = sim::TJunctionCell{speed, ttc, mu, 3.0, 10.0};
  c.feasible = speed / 3.6 * ttc <= 45.0;
  if (!c.feasible) {
    c.region = sim::Region::kInfeasible;
    return c;
  }
  const bool stoppable = sim::analytically_stoppable(speed, ttc, mu, sim::ActuationConfig{});
  const bool steerable = ttc >= 0.6 && mu >= 0.3;
  c.region = stoppable      ? sim::Region::kG
             : steerable    ? sim::Region::kY
             : speed < 45.0 ? sim::Region::kO
                            : sim::Region::kR;
  // Every seventh O/R cell rests on a failed search only; the others on a certificate.
  c.evidence = c.region == sim::Region::kG || c.region == sim::Region::kY ? campaign::CellEvidence::kWitness
               : index % 7 == 0                                           ? campaign::CellEvidence::kUndecided
                                                                          : campaign::CellEvidence::kCertificate;
  c.unmitigated_loss_level = speed > 50.0 ? 7 : 6;
  c.unmitigated_impact_speed_kph = speed;
  // Harm reduction: an avoidance removes the whole risk, a mitigation part of it, and half the R
  // cells lower the risk inside their loss level.
  c.unmitigated_p_mais3 = std::min(0.95, std::pow(speed / 80.0, 3.0));
  c.unmitigated_p_fatal = 0.3 * c.unmitigated_p_mais3;
  const double kept = c.region == sim::Region::kO   ? 0.4
                      : c.region == sim::Region::kR ? (index % 2 == 0 ? 0.75 : 1.0)
                                                    : 0.0;
  c.p_mais3_reduction = (1.0 - kept) * c.unmitigated_p_mais3;
  c.p_fatal_reduction = (1.0 - kept) * c.unmitigated_p_fatal;
  const int u = c.unmitigated_loss_level;
  const int lowered = c.region == sim::Region::kO ? u - 2 : u;
  c.outcomes = {
      outcome("emergency_stop", stoppable, 0.5 * speed, c.region == sim::Region::kO ? u - 1 : u, u),
      outcome("dodge", stoppable || steerable, 0.6 * speed, lowered, u),
      outcome("drift_to_avoid", stoppable || (steerable && speed < 60.0), 0.55 * speed, lowered, u),
      outcome("drift_to_accident", stoppable || (steerable && index % 3 != 0), 0.4 * speed, u - 1, u),
      outcome("emrm", stoppable || steerable, 0.45 * speed, lowered, u),
  };
  return c;
}

// The shipped campaign's four map grids: coarse 5 × 6, fine 43 × 46, speed × μ 43 × 10,
// TTC × μ 26 × 10: 2698 cells.
inline std::vector<CellRecord> synthetic_campaign() {
  std::vector<CellRecord> records;
  std::int64_t i = 0;
  for (int s = 0; s < 5; ++s)
    for (int t = 0; t < 6; ++t) records.push_back(synthetic_cell("coarse", i++, 30.0 + 10.5 * s, 0.25 + 0.54 * t, 1.0));
  i = 0;
  for (int s = 0; s < 43; ++s)
    for (int t = 0; t < 46; ++t) records.push_back(synthetic_cell("fine", i++, 30.0 + s, 0.25 + 0.06 * t, 1.0));
  i = 0;
  for (int s = 0; s < 43; ++s)
    for (int m = 0; m < 10; ++m) records.push_back(synthetic_cell("speed_mu", i++, 30.0 + s, 1.0, 0.1 + 0.1 * m));
  i = 0;
  for (int t = 0; t < 26; ++t)
    for (int m = 0; m < 10; ++m)
      records.push_back(synthetic_cell("ttc_mu", i++, 50.0, 0.25 + 0.108 * t, 0.1 + 0.1 * m));
  return records;
}

inline const std::vector<CellRecord>& campaign_records() {
  static const std::vector<CellRecord> records = synthetic_campaign();
  return records;
}

inline std::vector<CellRecord> without_grid(const std::string& grid) {
  std::vector<CellRecord> out;
  for (const auto& r : campaign_records())
    if (r.grid != grid) out.push_back(r);
  return out;
}

// --- checks -----------------------------------------------------------------------------------

inline void expect_png(const fs::path& path) {
  const std::string bytes = core::read_file(path);
  ASSERT_GT(bytes.size(), 5000u) << path;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
}

inline void expect_svg(const fs::path& path) {
  const std::string text = core::read_file(path);
  ASSERT_GT(text.size(), 1000u) << path;
  EXPECT_TRUE(text.rfind("<?xml", 0) == 0 || text.rfind("<svg", 0) == 0) << path;
  EXPECT_NE(text.find("</svg>"), std::string::npos) << path;
}

inline void expect_drawn(const Figure& f, const fs::path& dir, const std::string& name) {
  EXPECT_EQ(f.name, name);
  EXPECT_EQ(f.png, dir / (name + ".png"));
  EXPECT_EQ(f.svg, dir / (name + ".svg"));
  EXPECT_EQ(f.csv, dir / (name + ".csv"));
  EXPECT_FALSE(f.title.empty());
  expect_png(f.png);
  expect_svg(f.svg);
}

inline void expect_nothing_written(const Figure& f, const fs::path& dir) {
  EXPECT_FALSE(f.note.empty());
  EXPECT_FALSE(f.title.empty());  // the report still names the figure it could not draw
  EXPECT_TRUE(f.png.empty() && f.svg.empty() && f.csv.empty());
  EXPECT_TRUE(!fs::exists(dir) || fs::is_empty(dir)) << dir;
}

/// The CSV's header then its rows, as field lists.
inline std::vector<core::Row> csv_of(const fs::path& path) {
  std::vector<core::Row> rows;
  for (auto& r : core::parse_csv(core::read_file(path), path.string())) rows.push_back(std::move(r.fields));
  return rows;
}

/// The position of column `name` in a CSV's header row (a factor's column moves with the table).
inline std::size_t column_of(const std::vector<core::Row>& csv, const std::string& name) {
  const auto at = std::find(csv.front().begin(), csv.front().end(), name);
  EXPECT_NE(at, csv.front().end()) << name;
  return static_cast<std::size_t>(at - csv.front().begin());
}

inline double num(const std::string& field) { return std::strtod(field.c_str(), nullptr); }

// The maps of the T-junction's records (its factor table with the default scene).
template <class... Rest>
Figure draw_mitigability_map_t(const std::vector<CellRecord>& records, Rest&&... rest) {
  return draw_mitigability_map(records, test::tjunction_factors(), std::forward<Rest>(rest)...);
}
template <class... Rest>
Figure draw_harm_reduction_map_t(const std::vector<CellRecord>& records, Rest&&... rest) {
  return draw_harm_reduction_map(records, test::tjunction_factors(), std::forward<Rest>(rest)...);
}
template <class... Rest>
std::vector<Figure> draw_grid_maps_t(const std::vector<CellRecord>& records, Rest&&... rest) {
  return draw_grid_maps(records, test::tjunction_factors(), std::forward<Rest>(rest)...);
}

// Rates recomputed here, independently of the aggregation, from the definitions of docs/results.md.
struct Rates {
  std::size_t cells = 0;
  double car_pct = 0.0, impact_kph = 0.0, mitigated_pct = 0.0;
};

inline Rates rates_of(const std::vector<CellRecord>& records, const std::string& strategy,
                      double speed_kph = std::nan("")) {
  Rates r;
  std::size_t avoided = 0, mitigated = 0;
  double impact = 0.0;
  for (const auto& c : records) {
    if (!c.feasible || (!std::isnan(speed_kph) && std::abs(c.factors.ego_speed_kph() - speed_kph) > 1e-9)) continue;
    for (const auto& o : c.outcomes) {
      if (o.strategy != strategy) continue;
      ++r.cells;
      if (o.avoided) ++avoided;
      if (!o.avoided) impact += o.impact_speed_kph;
      if ((o.avoided ? 0 : o.loss_level) < c.unmitigated_loss_level) ++mitigated;
    }
  }
  const auto n = static_cast<double>(r.cells);
  r.car_pct = 100.0 * static_cast<double>(avoided) / n;
  r.mitigated_pct = 100.0 * static_cast<double>(mitigated) / n;
  r.impact_kph = impact / n;
  return r;
}

class FigureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!core::find_program("gnuplot")) GTEST_SKIP() << "gnuplot is not installed";
  }
  fs::path out() const { return tmp_.path() / "figures"; }
  core::TempDir tmp_{"emrm-figures-test"};
};

// Drawing nothing needs no gnuplot, so these run everywhere.
class FigureEmpty : public ::testing::Test {
 protected:
  fs::path out() const { return tmp_.path() / "figures"; }
  core::TempDir tmp_{"emrm-figures-test"};
};

}  // namespace figures_test
}  // namespace emrm::report
