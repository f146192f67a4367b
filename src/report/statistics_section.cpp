#include "statistics_section.hpp"

#include <fmt/format.h>

#include <cmath>

#include "emrm/core/text.hpp"
#include "emrm/report/report.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/run_estimates.hpp"
#include "emrm/scenario/statistics.hpp"
#include "html.hpp"

namespace emrm::report::detail {
namespace {

namespace fs = std::filesystem;

std::string fixed3(double v) { return fmt::format("{:.3f}", v); }

// The least n ≥ `n` at which the Wilson half-width at the observed rate is ≤ epsilon (the rate
// held), capped at `cap`.
std::size_t tests_for(double rate, std::size_t n, double epsilon, double confidence, std::size_t cap) {
  for (std::size_t m = std::max<std::size_t>(n, 1); m <= cap; ++m)
    if (scenario::wilson_interval(rate * static_cast<double>(m), static_cast<double>(m), confidence).half_width() <=
        epsilon)
      return m;
  return cap;
}

struct Cells {
  std::string table;
  std::vector<std::string> short_of_target;  ///< "cell (bins): n → m (+k)"
  std::size_t tracked = 0, met = 0, smallest_n = 0;
};

Cells cells_table(const results::RunEstimates& run) {
  const double epsilon = run.epsilon, confidence = run.confidence;
  Cells out;
  std::vector<std::string> factors;
  for (const auto& c : run.cells)
    for (const auto& [f, label] : c.levels)
      if (std::find(factors.begin(), factors.end(), f) == factors.end()) factors.push_back(f);
  core::Row header{"cell"};
  header.insert(header.end(), factors.begin(), factors.end());
  for (const char* h : {"n", "successes", "estimate", "Wilson low", "Wilson high", "half-width", "target met"})
    header.emplace_back(h);
  std::vector<core::Row> rows;
  const std::size_t wilson_n = scenario::wilson_sample_size(epsilon, confidence);
  for (const auto& c : run.cells) {
    const std::size_t n = c.n, k = c.successes;
    const double low = c.wilson.low, high = c.wilson.high;
    const bool tracked = c.tracked;
    const double rate = n > 0 ? static_cast<double>(k) / static_cast<double>(n) : 0.0;
    const bool met = 0.5 * (high - low) <= epsilon;
    core::Row row{c.cell};
    std::vector<std::string> bins;
    for (const auto& f : factors) {
      const auto level = std::find_if(c.levels.begin(), c.levels.end(), [&](const auto& l) { return l.first == f; });
      row.push_back(level != c.levels.end() ? level->second : "");
      bins.push_back(f + " " + row.back());
    }
    for (const auto& field :
         {std::to_string(n), std::to_string(k), fixed3(rate), fixed3(low), fixed3(high), fixed3(0.5 * (high - low)),
          std::string(!tracked ? "no target"
                      : met    ? "yes"
                               : "NO")})
      row.push_back(field);
    rows.push_back(std::move(row));
    if (!tracked) continue;
    out.smallest_n = out.tracked == 0 ? n : std::min(out.smallest_n, n);
    ++out.tracked;
    if (met) {
      ++out.met;
      continue;
    }
    const std::size_t m = tests_for(rate, n, epsilon, confidence, std::max(wilson_n, n));
    out.short_of_target.push_back(fmt::format("{} ({}): n = {} → {} at the observed rate (+{}), {} for any outcome",
                                              c.cell, core::join(bins, ", "), n, m, m - n, std::max(wilson_n, n)));
  }
  out.table = html_table(header, rows);
  return out;
}

std::string weighted_table(const results::RunEstimates& run) {
  core::Row header{"subset A", "tests", "n_eff", "Ŝ(A)", "Wilson low", "Wilson high", "shortfall of the plan"};
  std::vector<core::Row> rows;
  for (const auto& [subset, e] : run.weighted_success)
    rows.push_back({subset, std::to_string(e.n), fixed3(e.n_eff), e.estimate ? fixed3(*e.estimate) : "—",
                    fixed3(e.wilson.low), fixed3(e.wilson.high), e.shortfall.value_or("")});
  return html_table(header, rows);
}

std::string section(const results::RunEstimates& run, const fs::path& file, const fs::path& dir) {
  const double epsilon = run.epsilon;
  const double confidence = run.confidence;
  const double delta = 1.0 - confidence;
  std::string criterion = "the acceptance strategy avoids the collision";
  if (const auto& a = run.acceptance)
    criterion = fmt::format(
        "<code>{}</code> {}", html_escape(a->strategy),
        a->outcome == "mitigated" ? "avoids the collision or lowers the loss level" : "avoids the collision");
  const Cells cells = cells_table(run);
  std::string html = fmt::format(
      "<h3 id=\"statistics\">Statistics: acceptance criterion “{}”</h3>\n"
      "<p>From {}: {} scenarios. Each cell of the ODD estimates the probability that the criterion holds; "
      "its target is a Wilson interval no wider than ±{:g} at {:g} % confidence. {} of {} tracked cells meet it.</p>\n",
      criterion, html_escape(fs::relative(file, dir).generic_string()), run.scenarios, epsilon, 100.0 * confidence,
      cells.met, cells.tracked);
  html += cells.table;
  if (cells.tracked > 0) {
    const double hoeffding = scenario::hoeffding_epsilon(static_cast<double>(cells.smallest_n), delta);
    html += fmt::format(
        "<p>Hoeffding's inequality gives a bound that needs no approximation and holds whatever the true "
        "probability: with {} tests a cell's estimate lies within ±{:.2f} of the truth with probability {:g} %, "
        "and ±{:g} would take {} tests per cell (ln(2/δ)/(2ε²)); the Wilson intervals above are narrower "
        "because they use the number of successes seen.</p>\n",
        cells.smallest_n, hoeffding, 100.0 * confidence, epsilon, scenario::hoeffding_sample_size(epsilon, delta));
  }
  if (!cells.short_of_target.empty()) {
    html += fmt::format(
        "<p class=\"warning\">{} tracked {} miss the target. To meet it, <code>emrm plan</code>'s "
        "risk-weighted top-up would add scenarios here:</p>\n<ul>\n",
        cells.short_of_target.size(), cells.short_of_target.size() == 1 ? "cell" : "cells");
    for (const auto& line : cells.short_of_target) html += "<li>" + html_escape(line) + "</li>\n";
    html += "</ul>\n";
  }
  html +=
      "<p>The weighted success Ŝ(A) over the whole set and over each malfunction's region: the weights undo "
      "the plan's risk-weighted sampling, and the Wilson interval is taken at Kish's effective sample size "
      "n_eff.</p>\n" +
      weighted_table(run);
  return html;
}

}  // namespace

std::string statistics_html(const results::FoundRunEstimates& found, const fs::path& dir) {
  if (found.estimates) return section(*found.estimates, found.file, dir);
  if (!found.file.empty())
    return fmt::format("<p class=\"warning\">{} is not in the form emrm run writes ({}); no statistics shown.</p>\n",
                       html_escape(found.file.string()), html_escape(found.error));
  return "";  // no planned run here
}

}  // namespace emrm::report::detail
