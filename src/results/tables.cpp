#include "emrm/results/tables.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <utility>

#include "emrm/core/text.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::results {
namespace {

using core::format_number;
using core::kNoValue;
using core::Table;

// ---- numbers --------------------------------------------------------------------------------

std::string paper_number(double v) { return fmt::format("{:g}", v); }

std::string ours_beside(double ours, int decimals, std::optional<double> paper, int paper_decimals) {
  if (!paper) return format_number(ours, decimals);
  return fmt::format("{} (paper {})", format_number(ours, decimals), format_number(*paper, paper_decimals));
}

std::vector<const campaign::CellRecord*> feasible_of(const std::vector<campaign::CellRecord>& records,
                                                     std::string_view grid) {
  std::vector<const campaign::CellRecord*> out;
  for (const auto& r : records)
    if (r.feasible && (grid.empty() || r.grid == grid)) out.push_back(&r);
  return out;
}

std::vector<campaign::CellRecord> subset(const std::vector<campaign::CellRecord>& records, std::string_view grid,
                                         Breakdown f, std::string_view level, const LevelCuts& cuts) {
  std::vector<campaign::CellRecord> out;
  for (const auto& r : records)
    if ((grid.empty() || r.grid == grid) && level_of(f, r, cuts) == level) out.push_back(r);
  return out;
}

// The cells of `grid` (all grids when empty) at level `level` of a categorical factor.
std::vector<campaign::CellRecord> subset(const std::vector<campaign::CellRecord>& records, std::string_view grid,
                                         const LevelCuts::Categorical& factor, std::size_t level) {
  std::vector<campaign::CellRecord> out;
  for (const auto& r : records)
    if ((grid.empty() || r.grid == grid) && factor.index < r.factors.size() &&
        r.factors[factor.index] == static_cast<double>(level))
      out.push_back(r);
  return out;
}

bool has_grid(const std::vector<campaign::CellRecord>& records, std::string_view grid) {
  return std::any_of(records.begin(), records.end(), [&](const campaign::CellRecord& r) { return r.grid == grid; });
}

// Strategies are named by their registered records (sim/strategy.hpp); a name the registry does
// not know (a store written with a strategy registered then) stands for itself.
std::string strategy_title(std::string_view s) {
  const sim::StrategyTable strategies = sim::registered_strategies();
  const sim::StrategyInfo* info = strategies.info(s);
  return info != nullptr ? info->title : std::string(s);
}

std::string strategy_label(std::string_view s) {
  const sim::StrategyTable strategies = sim::registered_strategies();
  const sim::StrategyInfo* info = strategies.info(s);
  return info != nullptr ? info->label : std::string(s);
}

std::string first_name_of(sim::StrategyRole role) {
  const sim::StrategyTable strategies = sim::registered_strategies();
  const sim::StrategyInfo* info = strategies.first_of(role);
  return info != nullptr ? info->name : std::string();
}

bool is_chooser(std::string_view s) {
  const sim::StrategyTable strategies = sim::registered_strategies();
  const sim::StrategyInfo* info = strategies.info(s);
  return info != nullptr && info->role == sim::StrategyRole::kChooser;
}

// The controller against the oracle over `cells`; empty without both.
std::string controller_vs_oracle_note(const std::vector<campaign::CellRecord>& cells) {
  const OracleComparison c = compare_with_oracle(cells);
  if (c.cells == 0) return {};
  return fmt::format(
      "`{}` is a controller: it chooses from its own predictions (the stop rolled out, the evasive strategies "
      "planned with the on-board budget, scene.controller) and is judged on what its maneuver does; `{}`, the "
      "oracle, is the best simulated outcome of the strategies EMRM may choose and of the controller, in "
      "hindsight. Their outcomes "
      "differ in {} of {} cells ({} %): in {} only the oracle avoids, in {} only the controller does.",
      c.controller, c.oracle, c.differ, c.cells, format_number(c.pct(c.differ), 1), c.only_oracle_avoids,
      c.only_controller_avoids);
}

std::string difference_phrase(double ours, double paper, double tolerance, std::string_view unit) {
  if (std::isnan(ours)) return "no cells of ours";
  const double d = ours - paper;
  if (std::abs(d) <= tolerance) return fmt::format("agrees within {:g}{}", tolerance, unit);
  return fmt::format("{} by {:.1f}{}", d > 0 ? "higher" : "lower", std::abs(d), unit);
}

}  // namespace

