#include "emrm/results/aggregate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "emrm/core/error.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/strategy.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::results {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Grid values such as 0.25 + 0.06·k land a few ulps off their decimal; a cut must not split them.
constexpr double kCutTolerance = 1e-9;

double ratio_pct(std::size_t n, std::size_t total) {
  return total == 0 ? kNaN : 100.0 * static_cast<double>(n) / static_cast<double>(total);
}

}  // namespace

std::vector<std::string> grid_names(const std::vector<campaign::CellRecord>& records) {
  std::vector<std::string> names;
  for (const auto& r : records)
    if (std::find(names.begin(), names.end(), r.grid) == names.end()) names.push_back(r.grid);
  return names;
}

std::vector<campaign::CellRecord> records_of_grid(const std::vector<campaign::CellRecord>& records,
                                                  std::string_view grid) {
  std::vector<campaign::CellRecord> out;
  for (const auto& r : records)
    if (r.grid == grid) out.push_back(r);
  return out;
}

double RegionCounts::pct(std::size_t n) const noexcept { return ratio_pct(n, feasible); }

std::string headline_grid(const std::vector<campaign::CellRecord>& records, std::string_view wanted) {
  std::string best;
  std::size_t best_n = 0;
  for (const auto& g : grid_names(records)) {
    if (g == wanted) return g;
    const auto n = count_regions(records, g).cells;
    if (n > best_n) best = g, best_n = n;
  }
  return best;
}

RegionCounts count_regions(const std::vector<campaign::CellRecord>& records, std::string_view grid) {
  RegionCounts c;
  c.grid = std::string(grid);
  for (const auto& r : records) {
    if (r.grid != grid) continue;
    ++c.cells;
    if (!r.feasible) {
      ++c.infeasible;
      continue;
    }
    ++c.feasible;
    if (r.region == sim::Region::kG)
      ++c.g;
    else if (r.region == sim::Region::kY)
      ++c.y;
    else if (r.region == sim::Region::kO)
      ++c.o;
    else if (r.region == sim::Region::kR)
      ++c.r;
    else
      throw Error(fmt::format("cell {} of grid '{}' is feasible but its region is '{}' (expected G, Y, O or R)",
                              r.index, r.grid, core::enum_name(r.region)));
  }
  return c;
}

LevelCuts level_cuts(const sim::SceneConfig& scene) {
  LevelCuts cuts;
  cuts.car_width_m = scene.ego.width_m;
  const sim::FactorTable factors = sim::scenario_factors(scene);
  cuts.passage_factor = factors.find(sim::FactorRole::kPassage);
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (factors[i].categorical()) cuts.categorical.push_back({i, factors[i].key, factors[i].what, factors[i].levels});
  return cuts;
}

LevelCuts level_cuts_by_thirds(const sim::SceneConfig& scene, const std::vector<campaign::CellRecord>& records,
                               std::string_view grid) {
  LevelCuts cuts = level_cuts(scene);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double v_low = kInf, v_high = -kInf, t_low = kInf, t_high = -kInf;
  for (const auto& r : records) {
    if (!r.feasible || r.grid != grid) continue;
    v_low = std::min(v_low, r.factors.ego_speed_kph());
    v_high = std::max(v_high, r.factors.ego_speed_kph());
    t_low = std::min(t_low, r.factors.time_to_collision_s());
    t_high = std::max(t_high, r.factors.time_to_collision_s());
  }
  if (v_low > v_high) return cuts;  // no feasible cell: the defaults
  // A third of the range, rounded to the grid's own precision so that the labels read as written.
  const auto third = [](double low, double high, double k, double unit) {
    return std::round((low + k * (high - low) / 3.0) / unit) * unit;
  };
  cuts.speed_low_max_kph = third(v_low, v_high, 1.0, 1.0);
  cuts.speed_med_max_kph = third(v_low, v_high, 2.0, 1.0);
  cuts.ttc_low_max_s = third(t_low, t_high, 1.0, 0.01);
  cuts.ttc_med_max_s = third(t_low, t_high, 2.0, 0.01);
  return cuts;
}

std::string_view factor_name(Breakdown f) noexcept { return f ? core::enum_name(*f) : "all"; }

const std::vector<std::string>& level_names(Breakdown f) {
  static const std::vector<std::string> all{"all"};
  static const std::vector<std::string> three{"low", "med", "high"};
  static const std::vector<std::string> passage{"narrow", "wide"};
  if (!f || *f == sim::FactorRole::kOther) return all;
  return *f == sim::FactorRole::kPassage ? passage : three;
}

