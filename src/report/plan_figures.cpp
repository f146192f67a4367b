// The figures of a planned run (docs/report.md): maps over pairs of the ODD's factors and the
// sweep curves by the ODD's bins.

#include "emrm/report/plan_figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <utility>

#include "emrm/campaign/plan_settings.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/run_estimates.hpp"
#include "emrm/results/run_outcomes.hpp"
#include "emrm/scenario/statistics.hpp"
#include "figure_parts.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;

// --- reading the run ----------------------------------------------------------------------------

/// The factors (name, unit, level labels), confidence and acceptance criterion of estimates.json.
void read_estimates(const results::RunEstimates& estimates, PlannedRun& run) {
  run.factors.clear();
  for (const auto& f : estimates.factors.value_or(std::vector<scenario::PlanFactor>{})) {
    PlanFactor factor{f.name, f.unit, {}};
    for (const auto& level : f.levels) factor.levels.push_back(level.label);
    run.factors.push_back(std::move(factor));
  }
  run.confidence = estimates.confidence;
  if (const auto& a = estimates.acceptance) run.acceptance = fmt::format("{} {}", a->strategy, a->outcome);
}

/// The levels of a cell key "c0.2.1" (scenario::cell_key), one per factor.
std::vector<int> levels_of_key(const std::string& key, const std::vector<PlanFactor>& factors,
                               const SourceLocation& where) {
  std::vector<int> levels;
  const auto bad = [&] {
    return InputError(where, fmt::format("cell '{}' is not a key of the plan's {} factors (c, then one level each, "
                                         "separated by '.')",
                                         key, factors.size()));
  };
  if (key.empty() || key[0] != 'c') throw bad();
  const char* p = key.data() + 1;
  const char* end = key.data() + key.size();
  while (p < end) {
    int level = 0;
    const auto [next, ec] = std::from_chars(p, end, level);
    if (ec != std::errc() || level < 0) throw bad();
    levels.push_back(level);
    p = next;
    if (p < end && *p++ != '.') throw bad();
  }
  if (levels.size() != factors.size()) throw bad();
  for (std::size_t i = 0; i < levels.size(); ++i)
    if (static_cast<std::size_t>(levels[i]) >= factors[i].levels.size()) throw bad();
  return levels;
}

// The scenarios of outcomes.csv, read through its typed reader (results/run_outcomes.hpp).
void read_outcomes(const fs::path& path, PlannedRun& run) {
  const results::RunOutcomes outcomes = results::read_run_outcomes(path);
  for (std::size_t i = 0; i < outcomes.scenarios.size(); ++i) {
    const auto& o = outcomes.scenarios[i];
    PlannedScenario s;
    s.id = o.id;
    if (!run.factors.empty()) s.levels = levels_of_key(o.cell, run.factors, {path.string(), outcomes.lines[i], 1});
    s.feasible = o.feasible;
    s.success = o.success == 1 ? 1 : 0;
    run.scenarios.push_back(std::move(s));
  }
}

void attach_records(const fs::path& store, PlannedRun& run) {
  std::vector<CellRecord> cells;
  for (auto& r : campaign::read_results(store))
    if (r.grid == campaign::kPlanGrid) cells.push_back(std::move(r));
  if (cells.size() != run.scenarios.size())
    throw UsageError(fmt::format("{} lists {} scenarios, but {} holds {} of grid '{}': not the same run",
                                 results::ResultsDir(run.folder).outcomes_csv().string(), run.scenarios.size(),
                                 store.string(), cells.size(), campaign::kPlanGrid));
  for (auto& c : cells) {
    if (c.index < 0 || static_cast<std::size_t>(c.index) >= run.scenarios.size())
      throw UsageError(fmt::format("{} holds a scenario index {} beyond the run's {} scenarios", store.string(),
                                   c.index, run.scenarios.size()));
    run.scenarios[static_cast<std::size_t>(c.index)].record = std::move(c);
  }
}

// --- the map of a pair of factors --------------------------------------------------------------

/// The scenarios of one pair of levels.
struct PairCell {
  std::size_t scenarios = 0, feasible = 0, successes = 0, undecided = 0;
};

constexpr int kPlanMapWidthPx = 1000, kPlanMapHeightPx = 760, kPlanMapFontPt = 13;

std::string tics(const PlanFactor& f) {
  std::vector<std::string> items;
  for (std::size_t k = 0; k < f.levels.size(); ++k)
    items.push_back(fmt::format("{} {}", single_quoted(f.levels[k]), k));
  return fmt::format("({}) noenhanced", core::join(items, ", "));
}

/// The pooled cells of factors `a` × `b`: cells[la][lb].
std::vector<std::vector<PairCell>> pool(const PlannedRun& run, std::size_t a, std::size_t b) {
  std::vector<std::vector<PairCell>> cells(run.factors[a].levels.size(),
                                           std::vector<PairCell>(run.factors[b].levels.size()));
  for (const auto& s : run.scenarios) {
    PairCell& c = cells[static_cast<std::size_t>(s.levels[a])][static_cast<std::size_t>(s.levels[b])];
    ++c.scenarios;
    c.feasible += s.feasible;
    c.successes += static_cast<std::size_t>(s.feasible && s.success == 1);
    c.undecided += detail::is_undecided(s.record);
  }
  return cells;
}