// ---- the tables -----------------------------------------------------------------------------

Table emrm_vs_baseline_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                             std::string_view grid) {
  const auto cells = records_of_grid(records, grid);
  const auto feasible = feasible_of(records, grid).size();
  Table t;
  t.title = fmt::format("EMRM vs emergency stop (grid '{}', {} feasible cells{})", grid, feasible,
                        paper.empty() ? "" : fmt::format("; paper: {} cells", paper.emrm_vs_baseline.cells));
  t.header = {"Metric"};
  std::vector<StrategyKpis> kpis;
  std::vector<const PaperBaselineColumn*> columns;
  for (const auto& c : paper.emrm_vs_baseline.columns) {
    t.header.push_back(c.label + " (" + c.strategy + ")");
    kpis.push_back(strategy_kpis(cells, c.strategy, grid));
    columns.push_back(&c);
  }
  // Strategies the paper has no column for (drift to accident) are shown for completeness.
  std::vector<std::string> ours_only;
  for (const auto& entry : sim::registered_strategies().entries()) {
    const auto& info = entry.info;
    if (std::any_of(columns.begin(), columns.end(), [&](const auto* c) { return c->strategy == info.name; })) continue;
    t.header.push_back(fmt::format("{} ({}{})", info.title, info.name, paper.empty() ? "" : ", ours only"));
    kpis.push_back(strategy_kpis(cells, info.name, grid));
    ours_only.push_back(fmt::format("`{}`", info.name));
  }
  // The paper prints rates as whole percent, speeds with one decimal and ΔLoss with two.
  const auto row = [&](std::string name, int decimals, int paper_decimals, double StrategyKpis::*ours,
                       double PaperBaselineColumn::*theirs) {
    core::Row r{std::move(name)};
    for (std::size_t i = 0; i < kpis.size(); ++i) {
      std::optional<double> p;
      if (i < columns.size() && theirs != nullptr) p = columns[i]->*theirs;
      r.push_back(ours_beside(kpis[i].*ours, decimals, p, paper_decimals));
    }
    t.rows.push_back(std::move(r));
  };
  row("Collision Avoidance Rate (%)", 1, 0, &StrategyKpis::collision_avoidance_rate_pct,
      &PaperBaselineColumn::collision_avoidance_rate_pct);
  row("Mean Residual Impact Speed (km/h)", 1, 1, &StrategyKpis::mean_impact_speed_kph,
      &PaperBaselineColumn::mean_residual_impact_speed_kph);
  row("Mitigability Success (%)", 1, 0, &StrategyKpis::mitigability_success_pct,
      &PaperBaselineColumn::mitigability_success_pct);
  row("ΔLoss (avg. level reduction)", 2, 2, &StrategyKpis::mean_delta_loss, &PaperBaselineColumn::delta_loss);
  row("Mean impact speed, collisions only (km/h)", 1, 1, &StrategyKpis::mean_impact_speed_collisions_kph, nullptr);
  row("Mean minimum TTC (s)", 2, 2, &StrategyKpis::mean_min_ttc_s, nullptr);
  // How far each column is from the best outcome in hindsight (the oracle's own column reads 0).
  if (std::any_of(kpis.begin(), kpis.end(), [](const StrategyKpis& k) { return k.beside_oracle > 0; }))
    row("Outcome differs from the oracle's (% of cells)", 1, 0, &StrategyKpis::differs_from_oracle_pct, nullptr);
  const std::string controller_vs_oracle = controller_vs_oracle_note(cells);

  // ΔLoss cannot exceed the mean unmitigated level: the number that explains a ΔLoss gap.
  double unmitigated_sum = 0.0;
  for (const auto* r : feasible_of(records, grid)) unmitigated_sum += r->unmitigated_loss_level;
  const double mean_unmitigated =
      feasible == 0 ? std::numeric_limits<double>::quiet_NaN() : unmitigated_sum / static_cast<double>(feasible);
  const auto delta_loss_bound = [&](std::string_view levels) {
    return fmt::format(
        "ΔLoss counts levels {} (an avoided L7 cell counts 7), so it is bounded by the mean unmitigated level, {} on "
        "our cells; mitigability success counts a cell when its level is below the unmitigated level.",
        levels, format_number(mean_unmitigated, 2));
  };
  if (paper.empty()) {
    t.notes.push_back(
        "Each column is one of our strategies; no published numbers stand beside them (the example has no "
        "paper_reference.yaml). Our emergency stop avoids exactly the cells on or above its stop boundary through "
        "the actuators (diagnostics.json); the evasive strategies are a seeded RRT on our single-track model. " +
        delta_loss_bound("L0-L7"));
    if (!controller_vs_oracle.empty()) t.notes.push_back(controller_vs_oracle);
    return t;
  }
  std::vector<std::string> mapping;
  for (const auto* c : columns) mapping.push_back(fmt::format("\"{}\" is our `{}`", c->label, c->strategy));
  t.notes.push_back("Each cell reads \"ours (paper N)\". Columns: " + core::join(mapping, ", ") +
                    (ours_only.empty() ? std::string(".")
                                       : fmt::format("; {} {} ours only.", core::join(ours_only, ", "),
                                                     ours_only.size() == 1 ? "is" : "are")) +
                    " The paper's \"EMRM (All)\" is the EMRM feature choosing a strategy through the loss-evaluation "
                    "FSM, which is our `emrm`: a controller that decides from its own predictions and commits before "
                    "it knows the outcome.");
  if (!controller_vs_oracle.empty()) t.notes.push_back(controller_vs_oracle);
  std::vector<std::string> diffs;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const auto& k = kpis[i];
    const auto& c = *columns[i];
    diffs.push_back(
        fmt::format("{}: avoidance {} ({} vs {:g} %), residual impact speed {} ({} vs {:g} km/h)", c.label,
                    difference_phrase(k.collision_avoidance_rate_pct, c.collision_avoidance_rate_pct, 2.0, " points"),
                    format_number(k.collision_avoidance_rate_pct, 1), c.collision_avoidance_rate_pct,
                    difference_phrase(k.mean_impact_speed_kph, c.mean_residual_impact_speed_kph, 1.0, " km/h"),
                    format_number(k.mean_impact_speed_kph, 1), c.mean_residual_impact_speed_kph));
  }
  t.notes.push_back("Where ours differ: " + core::join(diffs, "; ") + ".");
  std::string why = fmt::format(
      "Why: our grid has {} feasible cells against the paper's {} (feasibility is v·TTC within the scene's "
      "max_initial_distance_m). Our emergency stop is full ABS braking, so it avoids exactly the cells above "
      "the "
      "analytic stop boundary TTC ≥ v/(2μg) (see diagnostics.json), and the evasive strategies are a "
      "seeded RRT on our single-track model, not the paper's planner. {} Road departures are L4 "
      "(docs/decisions.md).",
      feasible, paper.emrm_vs_baseline.cells, delta_loss_bound("L0/L4/L6/L7"));
  t.notes.push_back(why);
  return t;
}