std::string level_range(Breakdown f, std::string_view level, const LevelCuts& c) {
  if (!f) return "all";
  switch (*f) {
    case sim::FactorRole::kEgoSpeed:
      if (level == "low") return fmt::format("<= {:g} km/h", c.speed_low_max_kph);
      if (level == "med") return fmt::format("{:g}-{:g} km/h", c.speed_low_max_kph, c.speed_med_max_kph);
      return fmt::format("> {:g} km/h", c.speed_med_max_kph);
    case sim::FactorRole::kTtc:
      if (level == "low") return fmt::format("<= {:g} s", c.ttc_low_max_s);
      if (level == "med") return fmt::format("{:g}-{:g} s", c.ttc_low_max_s, c.ttc_med_max_s);
      return fmt::format("> {:g} s", c.ttc_med_max_s);
    case sim::FactorRole::kFriction:
      if (level == "low") return fmt::format("mu < {:g}", c.mu_med_min);
      if (level == "med") return fmt::format("{:g} <= mu < {:g}", c.mu_med_min, c.mu_high_min);
      return fmt::format("mu >= {:g}", c.mu_high_min);
    case sim::FactorRole::kPassage:
      if (level == "narrow") return fmt::format("< {:g} m", c.car_width_m);
      return fmt::format(">= {:g} m", c.car_width_m);
    case sim::FactorRole::kOther:
      break;
  }
  return std::string(level);
}

std::string level_of(Breakdown f, const campaign::CellRecord& cell, const LevelCuts& c) {
  if (!f) return "all";
  switch (*f) {
    case sim::FactorRole::kEgoSpeed:
      if (cell.factors.ego_speed_kph() <= c.speed_low_max_kph + kCutTolerance) return "low";
      if (cell.factors.ego_speed_kph() <= c.speed_med_max_kph + kCutTolerance) return "med";
      return "high";
    case sim::FactorRole::kTtc:
      if (cell.factors.time_to_collision_s() <= c.ttc_low_max_s + kCutTolerance) return "low";
      if (cell.factors.time_to_collision_s() <= c.ttc_med_max_s + kCutTolerance) return "med";
      return "high";
    case sim::FactorRole::kFriction:
      if (cell.factors.friction() < c.mu_med_min - kCutTolerance) return "low";
      if (cell.factors.friction() < c.mu_high_min - kCutTolerance) return "med";
      return "high";
    case sim::FactorRole::kPassage:
      return c.passage_factor && cell.factors[*c.passage_factor] < c.car_width_m - kCutTolerance ? "narrow" : "wide";
    case sim::FactorRole::kOther:
      break;
  }
  return "all";
}

StrategyKpis strategy_kpis(const std::vector<campaign::CellRecord>& records, std::string_view strategy,
                           std::string_view grid, Breakdown factor, std::string_view level) {
  StrategyKpis k;
  k.grid = std::string(grid);
  k.strategy = std::string(strategy);
  k.factor = factor;
  k.level = std::string(level);
  double impact_sum = 0.0, ttc_sum = 0.0, delta_loss_sum = 0.0;
  const std::string oracle = oracle_strategy();
  for (const auto& cell : records) {
    if (!cell.feasible) continue;
    const campaign::OutcomeRecord* o = cell.outcome(strategy);
    if (o == nullptr) continue;
    ++k.cells;
    if (const campaign::OutcomeRecord* best = oracle.empty() ? nullptr : cell.outcome(oracle)) {
      ++k.beside_oracle;
      if (better_record(*o, *best) || better_record(*best, *o)) ++k.differs_from_oracle;
    }
    if (o->avoided) {
      ++k.avoided;
    } else {
      ++k.collisions;
      impact_sum += o->impact_speed_kph;
    }
    // An avoided cell has level 0, so it counts as mitigated exactly when there was a loss to avoid.
    const int level_reached = o->avoided ? 0 : o->loss_level;
    if (level_reached < cell.unmitigated_loss_level) ++k.mitigated;
    if (std::isfinite(o->min_ttc_s)) {
      ++k.finite_min_ttc;
      ttc_sum += o->min_ttc_s;
    }
    delta_loss_sum += o->delta_loss;
  }
  const auto n = static_cast<double>(k.cells);
  k.collision_avoidance_rate_pct = ratio_pct(k.avoided, k.cells);
  k.mitigability_success_pct = ratio_pct(k.mitigated, k.cells);
  k.mean_impact_speed_kph = k.cells == 0 ? kNaN : impact_sum / n;
  k.mean_impact_speed_collisions_kph = k.collisions == 0 ? kNaN : impact_sum / static_cast<double>(k.collisions);
  k.mean_min_ttc_s = k.finite_min_ttc == 0 ? kNaN : ttc_sum / static_cast<double>(k.finite_min_ttc);
  k.mean_delta_loss = k.cells == 0 ? kNaN : delta_loss_sum / n;
  k.differs_from_oracle_pct = ratio_pct(k.differs_from_oracle, k.beside_oracle);
  return k;
}