/// The datablocks and CSV rows of a pair map.
struct PairData {
  std::vector<std::string> rated, infeasible, labels, crosses;
  std::vector<core::Row> rows;
  std::size_t undecided = 0, feasible = 0, scenarios = 0;
};

PairData pair_data(const PlannedRun& run, std::size_t a, std::size_t b) {
  const auto cells = pool(run, a, b);
  const PlanFactor &fa = run.factors[a], &fb = run.factors[b];
  PairData d;
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (std::size_t k = 0; k < cells[i].size(); ++k) {
      const PairCell& c = cells[i][k];
      if (c.scenarios == 0) continue;
      const std::string box = fmt::format("{} {} 0.48 0.48", i, k);
      core::Row row{fa.name,
                    std::to_string(i),
                    fa.levels[i],
                    fb.name,
                    std::to_string(k),
                    fb.levels[k],
                    std::to_string(c.scenarios),
                    std::to_string(c.feasible),
                    std::to_string(c.successes)};
      if (c.feasible > 0) {
        const double n = static_cast<double>(c.feasible), rate = static_cast<double>(c.successes) / n;
        const auto w = scenario::wilson_interval(static_cast<double>(c.successes), n, run.confidence);
        d.rated.push_back(fmt::format("{} {}", box, plot_number(rate)));
        d.labels.push_back(fmt::format("{} {} {}/{} [{:.2f},{:.2f}]", i, k, c.successes, c.feasible, w.low, w.high));
        row.insert(row.end(), {plot_number(rate), plot_number(w.low), plot_number(w.high)});
      } else {
        d.infeasible.push_back(fmt::format("{} {}", box, rgb_value("#bdbdbd")));
        row.insert(row.end(), 3, std::string());
      }
      if (c.undecided > 0)
        d.crosses.push_back(fmt::format("{} {}", plot_number(static_cast<double>(i) + 0.36),
                                        plot_number(static_cast<double>(k) + 0.36)));
      row.push_back(std::to_string(c.undecided));
      d.rows.push_back(std::move(row));
      d.undecided += c.undecided;
      d.feasible += c.feasible;
      d.scenarios += c.scenarios;
    }
  return d;
}

/// The gnuplot body of a pair map: one panel over a key strip.
std::string pair_script(const PlanFactor& fa, const PlanFactor& fb, const PairData& d, const std::string& title) {
  constexpr double kKeyH = 0.07, kTop = 0.955;
  std::string body = fmt::format(
      "set multiplot title {} font ',16'\nset tics out nomirror\nset border 3\nset key off\n"
      "set palette defined (0 '#d73027', 0.5 '#fee08b', 1 '#1a9850')\nset cbrange [0:1]\nset cbtics "
      "0,0.25,1\n"
      "set cblabel 'estimated success (share of feasible scenarios)'\n",
      single_quoted(title));
  body += fmt::format("set origin 0,{}\nset size 1,{}\n", kKeyH, kTop - kKeyH);
  body += fmt::format("set xlabel {}\nset ylabel {}\nset xtics {}\nset ytics {}\n",
                      single_quoted(enhanced_literal(plan_factor_label(fa))),
                      single_quoted(enhanced_literal(plan_factor_label(fb))), tics(fa), tics(fb));
  body += fmt::format("set xrange [-0.5:{}]\nset yrange [-0.5:{}]\n",
                      plot_number(static_cast<double>(fa.levels.size()) - 0.5),
                      plot_number(static_cast<double>(fb.levels.size()) - 0.5));
  std::vector<std::string> layers;
  if (!d.rated.empty()) layers.push_back("$rated using 1:2:3:4:5 with boxxyerror fs solid 1.0 noborder lc palette");
  if (!d.infeasible.empty())
    layers.push_back("$infeasible using 1:2:3:4:5 with boxxyerror fs solid 1.0 noborder lc rgb variable");
  if (!d.labels.empty())
    layers.push_back(
        "$labels using 1:($2+0.1):3 with labels noenhanced font ',13', "
        "$labels using 1:($2-0.14):4 with labels noenhanced font ',10'");
  if (!d.crosses.empty()) layers.push_back("$crosses using 1:2 with points pt 2 ps 1.5 lw 1.5 lc rgb 'black'");
  body += "plot " + core::join(layers, ", ") + "\n";
  std::vector<std::string> key{"NaN with boxes fs solid 1.0 lc rgb '#bdbdbd' title 'all its scenarios infeasible'"};
  if (!d.crosses.empty())
    key.push_back("NaN with points pt 2 ps 1.2 lw 1.5 lc rgb 'black' title 'undecided scenario (no proof either way)'");
  return body + "set key on\n" + key_strip(kKeyH, 1, 0, key) + "unset multiplot\n";
}