Table by_parameter_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                         std::string_view grid, std::string_view passage_grid, std::string_view friction_grid,
                         const LevelCuts& cuts) {
  Table t;
  t.title = fmt::format("Collision avoidance (%) by parameter level (grid '{}'{})", grid,
                        !cuts.passage_factor   ? ""
                        : passage_grid.empty() ? "; passage: 'all grids'"
                                               : fmt::format("; passage: '{}'", passage_grid));
  std::vector<std::string> strategies = paper.by_parameter.strategies;
  if (strategies.empty())  // the paper's columns; without them, ours in evaluation order
    for (const auto& entry : sim::registered_strategies().entries())
      if (entry.info.role != sim::StrategyRole::kChooser) strategies.push_back(entry.info.name);
  t.header = {"Parameter Level"};
  for (const auto& s : strategies) t.header.push_back(strategy_title(s) + " (%)");
  t.header.push_back("Tests");

  struct Largest {
    double gap = -1.0;
    std::string where;
  } largest;
  // A row over `levels`, the cells of level i those cells_of(i) gives.
  const auto add_levels_row = [&](std::string label, std::string_view on_grid, Breakdown f,
                                  const std::vector<std::string>& levels, const PaperByParameterRow* p,
                                  const std::function<std::vector<campaign::CellRecord>(std::size_t)>& cells_of) {
    core::Row r{std::move(label)};
    std::vector<std::size_t> counts(levels.size(), 0);
    for (const auto& s : strategies) {
      std::vector<std::string> ours, theirs;
      for (std::size_t i = 0; i < levels.size(); ++i) {
        const auto k = strategy_kpis(cells_of(i), s, on_grid, f, levels[i]);
        counts[i] = k.cells;
        ours.push_back(format_number(k.collision_avoidance_rate_pct, 0));
        if (p != nullptr && p->values.of(s) != nullptr) {
          const double pv = (*p->values.of(s))[i];
          theirs.push_back(paper_number(pv));
          if (!std::isnan(k.collision_avoidance_rate_pct) &&
              std::abs(k.collision_avoidance_rate_pct - pv) > largest.gap) {
            largest.gap = std::abs(k.collision_avoidance_rate_pct - pv);
            largest.where = fmt::format("{} at {} {} ({} vs paper {:g})", strategy_title(s), factor_name(f), levels[i],
                                        format_number(k.collision_avoidance_rate_pct, 0), pv);
          }
        }
      }
      r.push_back(core::join(ours, " / ") + (p && !theirs.empty() ? " (paper " + core::join(theirs, " / ") + ")" : ""));
    }
    std::vector<std::string> n;
    for (auto c : counts) n.push_back(std::to_string(c));
    std::vector<std::string> pn;
    if (p)
      for (int c : p->tests) pn.push_back(std::to_string(c));
    r.push_back(core::join(n, " / ") + (p ? " (paper " + core::join(pn, " / ") + ")" : ""));
    t.rows.push_back(std::move(r));
  };
  const auto add_row = [&](std::string label, std::string_view on_grid, Breakdown f,
                           const std::vector<std::string>& levels, const PaperByParameterRow* p) {
    add_levels_row(std::move(label), on_grid, f, levels, p,
                   [&](std::size_t i) { return subset(records, on_grid, f, levels[i], cuts); });
  };

  const auto range_label = [&](Breakdown f, const std::vector<std::string>& levels) {
    std::vector<std::string> parts;
    for (const auto& l : levels) parts.push_back(l + " (" + level_range(f, l, cuts) + ")");
    return core::join(parts, " / ");
  };
  for (const Breakdown f : kBreakdownRoles) {
    if (f == sim::FactorRole::kPassage && !cuts.passage_factor) continue;  // a scene without a passage
    const auto* p = paper.by_parameter_row(factor_name(f));
    const std::vector<std::string> levels = p ? p->levels : level_names(f);
    const std::string_view on_grid = f == sim::FactorRole::kPassage ? passage_grid : grid;
    const std::string name = f == sim::FactorRole::kEgoSpeed   ? "Ego speed"
                             : f == sim::FactorRole::kTtc      ? "TTC"
                             : f == sim::FactorRole::kFriction ? "Friction"
                                                               : "Passage width";
    add_row(fmt::format("{}: {}{}", name, range_label(f, levels),
                        on_grid == grid   ? ""
                        : on_grid.empty() ? std::string(" [all grids]")
                                          : fmt::format(" [grid '{}']", on_grid)),
            on_grid, f, levels, p);
  }
  // A categorical factor by its levels (ours only: the paper has none).
  for (const auto& c : cuts.categorical) {
    std::string what = c.what;
    if (!what.empty()) what[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(what[0])));
    add_levels_row(fmt::format("{}: {}", what, core::join(c.levels, " / ")), grid, kWholeGrid, c.levels, nullptr,
                   [&](std::size_t i) { return subset(records, grid, c, i); });
  }
  if (!friction_grid.empty() && has_grid(records, friction_grid))
    add_row(
        fmt::format("Friction: {} [grid '{}', ours only]",
                    range_label(sim::FactorRole::kFriction, level_names(sim::FactorRole::kFriction)), friction_grid),
        friction_grid, sim::FactorRole::kFriction, level_names(sim::FactorRole::kFriction), nullptr);

  if (paper.empty())
    t.notes.push_back(
        "Collision-avoidance rates per level, levels separated by \" / \"; speed and TTC are cut into thirds of "
        "the grid's range (docs/results.md). kpis.csv has mitigability success, ΔLoss and impact speeds for every "
        "level.");
  else
    t.notes.push_back(
        "Each cell reads \"ours (paper N)\", levels separated by \" / \". The paper's caption calls these "
        "numbers mitigability success, but its friction row (81/81/81/45) equals the collision-avoidance rates of "
        "its EMRM-vs-baseline table, so we show collision-avoidance rates; kpis.csv has mitigability success, ΔLoss "
        "and impact speeds for every level.");
  if (cuts.passage_factor && (has_grid(records, passage_grid) || passage_grid.empty())) {
    const auto narrow = subset(records, passage_grid, sim::FactorRole::kPassage, "narrow", cuts);
    const std::string evasive_name = first_name_of(sim::StrategyRole::kEvasive);
    const std::string baseline_name = first_name_of(sim::StrategyRole::kBaseline);
    const auto evasive = strategy_kpis(narrow, evasive_name);
    const auto stop = strategy_kpis(narrow, baseline_name);
    if (evasive.cells > 0)
      t.notes.push_back(fmt::format(
          "Narrow passages (narrower than the {:g} m car): no car fits beside the truck, so our evasive "
          "strategies "
          "avoid only by braking, where the emergency stop does too ({} {} % vs {} {} % of {} "
          "cells); "
          "the paper's dodge and drift-to-avoid show 0 % there, i.e. they do not brake to a stop.",
          cuts.car_width_m, strategy_label(evasive_name), format_number(evasive.collision_avoidance_rate_pct, 0),
          strategy_label(baseline_name), format_number(stop.collision_avoidance_rate_pct, 0), evasive.cells));
  }
  if (largest.gap >= 0.0)
    t.notes.push_back(
        fmt::format("Largest difference: {}. Test counts differ where our feasible cells differ from the "
                    "paper's (feasibility is "
                    "v·TTC within max_initial_distance_m); the passage row uses our passage grid, not the "
                    "paper's 8 scenarios. "
                    "Our emergency stop follows the analytic stop boundary exactly, so its rate per level is "
                    "the share of that "
                    "level's cells with TTC ≥ v/(2μg).",
                    largest.where));
  return t;
}

