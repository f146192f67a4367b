#pragma once

// Aggregation of a campaign's cell records (docs/results.md): region fractions per grid and the KPIs
// of each strategy over the feasible cells of a grid, overall and by parameter level. Pure
// functions of the records; no simulation. Definitions: docs/results.md.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/error.hpp"
#include "emrm/sim/actuation.hpp"
#include "emrm/sim/factors.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::results {

/// Grid names in order of first appearance in `records`.
[[nodiscard]] std::vector<std::string> grid_names(const std::vector<campaign::CellRecord>& records);
/// The records of one grid, in their stored order.
[[nodiscard]] std::vector<campaign::CellRecord> records_of_grid(const std::vector<campaign::CellRecord>& records,
                                                                std::string_view grid);

/// The grid headline tables and figures read: `wanted` when the records have it, else the grid
/// with the most cells (the first of equals); empty when there are no records.
[[nodiscard]] std::string headline_grid(const std::vector<campaign::CellRecord>& records,
                                        std::string_view wanted = "fine");

/// Region counts of one grid. Percentages are over the feasible cells.
struct RegionCounts {
  std::string grid;
  std::size_t cells = 0;  ///< all cells, infeasible included
  std::size_t feasible = 0;
  std::size_t infeasible = 0;
  std::size_t g = 0, y = 0, o = 0, r = 0;
  /// 100·n / feasible; NaN when there is no feasible cell.
  [[nodiscard]] double pct(std::size_t n) const noexcept;
};

/// Counts the regions of the records whose grid is `grid`. A feasible record whose region is not
/// G, Y, O or R (a corrupt store) throws emrm::Error naming the cell.
[[nodiscard]] RegionCounts count_regions(const std::vector<campaign::CellRecord>& records, std::string_view grid);

/// What a breakdown of the KPIs is by: the factor in a role the method reads (the ego speed, the
/// TTC, the friction, the passage), or the whole grid (none, kWholeGrid).
using Breakdown = std::optional<sim::FactorRole>;
inline constexpr Breakdown kWholeGrid = std::nullopt;
/// The roles the by-parameter tables break the KPIs down by, in their order.
inline constexpr std::array<sim::FactorRole, 4> kBreakdownRoles{sim::FactorRole::kEgoSpeed, sim::FactorRole::kTtc,
                                                                sim::FactorRole::kFriction, sim::FactorRole::kPassage};
/// all, speed, ttc, friction, passage (kpis.csv's "factor" column); "other" for kOther, which no
/// breakdown is by.
[[nodiscard]] std::string_view factor_name(Breakdown f) noexcept;

/// Where the levels of each factor are cut (docs/results.md). Upper bounds are inclusive for speed
/// and TTC (40 km/h is low, 41 medium; 0.7 s is low, 1.3 s medium), lower bounds inclusive for
/// friction (0.35 is medium, 0.7 high); a passage narrower than the car is narrow.
struct LevelCuts {
  double speed_low_max_kph = 40.0;
  double speed_med_max_kph = 56.0;
  double ttc_low_max_s = 0.7;
  double ttc_med_max_s = 1.3;
  double mu_med_min = 0.35;
  double mu_high_min = 0.7;
  double car_width_m = 1.61;
  /// Where the passage stands in the cells (sim::FactorRole::kPassage, set by level_cuts() from the
  /// scene's factor table); none: the scenario has no passage, and every cell counts as wide.
  std::optional<std::size_t> passage_factor;
  /// The scenario's categorical factors (the highway's obstacle and roadside, the street's oncoming
  /// car, the cut-in's following car), set by level_cuts() from the factor table: the by-parameter
  /// table and kpis.csv break the KPIs down by each one's levels too.
  struct Categorical {
    std::size_t index = 0;            ///< its position in the cells
    std::string key;                  ///< "obstacle": kpis.csv's factor
    std::string what;                 ///< "obstacle": the table's row
    std::vector<std::string> levels;  ///< by index: kpis.csv's levels
  };
  std::vector<Categorical> categorical;
};

/// The cuts for a scene: the defaults with its car's width and its passage factor.
[[nodiscard]] LevelCuts level_cuts(const sim::SceneConfig& scene);

/// The cuts for a scene without the paper's levels (an example without a paper_reference.yaml):
/// speed and TTC cut into thirds of their range over the feasible cells of `grid` (rounded to
/// 1 km/h and 0.01 s), friction at the defaults; the defaults when the grid has no feasible cell.
[[nodiscard]] LevelCuts level_cuts_by_thirds(const sim::SceneConfig& scene,
                                             const std::vector<campaign::CellRecord>& records, std::string_view grid);

