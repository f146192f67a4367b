#include "statistics_section.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "emrm/core/text.hpp"
#include "emrm/report/report.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/scenario/statistics.hpp"
#include "html.hpp"

namespace emrm::report::detail {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

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

Cells cells_table(const Json& j, double epsilon, double confidence) {
  Cells out;
  std::vector<std::string> factors;
  for (const auto& c : j.at("cells"))
    if (c.contains("levels"))
      for (const auto& [f, label] : c.at("levels").items())
        if (std::find(factors.begin(), factors.end(), f) == factors.end()) factors.push_back(f);
  core::Row header{"cell"};
  header.insert(header.end(), factors.begin(), factors.end());
  for (const char* h : {"n", "successes", "estimate", "Wilson low", "Wilson high", "half-width", "target met"})
    header.emplace_back(h);
  std::vector<core::Row> rows;
  const std::size_t wilson_n = scenario::wilson_sample_size(epsilon, confidence);
  for (const auto& c : j.at("cells")) {
    const auto n = c.at("n").get<std::size_t>();
    const auto k = c.at("successes").get<std::size_t>();
    const double low = c.at("wilson").at(0).get<double>(), high = c.at("wilson").at(1).get<double>();
    const bool tracked = c.at("tracked").get<bool>();
    const double rate = n > 0 ? static_cast<double>(k) / static_cast<double>(n) : 0.0;
    const bool met = 0.5 * (high - low) <= epsilon;
    core::Row row{c.at("cell").get<std::string>()};
    std::vector<std::string> bins;
    for (const auto& f : factors) {
      row.push_back(c.contains("levels") ? c.at("levels").value(f, "") : "");
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
                                              c.at("cell").get<std::string>(), core::join(bins, ", "), n, m, m - n,
                                              std::max(wilson_n, n)));
  }
  out.table = html_table(header, rows);
  return out;
}

std::string weighted_table(const Json& j) {
  core::Row header{"subset A", "tests", "n_eff", "Ŝ(A)", "Wilson low", "Wilson high", "shortfall of the plan"};
  std::vector<core::Row> rows;
  for (const auto& item : j.at("weighted_success").items()) {  // not a structured binding: clang < 16
    const std::string& subset = item.key();                    // cannot capture one in a lambda
    const Json& e = item.value();
    const auto num = [&](const char* key) {
      return e.contains(key) && e[key].is_number() ? fixed3(e[key].get<double>()) : "—";
    };
    const auto& w = e.at("wilson");
    rows.push_back({subset, std::to_string(e.at("n").get<std::size_t>()), num("n_eff"), num("estimate"),
                    fixed3(w.at(0).get<double>()), fixed3(w.at(1).get<double>()),
                    e.contains("shortfall") && e["shortfall"].is_string() ? e["shortfall"].get<std::string>() : ""});
  }
  return html_table(header, rows);
}

std::string section(const Json& j, const fs::path& file, const fs::path& dir) {
  const double epsilon = j.at("epsilon").get<double>();
  const double confidence = j.at("confidence").get<double>();
  const double delta = 1.0 - confidence;
  std::string criterion = "the acceptance strategy avoids the collision";
  if (const auto a = j.find("acceptance"); a != j.end())
    criterion =
        fmt::format("<code>{}</code> {}", html_escape(a->at("strategy").get<std::string>()),
                    a->at("outcome").get<std::string>() == "mitigated" ? "avoids the collision or lowers the loss level"
                                                                       : "avoids the collision");
  const Cells cells = cells_table(j, epsilon, confidence);
  std::string html = fmt::format(
      "<h3 id=\"statistics\">Statistics: acceptance criterion “{}”</h3>\n"
      "<p>From {}: {} scenarios. Each cell of the ODD estimates the probability that the criterion holds; "
      "its target is a Wilson interval no wider than ±{:g} at {:g} % confidence. {} of {} tracked cells meet it.</p>\n",
      criterion, html_escape(fs::relative(file, dir).generic_string()), j.at("scenarios").get<std::size_t>(), epsilon,
      100.0 * confidence, cells.met, cells.tracked);
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
      weighted_table(j);
  return html;
}

}  // namespace

std::string statistics_html(const fs::path& dir) {
  const results::ResultsDir folder(dir);
  for (const fs::path& file : {folder.plan_results().estimates_json(), folder.estimates_json()}) {
    const std::string text = read_or_empty(file);
    if (text.empty()) continue;
    const Json j = Json::parse(text, nullptr, false);
    try {
      return section(j, file, dir);
    } catch (const Json::exception& e) {
      return fmt::format("<p class=\"warning\">{} is not in the form emrm run writes ({}); no statistics shown.</p>\n",
                         html_escape(file.string()), html_escape(e.what()));
    }
  }
  return "<p>No planned scenario set was run in this folder (<code>emrm plan</code>, <code>emrm run</code>).</p>\n";
}

}  // namespace emrm::report::detail