Table regions_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                    const sim::ActuationConfig& actuation) {
  Table t;
  t.title = "Mitigability regions per grid (percent of feasible cells)";
  t.header = {"Grid", "Cells", "Feasible", "Infeasible", "G (%)", "Y (%)", "O (%)", "R (%)"};
  std::optional<RegionCounts> fine;
  std::size_t departure_o = 0;
  for (const auto& grid : grid_names(records)) {
    const auto c = count_regions(records, grid);
    t.rows.push_back({grid, std::to_string(c.cells), std::to_string(c.feasible), std::to_string(c.infeasible),
                      format_number(c.pct(c.g), 1), format_number(c.pct(c.y), 1), format_number(c.pct(c.o), 1),
                      format_number(c.pct(c.r), 1)});
    if (!paper.empty() && grid == paper.fine_grid.grid) {
      fine = c;
      const auto& pr = paper.fine_grid.regions_pct;
      t.rows.push_back({grid + " (paper)", std::string(kNoValue), std::to_string(paper.fine_grid.feasible_cells),
                        std::string(kNoValue), paper_number(pr.g), paper_number(pr.y), paper_number(pr.o),
                        paper_number(pr.r)});
    }
  }
  if (paper.empty()) {
    t.notes.push_back(
        "No published regions stand beside these (the example has no paper_reference.yaml). G is where the "
        "emergency stop avoids, Y where only an evasive maneuver does, O where one lowers the loss level, R where "
        "nothing does (docs/verify.md has the evidence of each cell).");
    return t;
  }
  if (!fine) {
    const auto& pr = paper.fine_grid.regions_pct;
    t.rows.push_back({paper.fine_grid.grid + " (paper; not in this campaign)", std::string(kNoValue),
                      std::to_string(paper.fine_grid.feasible_cells), std::string(kNoValue), paper_number(pr.g),
                      paper_number(pr.y), paper_number(pr.o), paper_number(pr.r)});
    t.notes.push_back(
        fmt::format("This campaign has no grid '{}', so the paper's regions stand alone.", paper.fine_grid.grid));
    return t;
  }
  std::size_t braking_o = 0;
  const std::string baseline = first_name_of(sim::StrategyRole::kBaseline);
  for (const auto& r : records) {
    if (r.grid != paper.fine_grid.grid || !r.feasible || r.region != sim::Region::kO) continue;
    for (const auto& o : r.outcomes)
      if (o.strategy == baseline && o.loss_level < r.unmitigated_loss_level) ++braking_o;
  }
  // O cells whose best outcome is a road departure: a scrape along the roadside barrier that scores
  // below the reference's level (docs/physics.md, "Road departure and the roadside").
  for (const auto& r : records) {
    if (r.grid != paper.fine_grid.grid || !r.feasible || r.region != sim::Region::kO) continue;
    const campaign::OutcomeRecord* best = nullptr;
    for (const auto& o : r.outcomes)
      if (!is_chooser(o.strategy) && (best == nullptr || o.loss_level < best->loss_level)) best = &o;
    if (best != nullptr && best->road_departure && !best->contact) ++departure_o;
  }
  std::size_t stoppable = 0;
  std::size_t stoppable_instant = 0;
  std::size_t certified = 0;
  std::size_t undecided = 0;
  for (const auto& r : records) {
    if (r.grid != paper.fine_grid.grid || !r.feasible) continue;
    stoppable += sim::analytically_stoppable(r.factors, actuation);
    stoppable_instant += sim::analytically_stoppable(r.factors, sim::ActuationConfig{});
    certified += r.evidence == campaign::CellEvidence::kCertificate;
    undecided += r.evidence == campaign::CellEvidence::kUndecided;
  }
  const auto& pr = paper.fine_grid.regions_pct;
  t.notes.push_back(
      fmt::format("Fine grid, ours vs paper: {} vs {} feasible cells; G {} vs {:g} %, Y {} vs {:g} %, O {} "
                  "vs {:g} %, R {} vs {:g} %.",
                  fine->feasible, paper.fine_grid.feasible_cells, format_number(fine->pct(fine->g), 1), pr.g,
                  format_number(fine->pct(fine->y), 1), pr.y, format_number(fine->pct(fine->o), 1), pr.o,
                  format_number(fine->pct(fine->r), 1), pr.r));
  t.notes.push_back(fmt::format(
      "Why they differ: our G region is the emergency stop's, which follows its stop boundary exactly "
      "(v·TTC at least the stopping distance through the actuators; diagnostics.json, stop_boundary). Under this "
      "scene's actuation ({}) {} of our {} feasible fine cells ({} %) lie on or above it; with instant actuation, "
      "the line TTC ≥ v/(2μg), {} ({} %) would. The paper draws that line as G's border but reports G {:g} %, so "
      "its emergency stop avoided fewer cells than the line allows, as a braking delay or a deceleration below "
      "μg would (the fitted `paper` profile names one such delay; docs/actuation.md). Our G is {:+.1f} points, "
      "our Y {:+.1f} and R {:+.1f} points against the paper's.",
      actuation.summary(), stoppable, fine->feasible, format_number(fine->pct(stoppable), 1), stoppable_instant,
      format_number(fine->pct(stoppable_instant), 1), pr.g, fine->pct(fine->g) - pr.g, fine->pct(fine->y) - pr.y,
      fine->pct(fine->r) - pr.r));
  t.notes.push_back(fmt::format(
      "How our outcome model moves Y, O and R (docs/physics.md): an avoidance counts only when the car then "
      "reaches a safe state (stopped, or stable with room to stop), which takes from Y the passes that were "
      "certain to leave the road; the unmitigated reference is the no-action contact assessed by the same "
      "off-centre impact model as the strategies (Δv ≈ 0.72–0.77 v instead of the central 0.92 v), so it is L6 "
      "only above ≈61–64 km/h and braking lowers its level in fewer cells, which moves cells from O to R; a road "
      "departure is an impact with the roadside barrier, so only a glancing scrape still scores below the "
      "reference: {} of our {} O cells are O through such a scrape, and in {} of them braking alone lowers the "
      "level too. Of our {} O and R cells, {} are certified unavoidable and {} are undecided (no avoidance found, "
      "none proven impossible; docs/verify.md). Y also depends on our vehicle model (an understeering car, ABS "
      "that keeps lateral grip) and our planner, which are not the paper's.",
      departure_o, fine->o, braking_o, fine->o + fine->r, certified, undecided));
  return t;
}