Figure draw_pair_map(const PlannedRun& run, std::size_t a, std::size_t b, const fs::path& dir) {
  const PlanFactor &fa = run.factors[a], &fb = run.factors[b];
  Figure figure;
  figure.name = fmt::format("plan_map_{}_{}", fa.name, fb.name);
  const PairData d = pair_data(run, a, b);
  const std::string pair = fmt::format("{} × {}", fa.name, fb.name);
  figure.title = fmt::format(
      "Planned run, {}: estimated success ({}) per pair of the ODD's levels, pooled over the other factors "
      "({} "
      "scenarios, {} feasible). Each rectangle is a pair of levels, coloured by the share of its feasible "
      "scenarios "
      "that succeed (red 0, yellow 0.5, green 1) and labelled successes/feasible over the Wilson interval at "
      "{:g} "
      "%; grey: only infeasible scenarios; blank: no scenario planned there.{}",
      pair, run.acceptance.empty() ? std::string("the plan's acceptance") : run.acceptance, d.scenarios, d.feasible,
      100.0 * run.confidence,
      d.undecided == 0 ? std::string()
                       : fmt::format(" A cross marks a pair with undecided scenarios ({} in all): a search found no "
                                     "avoidance, but nothing proves that none exists.",
                                     d.undecided));
  detail::write_csv(figure, dir,
                    {"factor_x", "level_x", "bin_x", "factor_y", "level_y", "bin_y", "scenarios", "feasible",
                     "successes", "rate", "wilson_low", "wilson_high", "undecided"},
                    d.rows);
  std::string data = datablock("rated", d.rated) + datablock("infeasible", d.infeasible) +
                     datablock("labels", d.labels) + datablock("crosses", d.crosses);
  const std::string title = fmt::format("Planned run: estimated success, {}", enhanced_literal(pair));
  render_png_and_svg(figure.png, figure.svg, data, pair_script(fa, fb, d, title), kPlanMapWidthPx, kPlanMapHeightPx,
                     kPlanMapFontPt);
  return figure;
}

}  // namespace

std::optional<PlannedRun> read_planned_run(const results::FoundRunEstimates& estimates) {
  // None read (not as `emrm run` writes it: the statistics section says so and shows no run).
  if (!estimates.estimates) return std::nullopt;
  const results::ResultsDir folder(estimates.file.parent_path());
  std::error_code ec;
  if (!fs::is_regular_file(folder.outcomes_csv(), ec)) return std::nullopt;
  PlannedRun run;
  run.folder = folder.root();
  read_estimates(*estimates.estimates, run);
  read_outcomes(folder.outcomes_csv(), run);
  attach_records(folder.store(), run);
  return run;
}

std::vector<Figure> draw_plan_maps(const PlannedRun& run, const fs::path& dir, std::size_t max_maps) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t a = 0; a < run.factors.size(); ++a)
    for (std::size_t b = a + 1; b < run.factors.size(); ++b)
      if (run.factors[a].levels.size() > 1 && run.factors[b].levels.size() > 1) pairs.emplace_back(a, b);
  std::vector<Figure> figures;
  const std::size_t drawn = std::min(pairs.size(), max_maps);
  for (std::size_t i = 0; i < drawn; ++i) figures.push_back(draw_pair_map(run, pairs[i].first, pairs[i].second, dir));
  if (drawn < pairs.size()) {
    Figure more;
    more.name = "plan_map_more";
    more.title = "Planned run, further pairs of factors";
    std::vector<std::string> left;
    for (std::size_t i = drawn; i < pairs.size(); ++i)
      left.push_back(run.factors[pairs[i].first].name + " × " + run.factors[pairs[i].second].name);
    more.note = fmt::format("{} pairs of factors; the first {} are drawn, these not: {}", pairs.size(), drawn,
                            core::join(left, "; "));
    figures.push_back(std::move(more));
  }
  return figures;
}

Figure draw_plan_sweep_curves(const PlannedRun& run, const sim::FactorTable& factors, const fs::path& dir,
                              const std::string& name) {
  std::optional<std::size_t> chosen;  // the ego speed, else the first factor with two levels or more
  for (std::size_t i = 0; i < run.factors.size(); ++i) {
    if (run.factors[i].levels.size() < 2) continue;
    if (run.factors[i].name == factors[sim::kEgoSpeedFactor].key) {
      chosen = i;
      break;
    }
    if (!chosen) chosen = i;
  }
  if (!chosen) {
    Figure figure;
    figure.name = name;
    figure.title = "Parameter sweep of the planned run by the ODD's bins";
    figure.note = run.factors.empty() ? "no ODD factors in estimates.json (emrm run copies them from the plan's "
                                        "scenarios.json beside scenarios.csv)"
                                      : "no factor of the ODD has two levels or more";
    return figure;
  }
  std::vector<CellRecord> cells;
  std::vector<int> levels;
  for (const auto& s : run.scenarios) {
    cells.push_back(s.record);
    levels.push_back(s.levels[*chosen]);
  }
  return draw_binned_sweep_curves(cells, levels, run.factors[*chosen], dir, name);
}

}  // namespace emrm::report