/// Level names of a factor, in table order: all → {all}; speed, ttc, friction → {low, med, high};
/// passage → {narrow, wide}.
[[nodiscard]] const std::vector<std::string>& level_names(Breakdown f);
/// Human-readable range of a level, e.g. "30-40 km/h" → "<= 40 km/h", "<= 0.7 s", "< 1.61 m".
[[nodiscard]] std::string level_range(Breakdown f, std::string_view level, const LevelCuts& cuts);
/// The level of a cell for a factor. Values within 1e-9 of a cut count as on it (grid values such
/// as 0.25 + 7·0.06 are not exact in binary).
[[nodiscard]] std::string level_of(Breakdown f, const campaign::CellRecord& cell, const LevelCuts& cuts);

/// The KPIs of one strategy over a set of feasible cells (docs/results.md).
struct StrategyKpis {
  std::string grid;
  std::string strategy;
  Breakdown factor = kWholeGrid;
  std::string level = "all";
  std::size_t cells = 0;                          ///< feasible cells with an outcome of this strategy
  std::size_t avoided = 0;                        ///< of which avoided
  std::size_t collisions = 0;                     ///< not avoided (contact or road departure)
  std::size_t mitigated = 0;                      ///< loss level below the unmitigated level
  double collision_avoidance_rate_pct = 0.0;      ///< 100·avoided / cells
  double mean_impact_speed_kph = 0.0;             ///< over all cells, 0 when avoided
  double mean_impact_speed_collisions_kph = 0.0;  ///< over collisions only; NaN without any
  double mean_min_ttc_s = 0.0;                    ///< over cells with a finite minimum TTC; NaN without any
  std::size_t finite_min_ttc = 0;                 ///< cells with a finite minimum TTC
  double mitigability_success_pct = 0.0;          ///< 100·mitigated / cells
  double mean_delta_loss = 0.0;                   ///< mean of unmitigated level − outcome level
  std::size_t beside_oracle = 0;                  ///< of the cells, those with an oracle's outcome too
  /// Of those, where this outcome differs from the oracle's (best_strategy, the best outcome in
  /// hindsight): one avoided and the other not, or another loss (better_record either way).
  std::size_t differs_from_oracle = 0;
  double differs_from_oracle_pct = 0.0;  ///< 100·differs_from_oracle / beside_oracle; NaN without any
};

/// Whether stored outcome `a` is better than `b`, in sim::better_outcome's order: an avoidance beats
/// a failure; between failures sim::less_loss (the level, P(fatal), P(MAIS3+), then Δv).
[[nodiscard]] bool better_record(const campaign::OutcomeRecord& a, const campaign::OutcomeRecord& b);
/// The oracle's name: the first registered chooser that picks in hindsight; empty without one.
[[nodiscard]] std::string oracle_strategy();

/// The controller (`emrm`: the first registered chooser that does not pick in hindsight) against the
/// oracle, over the feasible records that hold both outcomes.
struct OracleComparison {
  std::string controller, oracle;  ///< their names; empty when not registered
  std::size_t cells = 0;           ///< feasible records with both outcomes
  std::size_t differ = 0;          ///< one avoided and the other not, or another loss
  std::size_t only_oracle_avoids = 0;
  std::size_t only_controller_avoids = 0;
  [[nodiscard]] double pct(std::size_t n) const noexcept;  ///< 100·n / cells; NaN without cells
};
[[nodiscard]] OracleComparison compare_with_oracle(const std::vector<campaign::CellRecord>& records);

/// KPIs of `strategy` over the feasible records given (any grid mix; `grid`, `factor` and `level`
/// are only copied into the result). With no matching cell every mean and rate is NaN.
[[nodiscard]] StrategyKpis strategy_kpis(const std::vector<campaign::CellRecord>& records, std::string_view strategy,
                                         std::string_view grid = "", Breakdown factor = kWholeGrid,
                                         std::string_view level = "all");

/// Strategy names in order of first appearance in the records' outcomes.
[[nodiscard]] std::vector<std::string> strategy_names_of(const std::vector<campaign::CellRecord>& records);

/// Every KPI row of one grid: per strategy, the whole grid then each level of speed, TTC, friction
/// and passage (levels with no cell included, with NaN means), in that order.
[[nodiscard]] std::vector<StrategyKpis> grid_kpis(const std::vector<campaign::CellRecord>& records,
                                                  std::string_view grid, const LevelCuts& cuts);

/// The row of `kpis` for a strategy, factor and level, if there is one.
[[nodiscard]] const StrategyKpis* find_kpis(const std::vector<StrategyKpis>& kpis, std::string_view strategy,
                                            Breakdown factor = kWholeGrid, std::string_view level = "all");

}  // namespace emrm::results