Table claims_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                   std::string_view grid) {
  Table t;
  t.title = "The paper's claims against ours";
  t.header = {"Claim", "Paper", "Ours"};
  const auto& c = paper.claims;
  double fastest_stop = -1.0;
  const std::string baseline = first_name_of(sim::StrategyRole::kBaseline);
  for (const auto& r : records) {
    if (r.grid != grid || !r.feasible) continue;
    for (const auto& o : r.outcomes)
      if (o.strategy == baseline && o.avoided) fastest_stop = std::max(fastest_stop, r.factors.ego_speed_kph());
  }
  t.rows.push_back({fmt::format("Emergency stop never avoids above (km/h), grid '{}'", grid),
                    fmt::format("≈{:g}", c.emergency_stop_never_avoids_above_kph),
                    fastest_stop < 0 ? std::string(kNoValue) : fmt::format("avoids up to {:g}", fastest_stop)});
  std::size_t low_mu = 0, low_mu_avoided = 0;
  for (const auto& r : records) {
    if (!r.feasible || r.factors.friction() >= c.no_avoidance_below_mu ||
        std::abs(r.factors.time_to_collision_s() - c.no_avoidance_below_mu_at_ttc_s) > 1e-9)
      continue;
    ++low_mu;
    if (std::any_of(r.outcomes.begin(), r.outcomes.end(), [](const campaign::OutcomeRecord& o) { return o.avoided; }))
      ++low_mu_avoided;
  }
  t.rows.push_back({fmt::format("Cells with μ < {:g} at TTC {:g} s where some strategy avoids", c.no_avoidance_below_mu,
                                c.no_avoidance_below_mu_at_ttc_s),
                    "none", low_mu == 0 ? std::string(kNoValue) : fmt::format("{} of {}", low_mu_avoided, low_mu)});
  t.rows.push_back({"Coverage: framework / HARA only / STPA only / manual (%)",
                    fmt::format("{:g} / ≤{:g} / ≤{:g} / ≤{:g}", c.coverage_pct.framework, c.coverage_pct.hara_only,
                                c.coverage_pct.stpa_only, c.coverage_pct.manual),
                    "measured by the minimum scenario set: tables/coverage.md"});
  if (fastest_stop > c.emergency_stop_never_avoids_above_kph)
    t.notes.push_back(
        fmt::format("Our emergency stop avoids every feasible cell with TTC ≥ v/(2μg); feasibility (v·TTC within "
                    "max_initial_distance_m) still leaves cells above that line at {:g} km/h, so ours avoids above the "
                    "paper's "
                    "≈{:g} km/h.",
                    fastest_stop, c.emergency_stop_never_avoids_above_kph));
  if (low_mu_avoided > 0)
    t.notes.push_back(
        "At low friction some of our cells are still avoided: where the distance v·TTC is long enough to "
        "brake or to "
        "swerve within the reduced grip (kpis.csv, friction level low, has the rates per strategy and "
        "grid).");
  return t;
}

