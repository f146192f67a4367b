// The sections of report.html that come from side files of the results folder (docs/report.md):
// the planned run's shortfalls and estimates, the verification, the diagnostics and the findings of
// the safety analysis. No content of these files makes them throw: a missing file leaves its
// section out (the report's list of what the folder lacks says how to make it) and one of another
// shape is shown as it is.

#include "side_sections.hpp"

#include <fmt/format.h>

#include <cstdint>

#include "emrm/core/text.hpp"
#include "emrm/report/report.hpp"
#include "emrm/results/diagnostics.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/results/run_estimates.hpp"
#include "emrm/safety/traceability.hpp"
#include "html.hpp"
#include "statistics_section.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using detail::html_table;
using detail::read_or_empty;

// The findings of analysis/findings.json, one row each.
std::string findings_table(const std::vector<safety::Finding>& findings) {
  core::Row header{"severity", "code", "subject", "where", "message"};
  std::vector<core::Row> rows;
  for (const auto& f : findings)
    rows.push_back({core::enum_text(f.severity), f.code, f.subject,
                    fmt::format("{}:{}:{}", f.where.file, f.where.line, f.where.column), f.message});
  return html_table(header, rows);
}

std::string findings_html(const fs::path& dir) {
  const fs::path file = results::ResultsDir(dir).findings_json();
  const std::string text = read_or_empty(file);
  if (text.empty()) return "";
  try {
    const auto findings = safety::read_findings_json(file);
    return findings.empty() ? "<p class=\"ok\">No findings.</p>\n" : findings_table(findings);
  } catch (const InputError& e) {  // a file edited by hand: shown as it is
    return "<p>analysis/findings.json is not in the form emrm writes (" + html_escape(e.what()) +
           "); shown as it is.</p>\n<pre>" + html_escape(text) + "</pre>\n";
  }
}

// The checks of diagnostics.json (results::read_diagnostics_summary) as one table: what each
// found, then the file.
std::string diagnostics_table(const results::DiagnosticsSummary& d) {
  core::Row header{"check", "result"};
  std::vector<core::Row> rows;
  rows.push_back({"stop boundary", d.stop_boundary
                                       ? fmt::format("{} of {} feasible cells can stop analytically; {} of them R "
                                                     "(must be 0), {} G cells below the boundary (must be 0)",
                                                     d.stoppable, d.feasible, d.stoppable_red, d.green_not_stoppable)
                                       : std::string("none: the scene's family has no analytic stop boundary")});
  std::vector<std::string> reversals;
  for (const auto& c : d.reversal_counts)
    if (c.reversals > 0)
      reversals.push_back(
          fmt::format("{} {} over {}: {} of {} pairs", c.grid, c.strategy, c.factor, c.reversals, c.pairs));
  rows.push_back(
      {"monotonicity in TTC and mu", fmt::format("{} reversals{}", d.total_reversals,
                                                 reversals.empty() ? "" : " (" + core::join(reversals, "; ") + ")")});
  std::vector<std::string> planners;
  for (const auto& c : d.reference)
    planners.push_back(fmt::format("{}: reference avoids {}, RRT missed {}, RRT beyond the reference {}", c.strategy,
                                   c.reference_avoids, c.missed, c.beyond_reference));
  rows.push_back({fmt::format("RRT against the reference planner ({} cells, seed {})", d.sampled, d.seed),
                  planners.empty() ? std::string("no strategy checked") : core::join(planners, "; ")});
  for (const auto& c : d.fsm_coverage)
    rows.push_back({"FSM transition coverage: " + c.name,
                    fmt::format("{} of {} transitions exercised by {} traces", c.covered, c.total, c.traces)});
  return html_table(header, rows);
}

std::string diagnostics_html(const fs::path& dir) {
  const fs::path file = results::ResultsDir(dir).diagnostics_json();
  const std::string text = read_or_empty(file);
  if (text.empty()) return "";
  std::string table;
  try {
    table = diagnostics_table(results::read_diagnostics_summary(file));
  } catch (const InputError& e) {
    table = "<p>diagnostics.json is not in the form emrm writes (" + html_escape(e.what()) + "); shown as it is.</p>\n";
  }
  return table + "<details><summary>diagnostics.json</summary><pre>" + html_escape(text) + "</pre></details>\n";
}

std::string verification_html(const fs::path& dir) {
  const std::string text = read_or_empty(results::ResultsDir(dir).verify_json());
  if (text.empty()) return "";
  return "<details open><summary>verify.json</summary><pre>" + html_escape(text) + "</pre></details>\n";
}

}  // namespace

namespace detail {

std::vector<fs::path> coverage_candidates(const fs::path& dir, const results::FoundRunEstimates& run) {
  const results::ResultsDir folder(dir);
  std::vector<fs::path> files{folder.plan().coverage_json(), folder.coverage_json()};
  if (run.estimates && run.estimates->plan && run.estimates->plan->coverage)
    files.push_back(run.file.parent_path() / *run.estimates->plan->coverage);
  return files;
}

std::string shortfalls_html(const results::FoundRunEstimates& run) {
  if (!run.estimates || run.estimates->shortfalls.empty()) return "";
  std::string out =
      "<div class=\"missing\" id=\"shortfalls\"><strong>The plan fell short of its targets</strong> "
      "(scenarios.json, repeated by <code>emrm run</code>); the estimates below lack these:\n<ul>\n";
  for (const auto& s : run.estimates->shortfalls) out += "<li>" + html_escape(s.message) + "</li>\n";
  return out + "</ul></div>\n";
}

std::vector<Section> side_sections(const fs::path& dir, const results::FoundRunEstimates& run) {
  const std::string folder = html_escape(dir.string());
  return {
      {"plan", "Minimum scenario set", "Minimum scenario set: estimates", detail::statistics_html(run, dir),
       "the estimates of a planned scenario set: <code>emrm plan ODD.yaml -o PLAN</code>, then <code>emrm run "
       "PLAN/scenarios.csv -o DIR</code>"},
      {"verification", "Verification", "Verification (emrm verify)", verification_html(dir),
       "a verification: <code>emrm verify " + folder +
           "</code> re-checks every witness and certificate and keeps its result in verify.json"},
      {"diagnostics", "Diagnostics", "Diagnostics", diagnostics_html(dir),
       "diagnostics (the stop boundary, monotonicity, the RRT against the reference planner): <code>emrm "
       "diagnose " +
           folder + "</code>"},
      {"findings", "Findings", "Findings of the safety analysis", findings_html(dir),
       "the findings of a safety analysis: <code>emrm analyze</code> on the safety case, or <code>emrm "
       "reproduce</code>"},
  };
}

std::string sections_html(const std::vector<Section>& sections) {
  std::string out;
  for (const auto& s : sections)
    if (!s.body.empty()) out += fmt::format("<h2 id=\"{}\">{}</h2>\n{}", s.id, s.heading, s.body);
  return out;
}

}  // namespace detail

std::string side_files_html(const fs::path& dir) {
  const results::FoundRunEstimates run = results::find_run_estimates(dir);
  return detail::shortfalls_html(run) + detail::sections_html(detail::side_sections(dir, run));
}

}  // namespace emrm::report