bool better_record(const campaign::OutcomeRecord& a, const campaign::OutcomeRecord& b) {
  if (a.avoided != b.avoided) return a.avoided;
  if (a.avoided) return false;
  const auto impact = [](const campaign::OutcomeRecord& o) {
    sim::ImpactAssessment i;
    i.loss_level = o.loss_level;
    i.p_fatal = o.p_fatal;
    i.p_mais3 = o.p_mais3;
    i.delta_v_mps = o.delta_v_kph / 3.6;
    return i;
  };
  return sim::less_loss(impact(a), impact(b));
}

std::string oracle_strategy() {
  for (const auto& entry : sim::registered_strategies().entries())
    if (entry.info.role == sim::StrategyRole::kChooser && entry.info.hindsight) return entry.info.name;
  return {};
}

double OracleComparison::pct(std::size_t n) const noexcept { return ratio_pct(n, cells); }

OracleComparison compare_with_oracle(const std::vector<campaign::CellRecord>& records) {
  OracleComparison c;
  c.oracle = oracle_strategy();
  for (const auto& entry : sim::registered_strategies().entries())
    if (entry.info.role == sim::StrategyRole::kChooser && !entry.info.hindsight) {
      c.controller = entry.info.name;
      break;
    }
  if (c.oracle.empty() || c.controller.empty()) return c;
  for (const auto& r : records) {
    const campaign::OutcomeRecord* mine = r.feasible ? r.outcome(c.controller) : nullptr;
    const campaign::OutcomeRecord* best = r.feasible ? r.outcome(c.oracle) : nullptr;
    if (mine == nullptr || best == nullptr) continue;
    ++c.cells;
    if (better_record(*mine, *best) || better_record(*best, *mine)) ++c.differ;
    c.only_oracle_avoids += best->avoided && !mine->avoided;
    c.only_controller_avoids += mine->avoided && !best->avoided;
  }
  return c;
}

std::vector<std::string> strategy_names_of(const std::vector<campaign::CellRecord>& records) {
  std::vector<std::string> names;
  for (const auto& r : records)
    for (const auto& o : r.outcomes)
      if (std::find(names.begin(), names.end(), o.strategy) == names.end()) names.push_back(o.strategy);
  return names;
}

std::vector<StrategyKpis> grid_kpis(const std::vector<campaign::CellRecord>& records, std::string_view grid,
                                    const LevelCuts& cuts) {
  const auto cells = records_of_grid(records, grid);
  struct Subset {
    Breakdown factor;
    std::string level;
    std::vector<campaign::CellRecord> cells;
  };
  std::vector<Subset> subsets;
  std::vector<Breakdown> breakdowns{kWholeGrid};
  breakdowns.insert(breakdowns.end(), kBreakdownRoles.begin(), kBreakdownRoles.end());
  for (const Breakdown f : breakdowns) {
    for (const auto& level : level_names(f)) {
      Subset s{f, level, {}};
      for (const auto& c : cells)
        if (level_of(f, c, cuts) == level) s.cells.push_back(c);
      subsets.push_back(std::move(s));
    }
  }
  std::vector<StrategyKpis> out;
  for (const auto& strategy : strategy_names_of(cells))
    for (const auto& s : subsets) out.push_back(strategy_kpis(s.cells, strategy, grid, s.factor, s.level));
  return out;
}

const StrategyKpis* find_kpis(const std::vector<StrategyKpis>& kpis, std::string_view strategy, Breakdown factor,
                              std::string_view level) {
  for (const auto& k : kpis)
    if (k.strategy == strategy && k.factor == factor && k.level == level) return &k;
  return nullptr;
}

}  // namespace emrm::results