Table coverage_comparison_table(const std::vector<scenario::CoverageReport>& reports, const PaperReference& paper) {
  Table t;
  t.title = "Coverage comparison: the minimum scenario set vs traditional methods (%)";
  t.header = {"Method", "Scenarios", "Hazard", "UCA", "FSM transition", "Cell", "t-wise", "Boundary", "C1-C4"};
  if (!paper.empty()) t.header.push_back("Paper");
  const auto& pc = paper.claims.coverage_pct;
  const auto paper_figure = [&](const std::string& name) -> std::string {
    if (name == "emrm plan") return fmt::format("{:g}", pc.framework);
    if (name == "HARA only") return fmt::format("≤{:g}", pc.hara_only);
    if (name == "STPA only") return fmt::format("≤{:g}", pc.stpa_only);
    if (name == "manual grid") return fmt::format("≤{:g}", pc.manual);
    return std::string(kNoValue);
  };
  const auto percent = [](const scenario::CoverageCount& c) { return format_number(100.0 * c.fraction(), 1); };
  for (const auto& r : reports) {
    std::string flags;
    for (const auto& [label, holds] : {std::pair{"C1", r.c1}, {"C2", r.c2}, {"C3", r.c3}, {"C4", r.c4}})
      if (holds) flags += flags.empty() ? label : std::string(" ") + label;
    t.rows.push_back({r.name, std::to_string(r.scenarios), percent(r.hazards), percent(r.malfunctions),
                      percent(r.transitions), percent(r.cells), percent(r.twise), percent(r.boundaries),
                      flags.empty() ? std::string("none") : flags});
    if (!paper.empty()) t.rows.back().push_back(paper_figure(r.name));
  }
  if (paper.empty()) {
    t.notes.push_back(
        "Measured by one checker (docs/plan.md) on the example's ODD: hazard and UCA coverage count the hazards and "
        "UCAs whose region some test lies in, cell coverage the ODD's relevant cells. HARA only tests each hazard "
        "once at the nominal operating point, STPA only each UCA once inside its region, the manual grid the ODD's "
        "`baselines: manual` points.");
    return t;
  }
  t.notes.push_back(
      "Ours are measured by one checker (docs/plan.md) on the ODD of examples/tjunction/odd.yaml: hazard and UCA "
      "coverage count the hazards and UCAs whose region some test lies in, cell coverage the ODD's relevant cells "
      "(bins of speed, TTC, μ and passage), not the paper's fine (speed, TTC) grid. The paper gives one figure per "
      "method (hazard, UCA and parameter-space coverage for its framework, ≤75 / ≤19 / ≤1 % for HARA, STPA and "
      "manual) without saying how each was measured, so the Paper column stands beside the whole row.");
  t.notes.push_back(
      "HARA only tests each hazard once at the nominal operating point, so it reaches the hazards whose UCA region "
      "contains that point; STPA only tests each UCA once inside its region, so it covers every UCA and hazard but "
      "few cells; the manual 5 × 6 speed × TTC grid leaves friction and passage at their nominal values.");
  return t;
}

