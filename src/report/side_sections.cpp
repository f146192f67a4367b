// The sections of report.html that come from side files of the results folder (docs/report.md):
// the planned run's shortfalls and estimates, the verification, the diagnostics and the findings of
// the safety analysis. No content of these files makes them throw: a missing file is said so and
// one of another shape is shown as it is.

#include "side_sections.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>

#include "emrm/core/text.hpp"
#include "emrm/report/report.hpp"
#include "emrm/results/results_dir.hpp"
#include "html.hpp"
#include "statistics_section.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using detail::html_table;
using detail::read_or_empty;

// The findings of analysis/findings.json, one row each.
std::string findings_table(const nlohmann::json& list) {
  core::Row header{"severity", "code", "subject", "where", "message"};
  std::vector<core::Row> rows;
  for (const auto& f : list)
    rows.push_back({f.value("severity", ""), f.value("code", ""), f.value("subject", ""),
                    fmt::format("{}:{}:{}", f.value("file", ""), f.value("line", 0), f.value("column", 0)),
                    f.value("message", "")});
  return html_table(header, rows);
}

std::string findings_html(const fs::path& dir) {
  const std::string text = read_or_empty(results::ResultsDir(dir).findings_json());
  if (text.empty()) return "<p>No safety analysis in this folder (run <code>emrm analyze</code> or reproduce).</p>\n";
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_array() && !(j.is_object() && j.contains("findings"))) return "<pre>" + html_escape(text) + "</pre>\n";
  const auto& list = j.is_array() ? j : j["findings"];
  if (list.empty()) return "<p class=\"ok\">No findings.</p>\n";
  try {
    return findings_table(list);
  } catch (const nlohmann::json::exception& e) {  // a file edited by hand: shown as it is
    return "<p>analysis/findings.json is not in the form emrm writes (" + html_escape(e.what()) +
           "); shown as it is.</p>\n<pre>" + html_escape(text) + "</pre>\n";
  }
}

// The checks of diagnostics.json (results::to_json) as one table: what each found, then the file.
std::string diagnostics_table(const nlohmann::json& d) {
  const auto& stop = d.at("stop_boundary");
  const auto& mono = d.at("monotonicity");
  const auto& reference = d.at("rrt_vs_reference");
  const auto count = [](const nlohmann::json& j, const char* key) { return j.at(key).get<std::size_t>(); };
  core::Row header{"check", "result"};
  std::vector<core::Row> rows;
  rows.push_back(
      {"stop boundary", fmt::format("{} of {} feasible cells can stop analytically; {} of them R "
                                    "(must be 0), {} G cells below the boundary (must be 0)",
                                    count(stop, "stoppable"), count(stop, "feasible"),
                                    count(stop, "stoppable_red_count"), count(stop, "green_not_stoppable_count"))});
  std::vector<std::string> reversals;
  for (const auto& c : mono.at("counts"))
    if (count(c, "reversals") > 0)
      reversals.push_back(fmt::format("{} {} over {}: {} of {} pairs", c.at("grid").get<std::string>(),
                                      c.at("strategy").get<std::string>(), c.at("factor").get<std::string>(),
                                      count(c, "reversals"), count(c, "pairs")));
  rows.push_back(
      {"monotonicity in TTC and mu", fmt::format("{} reversals{}", count(mono, "total_reversals"),
                                                 reversals.empty() ? "" : " (" + core::join(reversals, "; ") + ")")});
  std::vector<std::string> planners;
  for (const auto& [name, c] : reference.items())
    if (c.is_object())
      planners.push_back(fmt::format("{}: reference avoids {}, RRT missed {}, RRT beyond the reference {}", name,
                                     count(c, "reference_avoids"), count(c, "rrt_missed"),
                                     count(c, "rrt_beyond_reference")));
  rows.push_back({fmt::format("RRT against the reference planner ({} cells, seed {})", count(reference, "sampled"),
                              reference.at("seed").get<std::uint64_t>()),
                  planners.empty() ? std::string("no strategy checked") : core::join(planners, "; ")});
  for (const auto& [name, c] : d.at("fsm_coverage").items())
    rows.push_back(
        {"FSM transition coverage: " + name, fmt::format("{} of {} transitions exercised by {} traces",
                                                         count(c, "covered"), count(c, "total"), count(c, "traces"))});
  return html_table(header, rows);
}