std::string kpis_csv(const std::vector<campaign::CellRecord>& records, const LevelCuts& cuts) {
  const core::Row header{"grid",
                         "strategy",
                         "factor",
                         "level",
                         "range",
                         "cells",
                         "avoided",
                         "collisions",
                         "mitigated",
                         "collision_avoidance_rate_pct",
                         "mean_impact_speed_kph",
                         "mean_impact_speed_collisions_kph",
                         "mean_min_ttc_s",
                         "finite_min_ttc_cells",
                         "mitigability_success_pct",
                         "mean_delta_loss",
                         "differs_from_oracle_pct"};
  const auto num = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6g}", v); };
  std::vector<core::Row> rows;
  const auto row = [&](const StrategyKpis& k, const std::string& factor, const std::string& range) {
    rows.push_back({k.grid, k.strategy, factor, k.level, range, std::to_string(k.cells), std::to_string(k.avoided),
                    std::to_string(k.collisions), std::to_string(k.mitigated), num(k.collision_avoidance_rate_pct),
                    num(k.mean_impact_speed_kph), num(k.mean_impact_speed_collisions_kph), num(k.mean_min_ttc_s),
                    std::to_string(k.finite_min_ttc), num(k.mitigability_success_pct), num(k.mean_delta_loss),
                    num(k.differs_from_oracle_pct)});
  };
  for (const auto& grid : grid_names(records)) {
    for (const auto& k : grid_kpis(records, grid, cuts))
      row(k, std::string(factor_name(k.factor)), level_range(k.factor, k.level, cuts));
    // Each categorical factor's levels, the factor by its key and a level by its name.
    for (const auto& s : strategy_names_of(records))
      for (const auto& c : cuts.categorical)
        for (std::size_t i = 0; i < c.levels.size(); ++i)
          row(strategy_kpis(subset(records, grid, c, i), s, grid, kWholeGrid, c.levels[i]), c.key, c.levels[i]);
  }
  return core::csv_table(header, rows);
}

std::vector<std::filesystem::path> write_tables(const std::filesystem::path& dir,
                                                const std::vector<campaign::CellRecord>& records,
                                                const PaperReference& paper, const TableOptions& options) {
  // Every table computed before the first file is written, then all together (core::write_files).
  const auto tables_dir = ResultsDir(dir).tables_dir();
  std::vector<core::FileContent> files;
  const auto add = [&](const std::string& stem, const Table& t) {
    for (auto& f : core::table_files(tables_dir, stem, t)) files.push_back(std::move(f));
  };
  add("emrm_vs_baseline", emrm_vs_baseline_table(records, paper, options.grid));
  add("by_parameter", by_parameter_table(records, paper, options.grid,
                                         has_grid(records, options.passage_grid) ? options.passage_grid : "",
                                         options.friction_grid, options.cuts));
  add("regions", regions_table(records, paper, options.actuation));
  if (!paper.empty()) add("claims", claims_table(records, paper, options.grid));
  files.push_back({ResultsDir(dir).kpis_csv(), kpis_csv(records, options.cuts)});
  core::write_files(files);
  std::vector<std::filesystem::path> written;
  for (const auto& f : files) written.push_back(f.path);
  return written;
}

}  // namespace emrm::results