std::string diagnostics_html(const fs::path& dir) {
  const std::string text = read_or_empty(results::ResultsDir(dir).diagnostics_json());
  if (text.empty())
    return "<p>No diagnostics in this folder: <code>emrm diagnose " + html_escape(dir.string()) +
           "</code> writes them (<code>emrm reproduce</code> does so itself).</p>\n";
  std::string table;
  try {
    table = diagnostics_table(nlohmann::json::parse(text));
  } catch (const nlohmann::json::exception& e) {
    table = "<p>diagnostics.json is not in the form emrm writes (" + html_escape(e.what()) + "); shown as it is.</p>\n";
  }
  return table + "<details><summary>diagnostics.json</summary><pre>" + html_escape(text) + "</pre></details>\n";
}

// The estimates.json of a planned run in this folder (reproduce's plan_results/ or `emrm run`'s own),
// with the folder it is in; nothing when there is none.
std::optional<std::pair<fs::path, nlohmann::json>> run_estimates(const fs::path& dir) {
  const results::ResultsDir folder(dir);
  for (const fs::path& file : {folder.plan_results().estimates_json(), folder.estimates_json()}) {
    auto j = nlohmann::json::parse(read_or_empty(file), nullptr, false);
    if (j.is_object() && j.contains("weighted_success")) return std::pair{file.parent_path(), std::move(j)};
  }
  return std::nullopt;
}

std::string verification_html(const fs::path& dir) {
  const std::string text = read_or_empty(results::ResultsDir(dir).verify_json());
  if (text.empty())
    return "<p>No verification in this folder (<code>emrm verify DIR</code> re-checks a store; <code>emrm "
           "reproduce</code> keeps its result in verify.json).</p>\n";
  return "<details open><summary>verify.json</summary><pre>" + html_escape(text) + "</pre></details>\n";
}

}  // namespace

namespace detail {

std::vector<fs::path> coverage_candidates(const fs::path& dir) {
  const results::ResultsDir folder(dir);
  std::vector<fs::path> files{folder.plan().coverage_json(), folder.coverage_json()};
  if (const auto run = run_estimates(dir)) {
    const auto& plan = run->second.value("plan", nlohmann::json::object());
    if (plan.is_object() && plan.contains("coverage") && plan["coverage"].is_string())
      files.push_back(run->first / plan["coverage"].get<std::string>());
  }
  return files;
}

std::string shortfalls_html(const fs::path& dir) {
  const auto run = run_estimates(dir);
  if (!run || !run->second.contains("shortfalls") || !run->second["shortfalls"].is_array() ||
      run->second["shortfalls"].empty())
    return "";
  std::string out =
      "<div class=\"missing\" id=\"shortfalls\"><strong>The plan fell short of its targets</strong> "
      "(scenarios.json, repeated by <code>emrm run</code>); the estimates below lack these:\n<ul>\n";
  for (const auto& s : run->second["shortfalls"])
    out +=
        "<li>" +
        html_escape(s.is_object() && s.contains("message") && s["message"].is_string() ? s["message"].get<std::string>()
                                                                                       : s.dump()) +
        "</li>\n";
  return out + "</ul></div>\n";
}

std::string side_sections_html(const fs::path& dir) {
  return "<h2 id=\"plan\">Minimum scenario set: estimates</h2>\n" + detail::statistics_html(dir) +
         "<h2 id=\"verification\">Verification (emrm verify)</h2>\n" + verification_html(dir) +
         "<h2 id=\"diagnostics\">Diagnostics</h2>\n" + diagnostics_html(dir) +
         "<h2 id=\"findings\">Findings of the safety analysis</h2>\n" + findings_html(dir);
}

}  // namespace detail

std::string side_files_html(const fs::path& dir) {
  return detail::shortfalls_html(dir) + detail::side_sections_html(dir);
}

}  // namespace emrm::report
